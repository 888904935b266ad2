"""The state a World hands to its compiled kernels, addressed by name.

Data is split by how it is used (as Box2D v3 splits body sims, body states and contacts):

  Settings   scalars fixed for a World's life (a named tuple: ``settings.dt``)
  Bodies     per-body arrays read every step: pose, velocity, mass, material, shape
  Geometry   per-body derived data: world vertices, bounding boxes (tight and fattened)
  Grid       a uniform-grid broadphase index (one for awake bodies, one for resting ones)
  Contacts   the persistent contact store: one slot per pair of overlapping fat boxes
  Solver     per-step solver data: one compact row per awake body, the constraint batches
  Activity   which bodies are awake, and the freeze policies' per-body state
  counters   an int64 array of running counts, columns named below

Every array's unit is stated where it is declared (``sim/buffers.py`` builds them). Columns of the
2-D arrays are named by the module-level constants below; kernels never index a tuple by position.
"""

from typing import NamedTuple

import numpy as np


class Settings(NamedTuple):
    """Scalars fixed for a World's life (SI units)."""

    dt: float  # s, one step
    substeps: int  # soft-step substeps per step
    iterations: int  # biased solve sweeps per substep
    relax_iterations: int  # unbiased (relax) sweeps per substep
    impact_iterations: int  # extra biased sweeps per substep on impact batches (with friction)
    gravity_x: float  # m/s^2
    gravity_y: float
    has_floor: bool
    floor_y: float  # m
    floor_friction: float
    floor_restitution: float
    slop: float  # m, largest contact tolerance (pairs use less for small bodies)
    speculative_distance: float  # m, largest speculative margin at rest (grows with speed)
    contact_hertz: float  # Hz, stiffness of a contact between two moving bodies (0: auto)
    damping_ratio: float  # of the soft contact (Box2D's default 10: overdamped)
    push_speed: float  # m/s, fastest a soft contact pushes overlapping bodies apart
    load_rate: float  # per step, how far a contact's carried load follows its impulse
    restitution_threshold: float  # m/s
    warm_starting: bool
    fast_friction: bool  # no friction rows for frictionless contacts (exact)
    fast_quiet: bool  # skip the steps after one that began and ended with nothing awake (exact)
    continuous: bool  # time-of-impact sweeps for fast bodies
    cell_size: float  # m, broadphase grid cell
    n_dynamic: int
    policy: int  # index into sim.freeze.POLICY_NAMES
    impulse_threshold: float  # N s   (paper)
    impact_speed: float  # m/s   (extended)
    sleep_speed: float  # m/s   (sleep)
    sleep_time: float  # s     (sleep)
    rest_speed: float  # m/s   (extended)
    rest_acceleration: float  # m/s^2 (extended)
    rest_steps: int  # steps (extended)
    slip_speed: float  # m/s   (extended)
    opening_speed: float  # m/s   (extended)
    closing_speed: float  # m/s   (extended)
    friction_margin: float  # fraction of mu (extended)
    tip_margin: float  # fraction of a body's size (extended)
    mixed_masses: bool  # two dynamic bodies' masses differ by > soft_step.HARD_RATIO
    profile: bool  # time each stage (cycle counter) into solver.profile


# ---- counters (int64 array, persisting across World.step calls) --------------------------------
(
    STEP_COUNT,
    N_ACTIVE,
    BAD_BODY,
    PRESOLVE_SWEEPS,
    N_AWAKE,
    N_EVENTS,
    RESTING_DIRTY,
    N_LINKS,
    N_SLOTS,
    FREE_HEAD,
    N_LIVE,
    N_AWAKE_CONTACTS,
    N_MOVED,
    MAX_DEGREE,
    N_BATCHES,
    N_COLOURS,
    N_SWEPT,
    N_IMPACTS,
    N_TOI_PAIRS,
    GROW_NEEDED,
    N_REBUILDS,
    AWAKE_UNSORTED,
    N_REFRESHED,
    N_HARD,
    N_SKIPPED,
    N_CERTIFICATES,
    N_QUIET,
    QUIET_ARMED,
    N_IMPACT_BATCHES,
    N_DEEP_BATCHES,
    PRESOLVE_CONVERGED,
) = range(31)
N_COUNTERS = 31
# GROW_NEEDED bits: which buffer the kernel found too small (the World grows it and retries)
GROW_CONTACTS, GROW_AWAKE_GRID, GROW_RESTING_GRID, GROW_SOLVER = 1, 2, 4, 8


class Bodies(NamedTuple):
    """Per-body arrays; M bodies, the N dynamic ones first, then the static polygons."""

    position: np.ndarray  # (M,2) m, centre of mass
    angle: np.ndarray  # (M,) rad
    velocity: np.ndarray  # (M,2) m/s
    angular_velocity: np.ndarray  # (M,) rad/s
    inv_mass: np.ndarray  # (M,) 1/kg, 0 for static
    inv_inertia: np.ndarray  # (M,) 1/(kg m^2), 0 for static
    friction: np.ndarray  # (M,) Coulomb mu
    restitution: np.ndarray  # (M,) in [0, 1]
    vert_start: np.ndarray  # (M+1,) int64 offsets into local_verts / local_normals
    local_verts: np.ndarray  # (V,2) m, body frame about the centre of mass
    local_normals: np.ndarray  # (V,2) outward unit edge normals, body frame
    extent: np.ndarray  # (M,) m, centre of mass to the farthest vertex
    size: np.ndarray  # (M,) m, thinnest width: the length tolerances scale with
    slop: np.ndarray  # (M,) m, own contact slop (sim.tolerances; a pair: the smaller)
    speculative: np.ndarray  # (M,) m, own speculative reach at rest
    margin: np.ndarray  # (M,) m, own fat-box margin
    bullet: np.ndarray  # (M,) bool: swept against dynamic bodies too


class Geometry(NamedTuple):
    """Per-body data derived from the pose, brought up to date for awake bodies every step."""

    rotation: np.ndarray  # (M,2) cos, sin of angle
    world_verts: np.ndarray  # (V,2) m
    world_normals: np.ndarray  # (V,2)
    aabb: np.ndarray  # (M,4) m: min x, min y, max x, max y, grown by the body's
    #   speculative reach this step
    fat: np.ndarray  # (M,4) m: the box pairs are kept for; refitted only when the
    #   aabb leaves it
    moved: np.ndarray  # (N,) int64 scratch: bodies whose fat box was refitted
    moved_flag: np.ndarray  # (N,) bool: body is in ``moved``
    partner: np.ndarray  # (M,) bool scratch, all False between uses: the partners of the moved
    #   body ``broadphase.find_new_pairs`` is looking at
    toi_scratch: np.ndarray  # (2K, 2) m: world vertices of a swept pair (K: most vertices)


# aabb / fat columns
MIN_X, MIN_Y, MAX_X, MAX_Y = 0, 1, 2, 3


class Grid(NamedTuple):
    """A uniform grid of boxes (``broadphase.build_grid``), in preallocated buffers.
    Bucket h holds entries start[h]..start[h+1]-1; ``info`` holds the layout. One extra bucket
    after the N_BUCKETS of cells holds the *large* boxes (more than ``broadphase.LARGE_CELLS``
    cells), each entered once and tested by every query."""

    start: np.ndarray  # (T+2,) int64
    entry_body: np.ndarray  # (E,) int64
    entry_cx: np.ndarray  # (E,) int64 cell column
    entry_cy: np.ndarray  # (E,) int64 cell row
    info: np.ndarray  # (GRID_INFO,) int64, columns below


# grid info columns
(LO_CX, LO_CY, WIDTH, HEIGHT, MASK, DENSE, N_ENTRIES, N_BUCKETS, NEEDED_ENTRIES, NEEDED_BUCKETS) = (
    range(10)
)
GRID_INFO = 10


class Contacts(NamedTuple):
    """The persistent contact store. A slot holds one pair of bodies whose fat boxes overlap, from
    the step they start to overlap until they stop; its manifold (0-2 points) is updated in place
    every step either body is awake, and carries its impulses to the next step (warm starting).

    Each dynamic body lists its contacts (a doubly linked list through the slots), so that freezing
    or waking a body moves exactly its contacts out of or into ``awake`` (data movement: contacts
    between resting bodies are never looked at)."""

    contact_int: np.ndarray  # (C, CONTACT_INT) int64, columns below
    contact_float: np.ndarray  # (C, CONTACT_FLOAT) float64, columns below
    point_float: np.ndarray  # (C, 2, POINT_FLOAT) float64, columns below
    point_id: np.ndarray  # (C, 2) int64 feature ids (see geometry.py)
    head: np.ndarray  # (N,) int64 first contact slot of each dynamic body, -1 none
    degree: np.ndarray  # (N,) int64 contacts in each dynamic body's list
    awake: np.ndarray  # (C,) int64 slots with at least one awake body
    active: np.ndarray  # (C,) int64 awake slots with points, this step (solver order)
    scratch_points: np.ndarray  # (2,2) narrowphase scratch
    scratch_separations: np.ndarray  # (2,)
    scratch_ids: np.ndarray  # (2,) int64
    scratch_normal: np.ndarray  # (2,)


# contact_int columns
(
    BODY_A,
    BODY_B,
    POINT_COUNT,
    REFERENCE,
    INCIDENT,
    AWAKE_INDEX,
    NEXT_A,
    PREV_A,
    NEXT_B,
    PREV_B,
    ALIVE,
) = range(11)
CONTACT_INT = 11
# contact_float columns
(
    NORMAL_X,
    NORMAL_Y,
    FRICTION,
    RESTITUTION,
    LOCAL_NORMAL_X,
    LOCAL_NORMAL_Y,
    LOCAL_FACE_X,
    LOCAL_FACE_Y,
    SLOP,
    SPECULATIVE,
    FIT_X,
    FIT_Y,
    FIT_C,
    FIT_S,
    FIT_MARGIN,
    FIT_GAP,
) = range(16)
CONTACT_FLOAT = 16
# FIT_*: the relative pose of B in A's frame (position m, rotation cos/sin) and the speculative
#   margin (m) at the last full narrowphase of the contact: while neither has changed more than a
#   fraction of the slop, the manifold is refreshed from its stored points instead (narrowphase.py).
#   FIT_GAP (m): a lower bound on the distance between the shapes then (their separating-axis
#   gap); a pair without points is not looked at again until its bodies could have closed it.
# point_float columns
(
    ANCHOR_AX,
    ANCHOR_AY,
    ANCHOR_BX,
    ANCHOR_BY,
    SEPARATION,
    NORMAL_IMPULSE,
    TANGENT_IMPULSE,
    WARM_NORMAL,
    WARM_TANGENT,
    LOCAL_X,
    LOCAL_Y,
    NORMAL_VELOCITY,
    CARRIED,
    END_SEPARATION,
) = range(14)
POINT_FLOAT = 14
# ANCHOR_*: the point relative to each centre of mass, m (A is the floor when BODY_A = -1).
# SEPARATION: m, negative = penetration, at the narrowphase of the step (its start).
# END_SEPARATION: m, the same point's separation at the end of the step (the anchors moved with
#   their bodies): what the freeze policies, judging the step after it, call touching.
# NORMAL_IMPULSE, TANGENT_IMPULSE: N s, everything the contact applied over the whole step (all
#   substeps, warm start, solve, relax and restitution): what the freeze policies read.
# WARM_NORMAL, WARM_TANGENT: N s, the last substep's accumulated impulses, applied at the start
#   of every substep of the next step (warm starting).
# LOCAL_X/Y: the point in the incident body's frame, m (the manifold's point on that body).
# NORMAL_VELOCITY: m/s, relative normal velocity at the start of the step (restitution).
# CARRIED: N s per substep, the load the point has been carrying, followed slowly (soft_step).


class Solver(NamedTuple):
    """Per-step data of the soft-step solver (``sim/soft_step/``).

    ``state`` has one 64-byte row per awake body (row k+1 for the body in awake slot k) and a
    dummy row 0 that stands for every body the solver cannot move (static, frozen, the floor):
    its velocity and displacement stay zero, so a constraint against it needs no branch."""

    state: np.ndarray  # (N+1, STATE_COLUMNS) float64, columns below
    colour_mask: np.ndarray  # (N+1, words) uint64 colours used by each row this step
    colour_batches: np.ndarray  # (64 words + 1,) int64 first batch of each colour
    colour_cursor: np.ndarray  # (64 words,) int64 scratch: next lane of each colour
    order: np.ndarray  # (C,) int64 scratch: the colour of each active contact
    colour_key: np.ndarray  # (C, 5) int64: slot, body A, body B, row A, row B of each active
    #                          contact coloured last
    colour_key_n: np.ndarray  # (1,) int64: how many (-1: nothing to reuse, as after a regrow)
    colour_kept: np.ndarray  # (1,) bool: this step kept the step before's colouring and lanes
    wide: np.ndarray  # flat float64: constraint batches (see sim/soft_step/layout.py)
    lane_row: np.ndarray  # flat uint64: solver rows of each lane's bodies A, B
    lane_slot: np.ndarray  # flat int64: contact slot of each lane, -1 padding
    batch_kind: np.ndarray  # (B,) uint8: MOVABLE or FIXED_A (soft_step/layout.py)
    batch_hard: np.ndarray  # (B,) bool: the batch touches a body in a high mass ratio contact
    batch_impact: np.ndarray  # (B,) bool: the batch touches a body in an impact this step
    batch_deep: np.ndarray  # (B,) bool: the batch touches a body in a deep contact this step
    row_mark: np.ndarray  # (N+1,) bool scratch: rows of the bodies being flagged
    profile: np.ndarray  # (N_STAGES,) int64 cycle counts per stage (settings.profile)
    steps_profiled: np.ndarray  # (1,) int64


# state columns: velocity (m/s, rad/s), rotation so far this step (rad), displacement so far (m),
# rotation so far as (cos, sin)
VX, VY, W, TURN, DPX, DPY, DQC, DQS = range(8)
STATE_COLUMNS = 8


class Activity(NamedTuple):
    """Which bodies are awake (``sim/activity.py``) and the freeze policy's own state."""

    states: np.ndarray  # (N,) int8 sim.State
    awake: np.ndarray  # (N,) int64 awake body indices, counters[N_AWAKE] used
    awake_slot: np.ndarray  # (N,) int64 position in ``awake``, -1 when frozen
    solver_inv_mass: np.ndarray  # (M,) 1/kg seen by the solver: 0 when frozen or static
    solver_inv_inertia: np.ndarray  # (M,)
    events: np.ndarray  # (E,5) int64 step, body, from, to, cause
    body_real: np.ndarray  # (N, policy.REAL_COLUMNS) float64, the policy's own
    body_int: np.ndarray  # (N, policy.INT_COLUMNS) int64, the policy's own
    links: np.ndarray  # (L,2) int64 the policy's body pairs (extended: support, body)
    link_load: np.ndarray  # (L, policy.LINK_COLUMNS or 3) float64 per link, the policy's own


# ---- named stages of a step, timed when settings.profile is on --------------------------------
STAGES = (
    "broadphase",
    "narrowphase",
    "freeze_before",
    "colour",
    "prepare",
    "integrate",
    "arms",
    "warm_start",
    "solve",
    "relax",
    "restitution",
    "store",
    "finalize",
    "continuous",
    "freeze_after",
)
(
    STAGE_BROADPHASE,
    STAGE_NARROWPHASE,
    STAGE_FREEZE_BEFORE,
    STAGE_COLOUR,
    STAGE_PREPARE,
    STAGE_INTEGRATE,
    STAGE_ARMS,
    STAGE_WARM_START,
    STAGE_SOLVE,
    STAGE_RELAX,
    STAGE_RESTITUTION,
    STAGE_STORE,
    STAGE_FINALIZE,
    STAGE_CONTINUOUS,
    STAGE_FREEZE_AFTER,
) = range(len(STAGES))
N_STAGES = len(STAGES)
