"""Column names of the small settings and counter arrays the kernels share.

Settings travel as two arrays (float64 and int64) rather than as arguments, so that adding a
setting does not change every kernel signature. Counters persist across ``World.step`` calls.
"""
# float settings
(DT, GRAVITY_X, GRAVITY_Y, FLOOR_Y, FLOOR_FRICTION, FLOOR_RESTITUTION, SLOP, MARGIN, BAUMGARTE,
 MAX_CORRECTION, RESTITUTION_THRESHOLD, CELL_SIZE,
 IMPULSE_THRESHOLD, SLEEP_SPEED, SLEEP_TIME, REST_SPEED, REST_ACCELERATION) = range(17)
N_FLOAT_SETTINGS = 17

# int settings
(ITERATIONS, POSITION_ITERATIONS, HAS_FLOOR, WARM_START, N_DYNAMIC, POLICY,
 REST_STEPS, FAST_PATHS) = range(8)
N_INT_SETTINGS = 8

# FAST_PATHS bits: work the solver skips when the scene does not need it (World(fast_paths=...))
FAST_FRICTION = 1          # no friction rows for a contact whose friction coefficient is zero

# counters
(STEP_COUNT, N_MANIFOLDS, BAD_BODY, PRESOLVE_SWEEPS, N_AWAKE, N_EVENTS, RESTING_DIRTY,
 N_LINKS) = range(8)
N_COUNTERS = 8

# policy codes (the order of sim.freeze.POLICY_NAMES)
OFF, SLEEP, PAPER, EXTENDED = range(4)
