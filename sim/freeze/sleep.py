"""``sleep``: what the big engines do (Box2D, Chipmunk, Bullet), in our solver, to isolate the
freezing method from the engine.

A body is *idle* while its speed |v| + |w| * extent stays under ``sleep_speed`` (m/s); its timer
counts how long. An *island* is a connected component of the contact graph among awake dynamic
bodies (the floor and static bodies do not connect islands). When every body of an island has been
idle for ``sleep_time`` (s), the island falls asleep: all its bodies are frozen (state SLEEPING)
and linked in a ring so the island can be woken as a whole. A sleeping island wakes entirely when
an awake body touches any of its bodies (a contact manifold between them exists) — so a support
knocked away, or a body landing on it, wakes it. Nothing that is asleep is solved.

Per-body state: body_real[:, TIMER] s; body_int[:, NEXT] the ring of a sleeping island (-1 when
awake), body_int[:, PARENT] union-find scratch.
"""

import numpy as np

from ..activity import CAUSE, freeze, record, wake
from ..data import BODY_A, BODY_B, N_ACTIVE, N_AWAKE
from ..jit import inline_kernel, lean_kernel
from .contact_math import arriving, touching
from ..state import State

NAME = "sleep"
PARAMETERS = {"sleep_speed": 0.05, "sleep_time": 0.5}
INT_PARAMETERS = ()  # parameters that are counts (the rest are reals)
TIMER = 0
REAL_COLUMNS = 1
NEXT, PARENT = 0, 1
INT_COLUMNS = 2

_FREE = np.int8(State.FREE)
_SLEEPING = np.int8(State.SLEEPING)
_TOUCHED = CAUSE["touched"]
_BY_ISLAND = CAUSE["woken_by_island"]
_TIMER = CAUSE["timer"]


def initial(activity, velocity, angular_velocity):
    """Per-body state of a new World: no body belongs to a sleeping island (the starting
    velocities play no part)."""
    activity.body_int[:, NEXT] = -1


@inline_kernel
def _find(parent, i):
    root = i
    while parent[root] != root:
        root = parent[root]
    while parent[i] != root:  # path compression
        nxt = parent[i]
        parent[i] = root
        i = nxt
    return root


@lean_kernel
def before_solve(settings, counters, bodies, contacts, activity):
    """An awake body touching a sleeping one wakes that body's whole island, before the solve, so
    the touch is solved between moving bodies. Returns the number of bodies woken."""
    ci = contacts.contact_int
    states, awake_slot, events = activity.states, activity.awake_slot, activity.events
    body_real, body_int = activity.body_real, activity.body_int
    n_dyn = settings.n_dynamic
    woken = 0
    for k in range(counters[N_ACTIVE]):
        c = contacts.active[k]
        if not arriving(c, settings, bodies, contacts):
            continue  # made ahead: this step's solve does not stop it (contact_math.arrives)
        a = ci[c, BODY_A]
        b = ci[c, BODY_B]
        for sleeper, other in ((a, b), (b, a)):
            if (
                0 <= sleeper < n_dyn
                and awake_slot[sleeper] < 0
                and 0 <= other < n_dyn
                and awake_slot[other] >= 0
            ):
                i = sleeper
                while True:
                    nxt = body_int[i, NEXT]
                    body_int[i, NEXT] = -1
                    body_real[i, TIMER] = 0.0
                    wake(i, settings, counters, bodies, contacts, activity)
                    states[i] = _FREE
                    record(
                        events,
                        counters,
                        i,
                        _SLEEPING,
                        _FREE,
                        _TOUCHED if i == sleeper else _BY_ISLAND,
                    )
                    woken += 1
                    if nxt < 0 or nxt == sleeper:
                        break
                    i = nxt
    return woken


@inline_kernel
def _due(settings):
    """The timer reading (s) at which a body has been idle for ``sleep_time``. A timer sums dt
    step by step in floating point: 30 steps of 1/60 s sum to 0.49999999999999994 s, short of
    0.5 by round-off, and the default 0.5 s took 31 steps where 1.0 s took 60. A millionth of a
    step of slack absorbs the round-off and nothing else. A body is idle for a whole step or not
    at all, so the reading is never below half a step: with sleep_time 0 (or under a millionth of
    a step) the slack made the reading negative, and a body whose timer had just been reset by its
    speed (0 s idle) was due: a box thrown at 10 m/s fell asleep in mid-air in its first step.
    Any sleep_time up to one step now means "idle for one step"."""
    return max(settings.sleep_time - 1e-6 * settings.dt, 0.5 * settings.dt)


@lean_kernel
def _timers_and_islands(settings, counters, bodies, contacts, activity):
    """Idle timers of the awake bodies; when one has been idle for sleep_time, the islands (union-
    find over this step's manifolds, into body_int[:, PARENT]). Returns the longest timer, s.
    Lean (no reference counting, see sim/jit): it walks every awake body and contact each step."""
    velocity, angular_velocity, extent = bodies.velocity, bodies.angular_velocity, bodies.extent
    ci = contacts.contact_int
    awake, awake_slot = activity.awake, activity.awake_slot
    body_real, body_int = activity.body_real, activity.body_int
    n_dyn = settings.n_dynamic
    dt = settings.dt
    limit = settings.sleep_speed
    longest = 0.0
    for k in range(counters[N_AWAKE]):
        i = awake[k]
        vx = velocity[i, 0]
        vy = velocity[i, 1]
        w = abs(angular_velocity[i]) * extent[i]
        if (
            abs(vx) < limit
            and abs(vy) < limit
            and w < limit
            and np.sqrt(vx * vx + vy * vy) + w < limit
        ):
            body_real[i, TIMER] += dt
            longest = max(longest, body_real[i, TIMER])
        else:
            body_real[i, TIMER] = 0.0
        body_int[i, PARENT] = i
    if longest < _due(settings):
        return longest  # no island can sleep: skip building them
    # islands of touching awake bodies (union-find over this step's manifolds)
    parent = body_int[:, PARENT]
    for k in range(counters[N_ACTIVE]):
        c = contacts.active[k]
        a = ci[c, BODY_A]
        b = ci[c, BODY_B]
        if (
            0 <= a < n_dyn
            and b < n_dyn
            and awake_slot[a] >= 0
            and awake_slot[b] >= 0
            and touching(c, contacts)
        ):
            ra = _find(parent, a)
            rb = _find(parent, b)
            if ra != rb:
                parent[max(ra, rb)] = min(ra, rb)  # the lower index is the root: deterministic
    return longest


@inline_kernel
def after_solve(settings, counters, bodies, contacts, activity):
    """Idle timers, islands, and islands falling asleep."""
    states, awake, awake_slot, events = (
        activity.states,
        activity.awake,
        activity.awake_slot,
        activity.events,
    )
    body_real, body_int = activity.body_real, activity.body_int
    n_awake = counters[N_AWAKE]
    if n_awake == 0:
        return
    if _timers_and_islands(settings, counters, bodies, contacts, activity) < _due(settings):
        return
    parent = body_int[:, PARENT]
    # an island sleeps when its least idle body has been idle long enough (minimum timer per
    # island, indexed by the awake slot of the island's root)
    island_min = np.full(n_awake, np.inf)
    root_slot = np.empty(n_awake, np.int64)
    for k in range(n_awake):
        i = awake[k]
        root_slot[k] = awake_slot[_find(parent, i)]
    for k in range(n_awake):
        island_min[root_slot[k]] = min(island_min[root_slot[k]], body_real[awake[k], TIMER])
    sleepers = np.empty(n_awake, np.int64)
    sleeper_island = np.empty(n_awake, np.int64)
    n_sleep = 0
    for k in range(n_awake):
        if island_min[root_slot[k]] >= _due(settings):
            sleepers[n_sleep] = awake[k]
            sleeper_island[n_sleep] = root_slot[k]
            n_sleep += 1
    if n_sleep == 0:
        return
    # put the islands to sleep, linking each island's bodies in a ring (first/last body of
    # each island, indexed by the awake slot of the island's root)
    first = np.full(n_awake, -1, np.int64)
    last = np.full(n_awake, -1, np.int64)
    for k in range(n_sleep):
        i = sleepers[k]
        s = sleeper_island[k]
        if first[s] < 0:
            first[s] = i
        else:
            body_int[last[s], NEXT] = i
        last[s] = i
    for k in range(n_sleep):
        s = sleeper_island[k]
        if first[s] >= 0:
            body_int[last[s], NEXT] = first[s]  # close the ring
            first[s] = -1
    for k in range(n_sleep):
        i = sleepers[k]
        freeze(i, settings, counters, bodies, contacts, activity)
        states[i] = _SLEEPING
        record(events, counters, i, _FREE, _SLEEPING, _TIMER)
