"""``off``: no freezing. Every body is solved every step; the reference for every comparison."""
NAME = "off"
PARAMETERS = {}
