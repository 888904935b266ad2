"""``off``: no freezing. Every body is solved every step; the reference for every comparison."""
NAME = "off"
PARAMETERS = {}
FLOAT_SETTINGS = {}     # parameter name -> column of the float settings (sim.layout)
INT_SETTINGS = {}
REAL_COLUMNS = 0        # per-body float state the policy keeps (World allocates (N, REAL_COLUMNS))
INT_COLUMNS = 0
