"""Which bodies are awake, and moving bodies between awake and frozen (DESIGN section 2).

Freezing is data movement, not a flag tested in every loop: the solver, the integrator and the
broadphase walk ``awake`` (a compact list of body indices); a frozen body leaves that list, its
solver masses drop to zero (to the awake bodies touching it, it is as immovable as a wall) and it
joins the *resting grid* (``broadphase.build_grid``) that awake bodies are tested against. The
resting grid is rebuilt once in a step in which the frozen set changed, never per step otherwise.

Arrays (N dynamic bodies, M bodies in all):
  awake (N,) int64          indices of awake dynamic bodies in awake[0..counters[N_AWAKE]-1]
  awake_slot (N,) int64     position of each body in ``awake``, -1 when frozen
  solver_inv_mass (M,)      1/kg seen by the solver: the body's own when awake, 0 when frozen/static
  solver_inv_inertia (M,)   1/(kg m^2), likewise
  events (E,5) int64        step, body, from_state, to_state, cause; counters[N_EVENTS] used
"""
import numpy as np

from .jit import inline_kernel, kernel

# counters (int64 array) shared with sim.kernel: columns named there, listed here for the helpers
from .layout import N_AWAKE, N_EVENTS, RESTING_DIRTY, STEP_COUNT

# event columns
EVENT_STEP, EVENT_BODY, EVENT_FROM, EVENT_TO, EVENT_CAUSE = range(5)

#: cause codes of events; the names are what ``World.events`` reports
CAUSES = ("rested", "touched", "woken_by_island", "impact", "support_lost", "pushed", "tipping",
          "one_vertex_on_floor", "two_vertices_on_floor", "com_outside_support", "held_by_contact",
          "stopped_sliding", "bounced", "lifted_off", "timer")
CAUSE = {name: code for code, name in enumerate(CAUSES)}


@inline_kernel
def record(events, counters, body, from_state, to_state, cause):
    """Append one transition to the event buffer (the step loop keeps room for a step's worth)."""
    k = counters[N_EVENTS]
    if k < events.shape[0]:
        events[k, EVENT_STEP] = counters[STEP_COUNT]
        events[k, EVENT_BODY] = body
        events[k, EVENT_FROM] = from_state
        events[k, EVENT_TO] = to_state
        events[k, EVENT_CAUSE] = cause
        counters[N_EVENTS] = k + 1


@inline_kernel
def freeze(i, awake, awake_slot, counters, solver_inv_mass, solver_inv_inertia, velocity,
           angular_velocity):
    """Take awake body i out of the awake list (swap with the last), zero its velocity and solver
    masses, and mark the resting grid for a rebuild."""
    slot = awake_slot[i]
    if slot < 0:
        return
    last = counters[N_AWAKE] - 1
    moved = awake[last]
    awake[slot] = moved
    awake_slot[moved] = slot
    awake_slot[i] = -1
    counters[N_AWAKE] = last
    solver_inv_mass[i] = 0.0
    solver_inv_inertia[i] = 0.0
    velocity[i, 0] = 0.0
    velocity[i, 1] = 0.0
    angular_velocity[i] = 0.0
    counters[RESTING_DIRTY] = 1


@inline_kernel
def wake(i, awake, awake_slot, counters, inv_mass, inv_inertia, solver_inv_mass,
         solver_inv_inertia):
    """Put frozen body i back at the end of the awake list with its own masses."""
    if awake_slot[i] >= 0:
        return
    n = counters[N_AWAKE]
    awake[n] = i
    awake_slot[i] = n
    counters[N_AWAKE] = n + 1
    solver_inv_mass[i] = inv_mass[i]
    solver_inv_inertia[i] = inv_inertia[i]
    counters[RESTING_DIRTY] = 1


@kernel
def resting_bodies(n_dynamic, n_bodies, awake_slot):
    """Indices of every body not awake: frozen dynamic bodies and all static bodies."""
    out = np.empty(n_bodies, np.int64)
    k = 0
    for i in range(n_bodies):
        if i >= n_dynamic or awake_slot[i] < 0:
            out[k] = i
            k += 1
    return out[:k]
