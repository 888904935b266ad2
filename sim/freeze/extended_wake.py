"""The ``extended`` policy's wake rules and its support graph (see ``sim.freeze.extended``):
when a frozen body's equilibrium breaks (``equilibrium_broken``: pushed, lifted, tipping), waking
it (``wake_one``) and everything it supports (``wake_supported``), and the loads and links that
freezing records for those rules (``add_load``, ``push_on_support``, ``drop_links_of_awake``).

Split from ``extended.py`` by job: these move bodies back to motion and keep the support graph
consistent, and both hooks call them (``before_solve`` on the estimated pushes,
``after_solve`` on the solved impulses); the rest test is ``extended_rest.py``.
"""

from ..activity import CAUSE, record, wake
from ..data import ANCHOR_BX, ANCHOR_BY, BODY_B, N_LINKS, POINT_COUNT
from ..jit import inline_kernel, lean_kernel
from .extended_layout import (
    FREE,
    LOAD_M,
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
    SUPPORT_MU,
    SUPPORT_NX,
    SUPPORT_NY,
    TOUCHED,
    is_support,
    impulse_on,
)


#: the centre of pressure may sit this far (m) outside the support extent before a frozen body
#: counts as tipping: round-off in a body balanced on one point must not wake it
TIP_TOLERANCE = 1e-4

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
    else -1. The supports must supply the reaction R = -(load + push): it must press into them
    (R . n_s > 0), stay inside the friction cone (|R . t_s| <= mu_s R . n_s) and act through the
    support extent: its centre of pressure s in [lo, hi].

    With q = h n + s t a point of the support line (h its offset along n) and x the centre of
    mass, moment balance cross(q - x, R) + M = 0 gives, since cross(n, R) = R.t and
    cross(t, R) = -R.n:  s = x.t + ((h - x.n) R.t + M) / R.n."""
    lx = body_real[i, LOAD_X] + body_real[i, PUSH_X]
    ly = body_real[i, LOAD_Y] + body_real[i, PUSH_Y]
    moment = body_real[i, LOAD_M] + body_real[i, PUSH_M]
    nx = body_real[i, SUPPORT_NX]
    ny = body_real[i, SUPPORT_NY]
    tx = -ny
    ty = nx
    rn = -(lx * nx + ly * ny)
    rt = -(lx * tx + ly * ty)
    if rn <= 0.0:
        return _PUSHED  # lifted off its supports
    if abs(rt) > body_real[i, SUPPORT_MU] * rn:
        return _PUSHED  # friction cannot hold it: it slides
    if body_real[i, SUPPORT_HI] < body_real[i, SUPPORT_LO]:
        return -1  # no recorded support points (zero gravity)
    x_t = position[i, 0] * tx + position[i, 1] * ty
    x_n = position[i, 0] * nx + position[i, 1] * ny
    s = x_t + ((body_real[i, SUPPORT_H] - x_n) * rt + moment) / rn
    if s < body_real[i, SUPPORT_LO] - TIP_TOLERANCE or s > body_real[i, SUPPORT_HI] + TIP_TOLERANCE:
        return _TIPPING
    return -1


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
    """Compact the link list, keeping only links whose supported body is still frozen. A dropped
    link's push leaves its support's load: the awake body's contacts now push live (else the
    support would count that weight twice and could not see the body tip or leave)."""
    links, link_load = activity.links, activity.link_load
    awake_slot, body_real = activity.awake_slot, activity.body_real
    kept = 0
    for k in range(counters[N_LINKS]):
        support = links[k, 0]
        if awake_slot[links[k, 1]] < 0:
            links[kept, 0] = support
            links[kept, 1] = links[k, 1]
            link_load[kept, 0] = link_load[k, 0]
            link_load[kept, 1] = link_load[k, 1]
            link_load[kept, 2] = link_load[k, 2]
            kept += 1
        elif awake_slot[support] < 0:
            body_real[support, LOAD_X] -= link_load[k, 0]
            body_real[support, LOAD_Y] -= link_load[k, 1]
            body_real[support, LOAD_M] -= link_load[k, 2]
    counters[N_LINKS] = kept


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
    supported (the same points whose push enters the support's load), and its moment about the
    support's centre of mass."""
    b = contacts.contact_int[c, BODY_B]
    fx = 0.0
    fy = 0.0
    m = 0.0
    for j in range(contacts.contact_int[c, POINT_COUNT]):
        px, py = impulse_on(i, c, j, contacts)
        if is_support(px, py, up_x, up_y):
            wx = contacts.point_float[c, j, ANCHOR_BX] + position[b, 0]
            wy = contacts.point_float[c, j, ANCHOR_BY] + position[b, 1]
            fx -= px
            fy -= py
            m -= (wx - position[support, 0]) * py - (wy - position[support, 1]) * px
    return fx, fy, m
