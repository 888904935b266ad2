"""The contact solver: soft step (Box2D v3's solver; Catto's Solver2D compares it with the
sequential impulses and position correction this project used before), solved in wide batches.

One step of dt is ``substeps`` substeps of h = dt / substeps, each:

  integrate velocities   v += h g
  warm start             apply each contact's accumulated impulse from the last substep
  solve                  ``iterations`` sweeps with a *soft* bias computed from the current
                         separation (normal rows only); in a step with an impact, the batches
                         around it get ``impact_iterations`` more, with friction rows
                         (IMPACT_SWEEP_SPEED)
  integrate positions    dp += h v, rotation likewise (bodies keep their start pose; the solver
                         tracks the displacement dp, dq so far)
  arms                   every point's lever arms and separation from the new poses (those of
                         the start poses are left by ``prepare``): the sweeps read them, as the
                         poses do not change between two integrations
  relax                  ``relax_iterations`` sweeps without bias (normal and friction rows): the
                         velocity the bias added to push bodies apart is taken out again

then one restitution pass, and the impulses are stored for the next step's warm start and for the
freeze policies (which read, per point, the total impulse applied over the whole step: N s).

The soft contact (Catto's "soft step"): a touching point (s <= 0) solves
    impulse = -m_n * (mass_scale * vn + bias) - impulse_scale * accumulated,
    bias = max(mass_scale * bias_rate * s, -push_speed),
the implicit-Euler form of a spring-damper of stiffness ``hertz`` and damping ratio ``zeta``: stable
at any stiffness, and the stiffness is bounded by the substep rate instead of by iterations. A
point still apart (s > 0) is speculative: bias = s / h, the bodies may close the gap, not more.
Contacts against an immovable body (static, frozen, the floor) are twice as stiff, so a pile does
not sink into its support. The steady sink of a contact is (load / effective mass) g / omega^2;
``contact_hertz`` is therefore raised for small bodies (``tolerances``: the sink stays a fixed
fraction of the size) up to its cap, a fraction of the substep rate.

Wide batches. Every step the active contacts are coloured (``colour``): no two contacts of one
colour share a body that can move (static and frozen bodies and the floor are a dummy row that
nothing writes, and use no colour). Each colour is cut into batches of LANES contacts, stored
field by field in one flat array (``wide``): the solver gathers the batch's body rows into the
batch, computes all lanes at once (packed vector instructions), and scatters the velocities back.
A batch whose every lane's body A cannot move (the floor) is swept with A's exact-zero terms left
out (``layout.FIXED_A``; ``batches``, FIXED SIDE): the same numbers, fewer operations and fields.

The package, one stage per module (the order of a step):

  parameters   the soft contact's defaults and stiffness rules (softness, pair_hertz)
  bodies       the solver's body rows: loaded, integrated, written back
  colouring    contacts into colours and batches (colour; capacity, mask_words size the buffers)
  packing      batches filled from the contacts (prepare), impulses stored back (store)
  arms         the lever arms and separations of the poses so far (arms)
  batches      the batch kernels (warm_start, solve, solve_impact, relax, relax_hard,
               restitution)
  layout       the fields of a batch in ``SolverData.wide``

``sim.kernel.step`` calls them in that order; what other modules use is re-exported here.
"""

from .arms import arms
from .batches import (
    deepest_separation,
    relax,
    relax_hard,
    restitution,
    solve,
    solve_impact,
    warm_start,
)
from .bodies import integrate_positions, integrate_velocities, load_bodies, row_of, unload_bodies
from .colouring import capacity, colour, mask_words, max_colours
from .layout import LANES, N_FIELDS, STRIDE
from .packing import lane_normal_impulse, prepare, store
from .parameters import (
    DAMPING_RATIO,
    DYNAMIC_CAP,
    HARD_RATIO,
    HARD_SWEEPS,
    IMPACT_ITERATIONS,
    IMPACT_SPEED,
    DEEP_SLOPS,
    DEEP_SWEEPS,
    IMPACT_SWEEP_SPEED,
    LOAD_TIME,
    MAX_CONDITION,
    PUSH_SPEED,
    RESTITUTION_SWEEPS,
    STATIC_CAP,
    STIFFNESS_RATIO,
    pair_hertz,
    softness,
)

__all__ = [
    "arms",
    "deepest_separation",
    "relax",
    "relax_hard",
    "restitution",
    "solve",
    "solve_impact",
    "warm_start",
    "integrate_positions",
    "integrate_velocities",
    "load_bodies",
    "row_of",
    "unload_bodies",
    "capacity",
    "colour",
    "mask_words",
    "max_colours",
    "LANES",
    "N_FIELDS",
    "STRIDE",
    "lane_normal_impulse",
    "prepare",
    "store",
    "DAMPING_RATIO",
    "DYNAMIC_CAP",
    "HARD_RATIO",
    "HARD_SWEEPS",
    "IMPACT_ITERATIONS",
    "IMPACT_SPEED",
    "DEEP_SLOPS",
    "DEEP_SWEEPS",
    "IMPACT_SWEEP_SPEED",
    "LOAD_TIME",
    "MAX_CONDITION",
    "PUSH_SPEED",
    "RESTITUTION_SWEEPS",
    "STATIC_CAP",
    "STIFFNESS_RATIO",
    "pair_hertz",
    "softness",
]
