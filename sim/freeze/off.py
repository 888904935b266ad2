"""``off``: no freezing. Every body is solved every step; the reference for every comparison."""

NAME = "off"
PARAMETERS = {}
INT_PARAMETERS = ()  # parameters that are counts (the rest are reals); all become Settings fields
REAL_COLUMNS = 0  # per-body float state the policy keeps (World allocates (N, REAL_COLUMNS))
INT_COLUMNS = 0
