"""Which bodies are awake, and moving bodies between awake and frozen (freezing is data movement).

Freezing is not a flag tested in every loop: the solver, the integrator and the broadphase walk
``activity.awake`` (a compact list of body indices); a frozen body leaves that list, its solver
masses drop to zero (to the awake bodies touching it, it is as immovable as a wall), its contacts
with other immovable bodies leave the awake contact list (``contacts.sleep_contacts_of``), and it
joins the *resting grid* that awake bodies are tested against. The resting grid is rebuilt once
in a step in which the frozen set changed, never per step otherwise. Waking reverses each move.

Arrays: see ``data.Activity``. Events are rows (step, body, from_state, to_state, cause) of
``activity.events``, counters[N_EVENTS] of them used.
"""

import numpy as np

from .contacts import sleep_contacts_of, wake_contacts_of
from .data import Activity, N_AWAKE, N_EVENTS, RESTING_DIRTY, STEP_COUNT
from .jit import inline_kernel, lean_kernel
from .state import State

# event columns
EVENT_STEP, EVENT_BODY, EVENT_FROM, EVENT_TO, EVENT_CAUSE = range(5)

#: cause codes of events; the names are what ``World.events`` reports
CAUSES = (
    "rested",
    "touched",
    "woken_by_island",
    "impact",
    "support_lost",
    "pushed",
    "tipping",
    "one_vertex_on_floor",
    "two_vertices_on_floor",
    "com_outside_support",
    "held_by_contact",
    "stopped_sliding",
    "bounced",
    "lifted_off",
    "timer",
)
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
def freeze(i, settings, counters, bodies, contacts, activity):
    """Take awake body i out of the awake list (swap with the last), zero its velocity and solver
    masses, move its contacts with immovable bodies out of the awake contacts, and mark the
    resting grid for a rebuild."""
    awake = activity.awake
    awake_slot = activity.awake_slot
    slot = awake_slot[i]
    if slot < 0:
        return
    last = counters[N_AWAKE] - 1
    moved = awake[last]
    awake[slot] = moved
    awake_slot[moved] = slot
    awake_slot[i] = -1
    counters[N_AWAKE] = last
    activity.solver_inv_mass[i] = 0.0
    activity.solver_inv_inertia[i] = 0.0
    bodies.velocity[i, 0] = 0.0
    bodies.velocity[i, 1] = 0.0
    bodies.angular_velocity[i] = 0.0
    sleep_contacts_of(i, settings.n_dynamic, awake_slot, contacts, counters)
    counters[RESTING_DIRTY] = 1


@inline_kernel
def wake(i, settings, counters, bodies, contacts, activity):
    """Put frozen body i back at the end of the awake list with its own masses and contacts."""
    awake_slot = activity.awake_slot
    if awake_slot[i] >= 0:
        return
    n = counters[N_AWAKE]
    activity.awake[n] = i
    awake_slot[i] = n
    counters[N_AWAKE] = n + 1
    activity.solver_inv_mass[i] = bodies.inv_mass[i]
    activity.solver_inv_inertia[i] = bodies.inv_inertia[i]
    wake_contacts_of(i, contacts, counters)
    counters[RESTING_DIRTY] = 1


@lean_kernel
def resting_bodies(n_dynamic, n_bodies, awake_slot, out):
    """Write the indices of every body not awake (frozen dynamic bodies, then all static bodies)
    into ``out`` (M,); returns how many."""
    k = 0
    for i in range(n_bodies):
        if i >= n_dynamic or awake_slot[i] < 0:
            out[k] = i
            k += 1
    return k


def initial_activity(
    n_dynamic, n_bodies, inv_mass, inv_inertia, policy, velocity, angular_velocity
):
    """Activity arrays of a new World: every body awake, no events, the policy's state zeroed
    (and set up by its ``initial`` hook when it has one, from the bodies' starting velocities:
    velocity (N,2) m/s, angular_velocity (N,) rad/s)."""
    act = Activity(
        states=np.full(n_dynamic, State.FREE, np.int8),
        awake=np.arange(n_dynamic, dtype=np.int64),
        awake_slot=np.arange(n_dynamic, dtype=np.int64),
        solver_inv_mass=inv_mass.copy(),
        solver_inv_inertia=inv_inertia.copy(),
        events=np.zeros((4 * n_dynamic + 64, 5), np.int64),
        body_real=np.zeros((n_dynamic, policy.REAL_COLUMNS)),
        body_int=np.zeros((n_dynamic, policy.INT_COLUMNS), np.int64),
        links=np.zeros((max(16, 4 * n_dynamic), 2), np.int64),
        link_load=np.zeros((max(16, 4 * n_dynamic), getattr(policy, "LINK_COLUMNS", 3))),
    )
    initial = getattr(policy, "initial", None)
    if initial is not None:
        initial(act, velocity[:n_dynamic], angular_velocity[:n_dynamic])
    return act
