"""The ``extended`` policy's wake rules and its support graph (see ``sim.freeze.extended``):
when a frozen body's equilibrium breaks (``equilibrium_broken``: pushed, lifted, tipping), waking
it (``wake_one``) and everything it supports (``wake_supported``), and the loads and links that
freezing records for those rules (``add_load``, ``push_on_support``, ``drop_links_of_awake``).

Split from ``extended.py`` by job: these move bodies back to motion and keep the support graph
consistent, and both hooks call them (``before_solve`` on the estimated pushes,
``after_solve`` on the solved impulses); the rest test is ``extended_rest.py``.
"""

import numpy as np

from ..activity import CAUSE, record, wake
from ..data import ANCHOR_BX, ANCHOR_BY, BODY_B, N_LINKS, POINT_COUNT
from ..jit import inline_kernel, lean_kernel
from .extended_layout import (
    CONE_HI,
    CONE_LO,
    BASE_M,
    BASE_X,
    BASE_Y,
    EXTRA_M,
    EXTRA_X,
    EXTRA_Y,
    FREE,
    LINK_FX,
    LINK_FY,
    LINK_M,
    LINK_PX,
    LINK_PY,
    LINK_SHARE,
    LOAD_M,
    MARK,
    PASSING,
    REACHED,
    SEND_M,
    SEND_X,
    SEND_Y,
    LOAD_X,
    LOAD_Y,
    PUSH_M,
    PUSH_NORMAL,
    PUSH_X,
    PUSH_Y,
    REST_COUNT,
    SUPPORT_H,
    SUPPORT_HI,
    SUPPORT_LO,
    SUPPORT_NX,
    SUPPORT_NY,
    TOUCHED,
    is_support,
    impulse_on,
)


#: a link whose share is within this of 1 carries all of its body (``transmit``)
SOLE_SUPPORT = 1e-9

#: the centre of pressure may sit this far (m) outside the support extent before a frozen body
#: counts as tipping: round-off in a body balanced on one point must not wake it
TIP_TOLERANCE = 1e-4

_IMPACT = CAUSE["impact"]
_PUSHED = CAUSE["pushed"]
_TIPPING = CAUSE["tipping"]
_SUPPORT_LOST = CAUSE["support_lost"]


@inline_kernel
def touch(i, touched, n_touched, body_real, body_int):
    """Add frozen body i to this pass's touched list, its push accumulators zeroed."""
    if body_int[i, TOUCHED] == 0:
        body_int[i, TOUCHED] = 1
        body_real[i, PUSH_X] = 0.0
        body_real[i, PUSH_Y] = 0.0
        body_real[i, PUSH_M] = 0.0
        body_real[i, PUSH_NORMAL] = 0.0
        touched[n_touched] = i
        return n_touched + 1
    return n_touched


@inline_kernel
def equilibrium_broken(i, body_real, position):
    """Cause code if frozen body i cannot stay at rest under its load plus this step's pushes,
    else -1 (``balance_broken``)."""
    return balance_broken(
        i,
        body_real[i, LOAD_X] + body_real[i, PUSH_X],
        body_real[i, LOAD_Y] + body_real[i, PUSH_Y],
        body_real[i, LOAD_M] + body_real[i, PUSH_M],
        body_real,
        position,
    )


@inline_kernel
def balance_broken(i, lx, ly, moment, body_real, position):
    """Cause code if frozen body i cannot stay at rest under the load (lx, ly) N s and ``moment``
    N m s about its centre of mass, else -1. The supports must supply the reaction
    R = -(load): it must lie in the supports' cone (its angle from the support direction n_s,
    toward t_s, in [CONE_LO, CONE_HI]: where their friction cones together reach) and act through
    the support extent: its centre of pressure s in [lo, hi]. The cone is the contacts' own: on a
    slope it leans with the slope, and a box already using most of its friction there has little
    left for a push. (Until 2026-12-07 it was the smallest friction about the direction of the
    support impulses, friction included: straight up on a slope, and a box using 0.53 of its 0.6
    friction on a 28 degree slope held a push of 0.6 of its weight down it where 0.05 moves it.)

    With q = h n + s t a point of the support line (h its offset along n) and x the centre of
    mass, moment balance cross(q - x, R) + M = 0 gives, since cross(n, R) = R.t and
    cross(t, R) = -R.n:  s = x.t + ((h - x.n) R.t + M) / R.n."""
    if lx == 0.0 and ly == 0.0 and moment == 0.0:
        return -1  # nothing acts on it (no gravity, nothing pressing): nothing to hold
    if body_real[i, SUPPORT_HI] < body_real[i, SUPPORT_LO]:
        # no recorded support point (frozen without gravity, touching only what pressed on it
        # with nothing): nothing it touches is known to hold it, so any load moves it. Judged
        # around a made-up normal instead, a box pushed toward its wall side stayed frozen
        return _PUSHED
    nx = body_real[i, SUPPORT_NX]
    ny = body_real[i, SUPPORT_NY]
    tx = -ny
    ty = nx
    rn = -(lx * nx + ly * ny)
    rt = -(lx * tx + ly * ty)
    lo = body_real[i, CONE_LO]
    hi = body_real[i, CONE_HI]
    if hi - lo < np.pi:
        angle = np.arctan2(rt, rn)
        if angle < lo or angle > hi:
            return _PUSHED  # no push its supports can give holds it: it slides, or lifts off
    elif rn <= 0.0:
        return _PUSHED  # lifted off its supports

    x_t = position[i, 0] * tx + position[i, 1] * ty
    x_n = position[i, 0] * nx + position[i, 1] * ny
    s = x_t + ((body_real[i, SUPPORT_H] - x_n) * rt + moment) / rn
    if s < body_real[i, SUPPORT_LO] - TIP_TOLERANCE or s > body_real[i, SUPPORT_HI] + TIP_TOLERANCE:
        return _TIPPING
    return -1


@lean_kernel
def judge_touched(n_touched, impacts, work, settings, counters, bodies, contacts, activity):
    """Judge the frozen bodies that awake bodies touch in this pass (touched[0..n_touched-1],
    their pushes summed in PUSH), and then the frozen bodies under those that hold, which carry
    their pushes too (``transmit``, for this step only: EXTRA); wake each that no longer holds,
    and what it carries (``wake_supported``). A touched body that does not hold moves instead of
    passing its push on (its contacts push live from the next step). ``impacts``: PUSH holds the
    impulses estimated before the solve, and a touched body whose pushes over its mass exceed
    ``impact_speed`` wakes as an impact; one that nothing approaches (no push) is not judged then
    (its load held when it froze; what rests on it is judged after the solve). ``work``: the
    arrays (touched, queue, reached: (N,) or longer; ring: (N+1,)). Returns the number woken."""
    touched, queue, ring, reached = work
    body_real, body_int, awake_slot = activity.body_real, activity.body_int, activity.awake_slot
    position = bodies.position
    n_ring = np.int64(0)  # not literals (sim/jit, LITERALS)
    n_queue = np.int64(0)
    for k in range(n_touched):
        i = touched[k]
        if impacts and body_real[i, PUSH_NORMAL] * bodies.inv_mass[i] > settings.impact_speed:
            cause = _IMPACT
        elif impacts and body_real[i, PUSH_NORMAL] <= 0.0:
            cause = -1
        else:
            cause = equilibrium_broken(i, body_real, position)
        if cause >= 0:
            n_queue = wake_one(
                i, cause, n_queue, queue, settings, counters, bodies, contacts, activity
            )
        else:
            # its change since it froze: before the solve the estimated new impulses alone (the
            # bodies resting on it are not in the estimate, and have not left); after it, its
            # load and this step's pushes against what it passed on when it froze
            keep = 0.0 if impacts else 1.0
            n_ring = send(
                i,
                body_real[i, PUSH_X] + keep * (body_real[i, LOAD_X] - body_real[i, BASE_X]),
                body_real[i, PUSH_Y] + keep * (body_real[i, LOAD_Y] - body_real[i, BASE_Y]),
                body_real[i, PUSH_M] + keep * (body_real[i, LOAD_M] - body_real[i, BASE_M]),
                ring,
                n_ring,
                body_real,
                body_int,
            )
    n_reached = transmit(n_ring, ring, reached, not impacts, counters, bodies, activity)
    for k in range(n_reached):
        i = reached[k]
        if awake_slot[i] >= 0:
            continue
        # a touched body reached from above is judged again, its own pushes and theirs together
        own = 1.0 if body_int[i, TOUCHED] == 1 else 0.0
        cause = balance_broken(
            i,
            body_real[i, LOAD_X] + own * body_real[i, PUSH_X] + body_real[i, EXTRA_X],
            body_real[i, LOAD_Y] + own * body_real[i, PUSH_Y] + body_real[i, EXTRA_Y],
            body_real[i, LOAD_M] + own * body_real[i, PUSH_M] + body_real[i, EXTRA_M],
            body_real,
            position,
        )
        if cause >= 0:
            n_queue = wake_one(
                i, cause, n_queue, queue, settings, counters, bodies, contacts, activity
            )
    for k in range(n_touched):
        body_int[touched[k], TOUCHED] = 0
    clear_reached(n_reached, reached, body_real, body_int)
    return wake_supported(n_queue, queue, settings, counters, bodies, contacts, activity)


@inline_kernel
def wake_one(i, cause, n_queue, queue, settings, counters, bodies, contacts, activity):
    """Wake frozen body i for ``cause`` (a ``CAUSE`` code): back in the awake list, FREE, the
    event recorded, its rest count reset; it joins ``queue`` (what it supports wakes next:
    ``wake_supported``). Returns the queue's new length."""
    wake(i, settings, counters, bodies, contacts, activity)
    record(activity.events, counters, i, activity.states[i], FREE, cause)
    activity.states[i] = FREE
    activity.body_int[i, REST_COUNT] = 0
    queue[n_queue] = i
    return n_queue + 1


@lean_kernel
def wake_supported(n_queue, queue, settings, counters, bodies, contacts, activity):
    """Support removed: everything the bodies in queue[0..n_queue-1] carry wakes too, in this
    same step, transitively (breadth first over the links). Returns the number woken in all."""
    links, awake_slot = activity.links, activity.awake_slot
    head = 0
    while head < n_queue:
        s = queue[head]
        head += 1
        for k in range(counters[N_LINKS]):
            if links[k, 0] == s and awake_slot[links[k, 1]] < 0:
                n_queue = wake_one(
                    links[k, 1],
                    _SUPPORT_LOST,
                    n_queue,
                    queue,
                    settings,
                    counters,
                    bodies,
                    contacts,
                    activity,
                )
    if n_queue > 0:
        drop_links_of_awake(counters, activity)
    return n_queue


@lean_kernel
def drop_links_of_awake(counters, activity):
    """Compact the link list, keeping only links whose supported body is still frozen (or
    freezing in this step: MARK 1; dropped, a body freezing when the list was full lost its
    links). A dropped link's push leaves its support's load: the awake body's contacts now push
    live (else the support would count that weight twice and could not see the body tip or
    leave)."""
    links, link_load = activity.links, activity.link_load
    awake_slot, body_real, body_int = activity.awake_slot, activity.body_real, activity.body_int
    kept = 0
    for k in range(counters[N_LINKS]):
        support = links[k, 0]
        body = links[k, 1]
        if awake_slot[body] < 0 or body_int[body, MARK] == 1:
            links[kept, 0] = support
            links[kept, 1] = body
            for col in range(link_load.shape[1]):
                link_load[kept, col] = link_load[k, col]
            kept += 1
        elif awake_slot[support] < 0:
            body_real[support, LOAD_X] -= link_load[k, LINK_FX]
            body_real[support, LOAD_Y] -= link_load[k, LINK_FY]
            body_real[support, LOAD_M] -= link_load[k, LINK_M]
    counters[N_LINKS] = kept


@inline_kernel
def send(i, fx, fy, m, ring, n_ring, body_real, body_int):
    """Queue the load (fx, fy) N s with moment ``m`` N m s about frozen body i's centre, newly on
    i, to be passed on to i's supports by ``transmit``. Returns the ring's new length."""
    body_real[i, SEND_X] += fx
    body_real[i, SEND_Y] += fy
    body_real[i, SEND_M] += m
    return _enqueue(i, ring, n_ring, body_int)


@inline_kernel
def _enqueue(i, ring, n_ring, body_int):
    # a body waits in the ring at most once (PASSING), so N + 1 slots never overflow
    if body_int[i, PASSING] == 1:
        return n_ring
    body_int[i, PASSING] = 1
    ring[n_ring % ring.shape[0]] = i
    return n_ring + 1


@lean_kernel
def transmit(n_ring, ring, reached, own_changes, counters, bodies, activity):
    """Pass the changes queued by ``send`` down the support graph, for this step only: a frozen
    body whose load differs from what it passed to its supports when it froze (BASE) passes the
    difference on to its frozen supports, each its share (link LINK_SHARE: its part of the body's
    support against gravity when it froze), and so on down. The supports' loads hold what the
    body carried when it froze; a block landing on a frozen plank later, or a push on it, is a
    change they never saw. Without this a block landing on the end of a frozen plank, on a plate,
    on a narrow pedestal whose edge the three bodies' centre of mass had passed, was judged
    against the plank's supports only, and the tower stood where ``off``'s tipped.

    Each reached body gets the changes from above in EXTRA and, ``own_changes``, adds its own
    (LOAD - BASE: bodies that froze onto it since, or woke off it, or the awake ones that pushed
    on it when it froze and left) to what it passes on. Returns how many bodies were reached,
    listed in ``reached`` with REACHED set; the caller judges them (LOAD + EXTRA) and clears them
    (``clear_reached``). Adding changes instead (a running load) counted twice what the supports
    already held: a body resting on a frozen one when both froze is in the lower one's load
    through the upper one's push, and its weight came again when it froze or pushed live.

    A support that holds all of its body up takes the whole change, its moment moved to the
    support's centre (exact: one rigid body on another). One of several takes its share of the
    force, at its contact: how a moment shifts the load among them is not known from one
    distribution (given as shares of the moment, the pillars under a plank each read a weight at
    its end as their own, and woke as tipping). A cycle in the graph would pass a change round
    for ever, smaller each time: the passes stop after 4 (N + L)."""
    links, link_load = activity.links, activity.link_load
    awake_slot, body_real, body_int = activity.awake_slot, activity.body_real, activity.body_int
    position = bodies.position
    n_reached = 0
    head = 0
    limit = 4 * (ring.shape[0] + counters[N_LINKS])
    while head < n_ring and head < limit:
        x = ring[head % ring.shape[0]]
        head += 1
        body_int[x, PASSING] = 0
        sx = body_real[x, SEND_X]
        sy = body_real[x, SEND_Y]
        sm = body_real[x, SEND_M]
        body_real[x, SEND_X] = 0.0
        body_real[x, SEND_Y] = 0.0
        body_real[x, SEND_M] = 0.0
        if sx == 0.0 and sy == 0.0 and sm == 0.0:
            continue
        for k in range(counters[N_LINKS]):
            if links[k, 1] != x:
                continue
            s = links[k, 0]
            share = link_load[k, LINK_SHARE]
            if awake_slot[s] >= 0 or share == 0.0:
                continue
            if share >= 1.0 - SOLE_SUPPORT:
                fx = sx
                fy = sy
                m = sm + (position[x, 0] - position[s, 0]) * fy
                m -= (position[x, 1] - position[s, 1]) * fx
            else:
                fx = share * sx
                fy = share * sy
                m = (link_load[k, LINK_PX] - position[s, 0]) * fy
                m -= (link_load[k, LINK_PY] - position[s, 1]) * fx
            body_real[s, EXTRA_X] += fx
            body_real[s, EXTRA_Y] += fy
            body_real[s, EXTRA_M] += m
            if body_int[s, REACHED] == 0:
                body_int[s, REACHED] = 1
                reached[n_reached] = s
                n_reached += 1
                if own_changes and body_int[s, TOUCHED] == 0:  # (a touched one sent its own)
                    fx += body_real[s, LOAD_X] - body_real[s, BASE_X]
                    fy += body_real[s, LOAD_Y] - body_real[s, BASE_Y]
                    m += body_real[s, LOAD_M] - body_real[s, BASE_M]
            n_ring = send(s, fx, fy, m, ring, n_ring, body_real, body_int)
    while head < n_ring:  # stopped at the limit: leave no body marked as queued
        x = ring[head % ring.shape[0]]
        head += 1
        body_int[x, PASSING] = 0
        body_real[x, SEND_X] = 0.0
        body_real[x, SEND_Y] = 0.0
        body_real[x, SEND_M] = 0.0
    return n_reached


@inline_kernel
def clear_reached(n_reached, reached, body_real, body_int):
    """Undo ``transmit``'s marks on the bodies it reached: REACHED and this step's EXTRA."""
    for k in range(n_reached):
        i = reached[k]
        body_int[i, REACHED] = 0
        body_real[i, EXTRA_X] = 0.0
        body_real[i, EXTRA_Y] = 0.0
        body_real[i, EXTRA_M] = 0.0


@inline_kernel
def add_load(i, fx, fy, c, j, contacts, position, body_real):
    """Add impulse (fx, fy), applied at point j of contact c, to frozen body i's load."""
    b = contacts.contact_int[c, BODY_B]
    wx = contacts.point_float[c, j, ANCHOR_BX] + position[b, 0]
    wy = contacts.point_float[c, j, ANCHOR_BY] + position[b, 1]
    body_real[i, LOAD_X] += fx
    body_real[i, LOAD_Y] += fy
    body_real[i, LOAD_M] += (wx - position[i, 0]) * fy - (wy - position[i, 1]) * fx


@inline_kernel
def push_on_support(i, support, c, contacts, position, up_x, up_y):
    """The impulse body i exerts on ``support`` through contact c at the points where it is
    supported (the same points whose push enters the support's load), its moment about the
    support's centre of mass, and where it acts (m, world): the points' mean, weighted by how
    much each holds i up."""
    b = contacts.contact_int[c, BODY_B]
    fx = 0.0
    fy = 0.0
    m = 0.0
    ax = 0.0
    ay = 0.0
    weight = 0.0
    for j in range(contacts.contact_int[c, POINT_COUNT]):
        px, py = impulse_on(i, c, j, contacts)
        if is_support(px, py, up_x, up_y):
            wx = contacts.point_float[c, j, ANCHOR_BX] + position[b, 0]
            wy = contacts.point_float[c, j, ANCHOR_BY] + position[b, 1]
            fx -= px
            fy -= py
            m -= (wx - position[support, 0]) * py - (wy - position[support, 1]) * px
            up = px * up_x + py * up_y
            ax += up * wx
            ay += up * wy
            weight += up
    if weight > 0.0:
        ax /= weight
        ay /= weight
    return fx, fy, m, ax, ay
