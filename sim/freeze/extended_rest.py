"""The ``extended`` policy's rest test: the stages that judge whether a still body is at rest,
beyond its own speed (``sim.freeze.extended`` runs them in ``after_solve``; the certificate of
static equilibrium is ``certificate.py``).

  slow_and_steady  a body's own speed and its change since its last test, and the rest count
  unsettled     a contact still working: sliding at its friction limit, a gap still closing,
                or deep and opening
  whole_groups  a candidate touching an awake body in motion is no candidate (to a fixed point)
  wedges        candidates refused one by one, certified together with the candidates they touch
                as one rigid body (``certificate.group_holds``)
  on_the_awake  a certified candidate that rests on an awake body not freezing with it waits for
                it (to a fixed point)

Split from ``extended.py`` by job: these judge contacts and groups of bodies, once per step,
while the hook that calls them moves data (freezes bodies, records the support graph); the
wake rules are ``extended_wake.py``.
"""

from ..data import (
    ANCHOR_BX,
    ANCHOR_BY,
    BODY_A,
    BODY_B,
    END_SEPARATION,
    FRICTION,
    NORMAL_IMPULSE,
    NORMAL_X,
    NORMAL_Y,
    POINT_COUNT,
    SEPARATION,
    SLOP,
    TANGENT_IMPULSE,
)
import numpy as np

from ..jit import inline_kernel, kernel, lean_kernel
from . import certificate, feasibility
from .contact_math import touching
from .extended_layout import (
    BRACED,
    MARK,
    PREVIOUS_VX,
    PREVIOUS_VY,
    PREVIOUS_W,
    REST_COUNT,
    TESTED,
    WAIT_CHANGING,
    WAIT_COUNTING,
    WAIT_MOVING,
    WAIT_NEIGHBOUR,
    WAIT_NONE,
    WAIT_ON_AWAKE,
    WAITING,
    impulse_on,
    is_movable,
    is_support,
)


#: a contact whose friction is at this share of its Coulomb limit, or more, is sliding
SLIDING_SHARE = 0.98
#: what ``unsettled`` finds in a contact
SLIDING, DEEP, CLOSING = 1, 2, 3


@inline_kernel
def slow_and_steady(i, step, settings, bodies, body_real, body_int):
    """The rest test's first stages for awake body i in step ``step`` (counters[STEP_COUNT]):
    slow (|v| + |w| extent below rest_speed), steady (its velocity changed by at most
    rest_acceleration dt since its last test) and so for rest_steps tests in a row. Returns
    whether it is a candidate (MARK 1); else WAITING says why not.

    Only bodies with a contact (a pair whose fat boxes overlap) are tested
    (``extended.after_solve``): a body with none is never certified (nothing near it can stop its
    fall or its drift), so where nothing is near anything the policy costs nothing per body
    (before, every awake body was tested every step: 6.9% of a 0.09 ms step of 1000 boxes in
    free fall). The change is measured against the previous step's test only (step 1's against
    the World's starting velocities, ``extended.initial``): a body not tested then (without a
    contact, or frozen: a frozen body's TESTED is NEVER_TESTED) has no velocity to compare with,
    and counts as changing."""
    consecutive = body_int[i, TESTED] == step - 1
    body_int[i, TESTED] = step
    limit = settings.rest_speed
    vx = bodies.velocity[i, 0]
    vy = bodies.velocity[i, 1]
    w = bodies.angular_velocity[i]
    extent = bodies.extent[i]
    body_int[i, MARK] = 0
    body_int[i, WAITING] = WAIT_NONE
    dvx = vx - body_real[i, PREVIOUS_VX]
    dvy = vy - body_real[i, PREVIOUS_VY]
    dw = w - body_real[i, PREVIOUS_W]
    body_real[i, PREVIOUS_VX] = vx
    body_real[i, PREVIOUS_VY] = vy
    body_real[i, PREVIOUS_W] = w
    # cheap exit for bodies clearly in motion: any one component at or above the limit means
    # |v| + |w| extent is too
    if abs(vx) >= limit or abs(vy) >= limit or abs(w) * extent >= limit:
        body_int[i, REST_COUNT] = 0
        body_int[i, WAITING] = WAIT_MOVING
        return False
    speed = np.sqrt(vx * vx + vy * vy) + abs(w) * extent
    change = np.sqrt(dvx * dvx + dvy * dvy) + abs(dw) * extent
    if speed < limit and consecutive and change <= settings.rest_acceleration * settings.dt:
        body_int[i, REST_COUNT] += 1
    else:
        body_int[i, REST_COUNT] = 0
        body_int[i, WAITING] = WAIT_MOVING if speed >= limit else WAIT_CHANGING
    # MARK = 1: candidate (slow and steady long enough); cleared by the later stages when a
    # contact moves, a neighbour cannot rest or the certificate fails (each records why: WAITING)
    if body_int[i, REST_COUNT] >= settings.rest_steps:
        body_int[i, MARK] = 1
        return True
    if body_int[i, WAITING] == WAIT_NONE:
        body_int[i, WAITING] = WAIT_COUNTING
    return False


@lean_kernel
def whole_groups(count, n_dyn, awake, n_awake, contacts, awake_slot, body_int):
    """Clear the mark of every candidate (MARK 1) that touches an awake body in motion (MARK 0),
    to a fixed point: an awake body that is still moving keeps its neighbours awake, so nothing
    freezes against something that pushes it. Returns whether any candidate is left."""
    ci = contacts.contact_int
    changed = True
    while changed:
        changed = False
        for kk in range(count):
            c = contacts.active[kk]
            a = ci[c, BODY_A]
            b = ci[c, BODY_B]
            if not (is_movable(a, n_dyn, awake_slot) and is_movable(b, n_dyn, awake_slot)):
                continue
            if not touching(c, contacts):
                continue  # made ahead for a fast body that did not arrive
            if body_int[a, MARK] + body_int[b, MARK] == 1:  # a candidate and a mover
                candidate = a if body_int[a, MARK] == 1 else b
                body_int[candidate, WAITING] = WAIT_NEIGHBOUR
                body_int[a, MARK] = 0
                body_int[b, MARK] = 0
                changed = True
    for k in range(n_awake):
        if body_int[awake[k], MARK] == 1:
            return True
    return False


@inline_kernel
def unsettled(c, settings, dt, bodies, contacts):
    """Is contact c still working? ``SLIDING``: its friction at the Coulomb limit while the
    surfaces slip faster than ``slip_speed`` (m/s); else ``CLOSING``: a point apart but within
    the pair's slop whose gap closed faster than ``closing_speed`` (m/s) over the step (dt, s);
    else ``DEEP``: a touching point deeper than twice the pair's slop that opened faster than
    ``opening_speed`` (m/s) over the step; else 0 (the speeds from ``settings``).

    Why CLOSING. A point within slop counts as touching, and the certificate takes it as a
    support, which can stop the body's momentum (``certificate``, MOTION): without gravity, a box
    drifting at 1 cm/s toward a static wall 1 mm away was frozen in its first step, and one
    starting 1 cm away was frozen 5 mm (the slop) short of the wall, still moving. A gap that is
    still closing has not yet met the surface that would stop it; in drop(30), seeds 0-5, no
    body froze with such a point (291 freezes), and over 100 seeds the median time to rest
    stayed 231 steps, 7 piles never frozen.

    (One speed served the sliding and deep tests until 2026-12: raising slip_speed to let slow
    slides through also switched the deep test off. Over 100 seeds of drop(30), piles froze
    whole at a median step of 225.5 with both tests, 199 with the sliding test off, 204.5 with
    the deep one off and 163 with both off, the last by freezing bodies in deep, opening
    contacts.)"""
    position, velocity, angular_velocity = bodies.position, bodies.velocity, bodies.angular_velocity
    ci = contacts.contact_int
    cf = contacts.contact_float
    pf = contacts.point_float
    a = ci[c, BODY_A]
    b = ci[c, BODY_B]
    sum_pn = 0.0
    sum_pt = 0.0
    slip = 0.0
    deep = False
    closing = False
    for j in range(ci[c, POINT_COUNT]):
        # deep and still opening: the soft contact is pushing the bodies apart (a contact that
        # carries a load sits at a steady depth, which freezing keeps as it is)
        deep = deep or (
            pf[c, j, END_SEPARATION] < -2.0 * cf[c, SLOP]
            and pf[c, j, END_SEPARATION] - pf[c, j, SEPARATION] > settings.opening_speed * dt
        )
        if pf[c, j, END_SEPARATION] > cf[c, SLOP]:
            continue  # not touching
        closing = closing or (
            pf[c, j, END_SEPARATION] > 0.0
            and pf[c, j, END_SEPARATION] - pf[c, j, SEPARATION] < -settings.closing_speed * dt
        )
        sum_pn += pf[c, j, NORMAL_IMPULSE]
        sum_pt += pf[c, j, TANGENT_IMPULSE]
        # B's surface against A's along the tangent (ny, -nx)
        wx = pf[c, j, ANCHOR_BX] + position[b, 0]
        wy = pf[c, j, ANCHOR_BY] + position[b, 1]
        vx = velocity[b, 0] - angular_velocity[b] * (wy - position[b, 1])
        vy = velocity[b, 1] + angular_velocity[b] * (wx - position[b, 0])
        if a >= 0:
            vx -= velocity[a, 0] - angular_velocity[a] * (wy - position[a, 1])
            vy -= velocity[a, 1] + angular_velocity[a] * (wx - position[a, 0])
        slip = max(slip, abs(vx * cf[c, NORMAL_Y] - vy * cf[c, NORMAL_X]))
    # at the limit: the solver clamps |pt| <= mu pn point by point, so a manifold at 98% of it
    # is sliding (a sticking contact sits well inside)
    if (
        slip > settings.slip_speed
        and sum_pn > 0.0
        and abs(sum_pt) >= SLIDING_SHARE * cf[c, FRICTION] * sum_pn
    ):
        return SLIDING
    if closing:
        return CLOSING
    return DEEP if deep else 0


@inline_kernel
def _root(parent, k):
    while parent[k] != k:
        parent[k] = parent[parent[k]]
        k = parent[k]
    return k


#: a refused group grows ring by ring while its solve has at most this many equations (16 members);
#: past it, it is judged once more as the whole connected set of candidates (up to
#: ``feasibility.MAX_ROWS``; a larger set: as its first ring past RING_ROWS), a whole set once a
#: step however many refused groups lie in it. Why not ring by ring up to that size: a pile the
#: certificate refuses for good would pay every ring's solve every step (drop(30) seed 71 from step
#: 1000, 17 bodies still and refused, us a step, medians of 5 x 100 steps, one process per variant,
#: so noisy: rings stopped at 16 members 72-122, rings up to 32 266, one whole try 125-140; an awake
#: pile of 30 costs about 50). Before (until 2026-12) a group that grew past 16 members was not
#: judged again: drop(30) seed 46's pile, still and held as one group of 28 (its bodies wedged
#: between each other, their floor friction at its limit in the solver's witness), never froze
RING_ROWS = 48


@inline_kernel
def _group_certified(
    members,
    n_members,
    refused_members,
    saved,
    row_of,
    held,
    awake_slot,
    settings,
    bodies,
    contacts,
    count,
):
    """Is the group members[:n_members] held as one rigid body (``certificate.group_holds``),
    and each of its refused members (held False) with the others taken as immovable supports?
    The union can be held while a part of it turns on an edge inside it (a plank tipping slowly
    off the box it lies on, 2 mm past the edge, was frozen as one body with the box).
    awake_slot is marked -1 (frozen) for the members while they are judged, and restored."""
    if not certificate.group_holds(
        members, n_members, awake_slot, settings, bodies, contacts, count
    ):
        return False
    n_refused = np.int64(0)  # not a literal 0 (sim/jit, LITERALS)
    for m in range(n_members):
        i = members[m]
        saved[i] = awake_slot[i]
        awake_slot[i] = -1
        if not held[row_of[i]]:
            refused_members[n_refused] = i
            n_refused += 1
    parts, _ = certificate.holds(
        refused_members, n_refused, awake_slot, settings, bodies, contacts, count
    )
    for m in range(n_members):
        awake_slot[members[m]] = saved[members[m]]
    return parts[:n_refused].all()


@inline_kernel
def _grow(members, n_members, in_group, row_of, n_dyn, contacts, count):
    """Add to members every candidate (row_of >= 0) that touches a member and is not one yet;
    returns the new member count."""
    ci = contacts.contact_int
    n = n_members
    for kk in range(count):
        c = contacts.active[kk]
        a = ci[c, BODY_A]
        b = ci[c, BODY_B]
        if not (0 <= a < n_dyn and 0 <= b < n_dyn) or in_group[a] == in_group[b]:
            continue
        new = b if in_group[a] else a
        if row_of[new] < 0 or not touching(c, contacts):
            continue
        in_group[new] = True
        members[n] = new
        n += 1
    return n


@kernel
def wedges(candidates, n_candidates, held, n_dyn, awake_slot, settings, bodies, contacts, count):
    """Candidates the certificate refused one by one (held[k] False) may hold as a group: bodies
    that each rest on the other (a polygon on one floor point leaning on a body that rests on it)
    are refused one by one, since each one's support is the other, which may move; frozen one
    after the other, each froze and was woken by the other's push the next step, every step
    (drop(30) seed 4: 573 freezes and wakes in 10 s). Each refused candidate joins the candidates
    it touches into a group (connected through touching contacts with a refused member). A group
    is certified whole (held[k] True for all of its members) when ``certificate.group_holds``
    holds it as one rigid body *and* each refused member is held (``certificate.holds``) with the
    other members taken as immovable supports (``_group_certified``). A group that is not
    certified grows by the candidates it touches, ring by ring, and is judged again, until it
    holds or touches no more candidates; past ``RING_ROWS`` it is judged once more as the whole
    connected set of candidates, if that fits ``feasibility.MAX_ROWS``: inside a group the
    forces are solved for, while a load from outside stays at the solver's witness, which can
    leave too little friction to spare inside (drop(30) seed 2: two bodies whose one contact the
    witness puts at 98% of its friction limit were refused as a pair, for good, and held as five).
    A body balanced on one corner carrying a plank is still refused (as one body the pair stands on
    one point), and so is a plank tipping slowly off a box's edge (the box holds it on one point).
    Returns the number of group certificates tried."""
    ci = contacts.contact_int
    any_refused = False
    for k in range(n_candidates):
        any_refused = any_refused or not held[k]
    if not any_refused:
        return 0  # (before any work array: row_of costs a write per body of the World)
    row_of = np.full(n_dyn, -1, np.int64)
    parent = np.arange(n_candidates)
    for k in range(n_candidates):
        row_of[candidates[k]] = k
    for kk in range(count):
        c = contacts.active[kk]
        a = ci[c, BODY_A]
        b = ci[c, BODY_B]
        if not (0 <= a < n_dyn and 0 <= b < n_dyn and row_of[a] >= 0 and row_of[b] >= 0):
            continue
        ka = row_of[a]
        kb = row_of[b]
        if held[ka] and held[kb]:
            continue
        if not touching(c, contacts):
            continue
        ra = _root(parent, ka)
        rb = _root(parent, kb)
        if ra != rb:
            parent[ra] = rb
    members = np.empty(n_candidates, np.int64)
    refused_members = np.empty(n_candidates, np.int64)
    saved = np.empty(n_dyn, np.int64)
    in_group = np.zeros(n_dyn, np.bool_)
    whole_tried = np.zeros(n_dyn, np.bool_)  # a whole connected set judged in this step
    tried = 0
    for r in range(n_candidates):
        if _root(parent, r) != r:
            continue
        n_members = np.int64(0)  # not a literal 0 (sim/jit, LITERALS)
        refused = False
        for k in range(n_candidates):
            if _root(parent, k) == r:
                members[n_members] = candidates[k]
                in_group[candidates[k]] = True
                n_members += 1
                refused = refused or not held[k]
        if n_members >= 2 and refused:
            last = False
            while True:
                tried += 1
                if _group_certified(
                    members,
                    n_members,
                    refused_members,
                    saved,
                    row_of,
                    held,
                    awake_slot,
                    settings,
                    bodies,
                    contacts,
                    count,
                ):
                    for m in range(n_members):
                        held[row_of[members[m]]] = True
                    break
                # Not as it stands: the forces inside may need more freedom than its loads at
                # their witness leave (two bodies whose one contact the witness puts at 98% of
                # its friction limit, under a neighbour's push that could be less). So the
                # candidates it touches join it (one pass of _grow over the contacts, which can
                # reach several hops) while it has at most RING_ROWS equations; past that it
                # is judged once more, as the whole connected set of candidates, or, when that
                # is beyond the solve, as the first ring past RING_ROWS.
                if last:
                    break
                grown = _grow(members, n_members, in_group, row_of, n_dyn, contacts, count)
                if grown == n_members:
                    break
                if 3 * grown > RING_ROWS:
                    last = True
                    ring = grown
                    n_members = grown
                    while True:
                        grown = _grow(members, n_members, in_group, row_of, n_dyn, contacts, count)
                        if grown == n_members:
                            break
                        n_members = grown
                    if 3 * grown > feasibility.MAX_ROWS:
                        for m in range(ring, grown):  # back to the first ring past RING_ROWS
                            in_group[members[m]] = False
                        grown = ring
                        if 3 * grown > feasibility.MAX_ROWS:
                            n_members = grown
                            break
                    elif whole_tried[members[0]]:
                        # judged already in this step, from another refused group in the same
                        # set: the same question, the same answer
                        n_members = grown
                        break
                    else:
                        for m in range(grown):
                            whole_tried[members[m]] = True
                n_members = grown
        for m in range(n_members):
            in_group[members[m]] = False
    return tried


@lean_kernel
def on_the_awake(count, n_dyn, contacts, awake_slot, body_int, up_x, up_y):
    """Set MARK 2 (still, not frozen) on every certified candidate (MARK 1) that rests on an
    awake body that is not freezing with it, to a fixed point: "rests on" is an impulse on it
    that holds it up (``is_support``), as freezing records its supports; and, for a candidate
    the certificate held only with a bracing load's help (BRACED), any push of such a body.

    Why: a frozen body's supports must be at rest too, since the wake rules rely on it (a body
    wakes with what it rests on, through the support graph; an awake body's motion wakes
    nothing it does not push). The certificate takes an awake body under a candidate as a
    support, which holds for this step only, and once the candidate is frozen it is immovable,
    so it then clamps what it rests on: an inverted triangle balanced on its apex carrying a box
    was certified, box first and then triangle held by the frozen box, and both stayed frozen
    while off's fell (1e-3 rad off balance). The same holds for a brace: a plank standing on one
    corner, leaning on the side of a box that nothing held (frictionless) was certified, braced by
    the box, and frozen; frozen, it barely pushed the box, which crept away at a tenth of off's
    speed, and the plank stayed leaning on the air (until 2026-12). Any push of an awake body
    on any candidate (not only on a braced one) kept 6 of 100 drop(30) piles from ever freezing
    whole: a still body the certificate will not take (on one point) presses on its neighbours
    for good, and held them all awake."""
    ci = contacts.contact_int
    changed = True
    while changed:
        changed = False
        for kk in range(count):
            c = contacts.active[kk]
            a = ci[c, BODY_A]
            b = ci[c, BODY_B]
            if not (is_movable(a, n_dyn, awake_slot) and is_movable(b, n_dyn, awake_slot)):
                continue
            for i, other in ((a, b), (b, a)):
                if body_int[i, MARK] != 1 or body_int[other, MARK] == 1:
                    continue
                for j in range(ci[c, POINT_COUNT]):
                    px, py = impulse_on(i, c, j, contacts)
                    # what holds it up, or, when it needed a brace, anything that presses on it
                    if is_support(px, py, up_x, up_y) or (
                        body_int[i, BRACED] == 1
                        and contacts.point_float[c, j, NORMAL_IMPULSE] > 0.0
                    ):
                        body_int[i, MARK] = 2
                        body_int[i, WAITING] = WAIT_ON_AWAKE
                        changed = True
                        break
