"""The ``extended`` policy's freezing (see ``sim.freeze.extended``): the bodies its rest test
certified become frozen, each with the summary of its supports and loads that the wake rules
(``extended_wake``) read. Split from ``extended.py`` by job: the hook there decides who freezes;
this records what each frozen body stands on, what it carries, and what it passes on.
"""

import numpy as np

from ..activity import CAUSE, freeze, record
from ..data import (
    ANCHOR_BX,
    ANCHOR_BY,
    BODY_A,
    BODY_B,
    FRICTION,
    N_ACTIVE,
    N_AWAKE,
    N_LINKS,
    NORMAL_IMPULSE,
    POINT_COUNT,
)
from ..jit import lean_kernel
from .extended_layout import (
    BASE_M,
    BASE_X,
    BASE_Y,
    CONE_HI,
    CONE_LO,
    FREE,
    FROZEN,
    LINK_FX,
    LINK_FY,
    LINK_M,
    LINK_PX,
    LINK_PY,
    LINK_SHARE,
    LOAD_M,
    LOAD_X,
    LOAD_Y,
    MARK,
    NEVER_TESTED,
    REST_COUNT,
    SUPPORT_H,
    SUPPORT_HI,
    SUPPORT_LO,
    SUPPORT_NX,
    SUPPORT_NY,
    SUPPORT_UP,
    TESTED,
    TOUCHED,
    impulse_on,
    is_movable,
    is_support,
    normal_on,
)
from .extended_rest import on_the_awake
from .extended_wake import add_load, drop_links_of_awake, push_on_support

_RESTED = CAUSE["rested"]


@lean_kernel
def freeze_certified(settings, counters, bodies, contacts, activity):
    """``after_solve``'s last part: freeze every body still marked (MARK 1), with the summary of
    its supports and loads that the wake rules read, and what it passes on to its supports
    (BASE: ``extended_wake.transmit`` passes on only changes from it)."""
    position = bodies.position
    inv_mass = bodies.inv_mass
    ci = contacts.contact_int
    cf = contacts.contact_float
    pf = contacts.point_float
    states, awake, awake_slot, events = (
        activity.states,
        activity.awake,
        activity.awake_slot,
        activity.events,
    )
    body_real, body_int = activity.body_real, activity.body_int
    links, link_load = activity.links, activity.link_load
    n_dyn = settings.n_dynamic
    dt = settings.dt
    gx = settings.gravity_x
    gy = settings.gravity_y
    g = np.hypot(gx, gy)
    up_x = -gx / g if g > 0 else 0.0
    up_y = -gy / g if g > 0 else 1.0
    count = counters[N_ACTIVE]
    n_awake = counters[N_AWAKE]
    on_the_awake(count, n_dyn, contacts, awake_slot, body_int, up_x, up_y)
    # freeze the survivors: summarise supports and loads, link dynamic supports
    for k in range(n_awake):
        i = awake[k]
        if body_int[i, MARK] == 1:
            body_real[i, LOAD_X] = gx * dt / inv_mass[i]
            body_real[i, LOAD_Y] = gy * dt / inv_mass[i]
            body_real[i, LOAD_M] = 0.0
            body_real[i, SUPPORT_NX] = 0.0
            body_real[i, SUPPORT_NY] = 0.0
            body_real[i, SUPPORT_UP] = 0.0
            body_real[i, BASE_X] = 0.0
            body_real[i, BASE_Y] = 0.0
            body_real[i, BASE_M] = 0.0
    for kk in range(count):
        c = contacts.active[kk]
        a = ci[c, BODY_A]
        b = ci[c, BODY_B]
        for i, other in ((a, b), (b, a)):
            if not (is_movable(i, n_dyn, awake_slot) and body_int[i, MARK] == 1):
                continue
            sx = 0.0
            sy = 0.0
            onto_frozen = 0 <= other < n_dyn and awake_slot[other] < 0
            # A push enters the load only from what stays still with i: the floor, a static or
            # frozen body, or one freezing with it (whose link takes its push back when it
            # wakes). An awake body's push is read live every step (PUSH, ``_candidates``): in
            # the load too it counted twice, and stayed there after the body left (a box with a
            # triangle balanced on its apex, which later tipped off, kept the triangle's weight
            # for good, and a box sliding into it was stopped dead where off's moved it).
            holds_still = not is_movable(other, n_dyn, awake_slot) or body_int[other, MARK] == 1
            for j in range(ci[c, POINT_COUNT]):
                px, py = impulse_on(i, c, j, contacts)
                if is_support(px, py, up_x, up_y):
                    sx += px
                    sy += py
                    body_real[i, SUPPORT_UP] += px * up_x + py * up_y
                    if onto_frozen:
                        # resting on an already frozen body: that body now carries this push,
                        # the opposite of the support impulse, at this very point (and so do
                        # its own supports: a change from what it passed on, ``transmit``)
                        add_load(other, -px, -py, c, j, contacts, position, body_real)
                else:
                    wx = pf[c, j, ANCHOR_BX] + position[b, 0]
                    wy = pf[c, j, ANCHOR_BY] + position[b, 1]
                    m = (wx - position[i, 0]) * py - (wy - position[i, 1]) * px
                    if holds_still:  # a load
                        body_real[i, LOAD_X] += px
                        body_real[i, LOAD_Y] += py
                        body_real[i, LOAD_M] += m
                    else:  # an awake body's push: not in the load, but its supports carry it
                        body_real[i, BASE_X] += px
                        body_real[i, BASE_Y] += py
                        body_real[i, BASE_M] += m
            if sx != 0.0 or sy != 0.0:
                # impulse-weighted support direction: the reaction's at freezing, so that the
                # tipping test's support line is square to it (where the support points are not
                # on one line, as on two slanted neighbours, their mean offset h then does not
                # move the centre of pressure; square to the mean contact normal instead, it did,
                # and bodies of the drop(30) piles woke as tipping the step after they froze)
                body_real[i, SUPPORT_NX] += sx
                body_real[i, SUPPORT_NY] += sy
                if 0 <= other < n_dyn:
                    n_links = counters[N_LINKS]
                    if n_links == links.shape[0]:
                        drop_links_of_awake(counters, activity)
                        n_links = counters[N_LINKS]
                    if n_links < links.shape[0]:
                        links[n_links, 0] = other
                        links[n_links, 1] = i
                        # what i puts on its support (the support's load holds it, whether the
                        # support froze before or with i): taken back when i wakes
                        fx, fy, m, ax, ay = push_on_support(
                            i, other, c, contacts, position, up_x, up_y
                        )
                        link_load[n_links, LINK_FX] = fx
                        link_load[n_links, LINK_FY] = fy
                        link_load[n_links, LINK_M] = m
                        link_load[n_links, LINK_PX] = ax
                        link_load[n_links, LINK_PY] = ay
                        # the part of i held up here, over all of i's: made a fraction below
                        link_load[n_links, LINK_SHARE] = -(fx * up_x + fy * up_y)
                        counters[N_LINKS] = n_links + 1
    # each new link's share of its body's support against gravity (``transmit``)
    for k in range(counters[N_LINKS]):
        i = links[k, 1]
        if body_int[i, MARK] == 1 and awake_slot[i] >= 0:
            up = body_real[i, SUPPORT_UP]
            link_load[k, LINK_SHARE] = link_load[k, LINK_SHARE] / up if up > 0.0 else 0.0
    # support extent along the tangent of the dominant support normal
    for k in range(n_awake):
        i = awake[k]
        if body_int[i, MARK] == 1:
            nx = body_real[i, SUPPORT_NX]
            ny = body_real[i, SUPPORT_NY]
            norm = np.hypot(nx, ny)
            if norm > 0.0:
                body_real[i, SUPPORT_NX] = nx / norm
                body_real[i, SUPPORT_NY] = ny / norm
            else:  # held with no support against gravity: zero-g scenes
                body_real[i, SUPPORT_NX] = up_x
                body_real[i, SUPPORT_NY] = up_y
            body_real[i, SUPPORT_LO] = np.inf
            body_real[i, SUPPORT_HI] = -np.inf
            body_real[i, SUPPORT_H] = 0.0
            body_real[i, CONE_LO] = np.inf
            body_real[i, CONE_HI] = -np.inf
            body_int[i, TOUCHED] = 0  # scratch: number of support points
    for kk in range(count):
        c = contacts.active[kk]
        a = ci[c, BODY_A]
        b = ci[c, BODY_B]
        for i in (a, b):
            if not (is_movable(i, n_dyn, awake_slot) and body_int[i, MARK] == 1):
                continue
            tx = -body_real[i, SUPPORT_NY]
            ty = body_real[i, SUPPORT_NX]
            # a side contact with a body that cannot move (a wall, a frozen neighbour, one
            # freezing in this step) holds i against turning too: the certificate counts it, so
            # the extent does. Left out, a body certified on one floor point and a frozen
            # neighbour had an extent of one point, and any load on it woke it as tipping (most
            # wakes of the drop(30) piles)
            other = a if i == b else b
            immovable = not is_movable(other, n_dyn, awake_slot) or body_int[other, MARK] == 1
            for j in range(ci[c, POINT_COUNT]):
                px, py = impulse_on(i, c, j, contacts)
                up = is_support(px, py, up_x, up_y)
                if up or (immovable and pf[c, j, NORMAL_IMPULSE] > 0.0):
                    wx = pf[c, j, ANCHOR_BX] + position[b, 0]
                    wy = pf[c, j, ANCHOR_BY] + position[b, 1]
                    s = wx * tx + wy * ty
                    body_real[i, SUPPORT_LO] = min(body_real[i, SUPPORT_LO], s)
                    body_real[i, SUPPORT_HI] = max(body_real[i, SUPPORT_HI], s)
                    if up:  # the support line's offset: from the points that hold i up
                        body_real[i, SUPPORT_H] += wx * ty - wy * tx  # along n = -perp(t)
                        body_int[i, TOUCHED] += 1
                        # the point's friction cone, in angles from the mean normal: the
                        # supports can push together anywhere between their cones' edges
                        qx, qy = normal_on(i, c, contacts)
                        angle = np.arctan2(qx * tx + qy * ty, qx * ty - qy * tx)
                        half = np.arctan(cf[c, FRICTION])
                        body_real[i, CONE_LO] = min(body_real[i, CONE_LO], angle - half)
                        body_real[i, CONE_HI] = max(body_real[i, CONE_HI], angle + half)
    k = 0
    while k < counters[N_AWAKE]:
        i = awake[k]
        if body_int[i, MARK] == 1:
            body_real[i, BASE_X] += body_real[i, LOAD_X]
            body_real[i, BASE_Y] += body_real[i, LOAD_Y]
            body_real[i, BASE_M] += body_real[i, LOAD_M]
            if body_int[i, TOUCHED] > 0:
                body_real[i, SUPPORT_H] /= body_int[i, TOUCHED]
            body_int[i, TOUCHED] = 0
            body_int[i, MARK] = 0
            body_int[i, REST_COUNT] = 0
            # no test in a row with a test from before the freeze: a body woken in the next
            # step (after that step's solve, in which it was immovable) was compared with its
            # velocity from before the freeze, counted as steady, and could freeze again in the
            # step it woke (a box frozen on the floor and woken by a box landing on it)
            body_int[i, TESTED] = NEVER_TESTED
            freeze(i, settings, counters, bodies, contacts, activity)
            states[i] = FROZEN
            record(events, counters, i, FREE, FROZEN, _RESTED)
            continue  # freeze() moved the last awake body into slot k
        k += 1
