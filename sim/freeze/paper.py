"""``paper``: the seed's state machine, as written (``docs/seed/translation.md``), with its
limits left visible. Where the seed is vague, the choice made here is marked CHOICE.

States: FREE (the seed's vertical-unstable), VERTICAL_STABLE (VS), ROTATION_STABLE (RS).

Floor-like surfaces (sections 2, 5.2): the floor; an upward, floor-parallel face of a static body
(CHOICE: the seed has no static bodies; a fixed ledge is treated as the floor is); and the
floor-parallel top edge of an RS body. A contact counts as floor-like when its normal on the body
is within 1 degree of straight up (CHOICE: the normal alone decides, so an RS body's corner under a
mover's horizontal face counts as its edge too, as a triangle's apex under a flat box does).

Section 2, the impulse threshold: when a FREE body hits a floor-like surface with a normal
impulse larger than ``impulse_threshold`` (N s) it bounces by its impulse (the ordinary solve
stands); otherwise it *stays in contact*. CHOICE: the collision impulse is the one that stops the
body's approach against the (immovable) surface, from its velocity before gravity acts in the
step, at all its arriving points of a contact at once (``contact_math.approach_impulses``). In an
impulse solver a resting body also receives, every step, its weight and the weight of everything
it carries; that is not collision (judging the solved impulse instead froze no box in a pyramid's
bottom row: they carry more than the threshold). CHOICE: the default threshold, 1 N s (the seed
gives no value), is a 1 kg body landing at 1 m/s; ``fig_tradeoff`` sweeps it.

Section 4, staying in contact:
  - one vertex touching -> VS: that vertex no longer moves vertically (it is held on the
    surface's height); the body only rotates about it and translates horizontally. Done by solving
    the ordinary contacts and then one exact vertical constraint at the vertex (an impulse that
    zeroes the vertex's vertical velocity, and a translation that keeps it at its height). CHOICE:
    the vertex keeps the floor's friction.
  - two or more vertices touching, centre of mass over the support (its x within the touching
    points') -> RS. Otherwise the body keeps rotating: VS about the touching vertex on the side of
    the centre of mass. CHOICE: only a vertex of the body pivots, one the manifold has as its
    incident point (the support holds the reference face); a body whose touching point on that
    side is the support's corner under its face (tipping off an edge), or one whose face is the
    reference face (it lands nearly flat, and is on its face a step later), stays FREE (a VS
    body keeps its pivot).
RS: rotation and vertical motion stop (held at the pose reached, set down on the surface: CHOICE,
the step's solve may have begun a bounce the threshold has just ruled out); the body is no longer
solved against anything (its solver masses are zero: to others it is immovable); horizontal motion
goes on under Coulomb friction with its support, v_x reduced by mu g h in each substep h (CHOICE:
exactly as the solver applies friction to a sliding body, so an RS body slides as far as under
`off`), until it stops; then it is frozen outright (taken out of the awake list).

Section 5.1: a VS body in contact with an RS body (a point within the pair's slop, as a vertex
touches in section 4) for two consecutive steps -> both held at rest (frozen), until another body
collides with them. CHOICE: "stays in contact right after the collision" is read as the contact
lasting two steps; a collision above the threshold would have woken the RS body first
(``before_solve``). The RS body the VS body stands on is its floor (section 5.2), not a partner.
Section 5.2: a FREE body landing on an RS body's floor-parallel top edge treats it as the floor
(same threshold and states); two stacked RS bodies are held without computing their interaction
(frozen bodies are never paired). An RS body resting on another RS body whose centre of mass is no
longer over any of their contact points becomes FREE (seed figure 3).

Events: besides state changes, ``paper`` logs the moment a body is frozen outright without a
change of state, as an event whose from and to states are equal (RS -> RS "stopped_sliding",
VS -> VS or RS -> RS "held_by_contact"): counting state changes means skipping those.

Waking (section 3: "until a collision with another body is detected"): a moving body (FREE or VS)
colliding with a held or RS body anywhere but its floor-parallel top edge makes that body FREE,
before the step is solved. CHOICE: a collision is what section 2 calls one, an impact whose
impulse (estimated as the impulse that would stop the mover against an immovable body) exceeds
``impulse_threshold``; a body sliding or tipping along a held one does not wake it.
CHOICE (figure 3): a body freed because its centre of mass left its support's edge does not take
that edge as its floor again; it tips off it (otherwise it would at once become VS on the edge's
corner and, its vertex held up, never fall). Nothing else wakes a body (the seed's second limit): a
body resting on a body that is knocked away stays where it was, floating; a VS body moving on its
own never returns to FREE. CHOICE: a VS body held under section 5.1 and then struck wakes FREE, as
any held body does (the seed, 6.2, leaves VS -> FREE out; a held body woken keeps no pivot).
"""

import numpy as np

from ..activity import CAUSE, freeze, record, wake
from ..data import (
    ANCHOR_BX,
    BODY_A,
    BODY_B,
    FRICTION,
    INCIDENT,
    LOCAL_FACE_X,
    LOCAL_FACE_Y,
    LOCAL_X,
    LOCAL_Y,
    N_ACTIVE,
    N_AWAKE,
    NORMAL_Y,
    POINT_COUNT,
    REFERENCE,
    END_SEPARATION,
    SLOP,
)
from ..jit import inline_kernel, lean_kernel
from ..state import State
from .contact_math import approach_impulses, touching

NAME = "paper"
PARAMETERS = {"impulse_threshold": 1.0}
INT_PARAMETERS = ()
# body_real columns
HELD_Y, HELD_ANGLE, PIVOT_LX, PIVOT_LY, PIVOT_Y, SLIDE_MU, FLOOR_IMPACT = range(7)
REAL_COLUMNS = 7
# body_int columns: the body's floor-like support (-1 floor, -2 none), the floor-like manifold of
# this step (scratch), consecutive steps a VS body has touched an RS body, and that body
# (section 5.1), and the support a body slid off (figure 3; -2 none)
SUPPORT, FLOOR_MANIFOLD, RS_CONTACT_STEPS, RS_PARTNER, LEFT_SUPPORT = range(5)
INT_COLUMNS = 5

#: a contact normal within 1 degree of vertical counts as floor-parallel
COS_FLOOR = np.cos(np.radians(1.0))

_FREE = np.int8(State.FREE)
_VS = np.int8(State.VERTICAL_STABLE)
_RS = np.int8(State.ROTATION_STABLE)
_COM_OUTSIDE_SUPPORT = CAUSE["com_outside_support"]
_HELD_BY_CONTACT = CAUSE["held_by_contact"]
_IMPACT = CAUSE["impact"]
_ONE_VERTEX_ON_FLOOR = CAUSE["one_vertex_on_floor"]
_STOPPED_SLIDING = CAUSE["stopped_sliding"]
_TWO_VERTICES_ON_FLOOR = CAUSE["two_vertices_on_floor"]


def initial(activity, velocity, angular_velocity):
    """Per-body state of a new World: no support or floor manifold yet (the starting velocities
    play no part)."""
    body_int = activity.body_int
    body_int[:, SUPPORT] = -2
    body_int[:, FLOOR_MANIFOLD] = -1
    body_int[:, LEFT_SUPPORT] = -2


@inline_kernel
def _up_normal_on(i, c, manifold_int, manifold_float):
    """y component of manifold c's normal as it pushes on body i."""
    ny = manifold_float[c, NORMAL_Y]
    return ny if manifold_int[c, BODY_B] == i else -ny


@inline_kernel
def _floor_like_for(i, other, c, n_dyn, states, manifold_int, manifold_float):
    """Is ``other`` a floor-like surface under body i in manifold c?"""
    if _up_normal_on(i, c, manifold_int, manifold_float) < COS_FLOOR:
        return False
    if other < 0 or other >= n_dyn:
        return True  # the floor, or a static body's upward face
    return states[other] == _RS


@lean_kernel
def before_solve(settings, counters, bodies, contacts, activity):
    """Section 3: a moving body colliding with a held body (frozen, or RS and sliding) anywhere
    but its floor-parallel top edge makes it FREE before the solve. Returns the number woken."""
    inv_mass, inv_inertia = bodies.inv_mass, bodies.inv_inertia
    manifold_int = contacts.contact_int
    manifold_float = contacts.contact_float
    states, awake, awake_slot = activity.states, activity.awake, activity.awake_slot
    solver_inv_mass, solver_inv_inertia = activity.solver_inv_mass, activity.solver_inv_inertia
    events, body_real, body_int = activity.events, activity.body_real, activity.body_int
    n_dyn = settings.n_dynamic
    count = counters[N_ACTIVE]
    # Section 2's collision impulse of each moving body against its floor-like surfaces, judged
    # by after_solve: the impulse that stops its approach, from the velocities before gravity
    for k in range(counters[N_AWAKE]):
        body_real[awake[k], FLOOR_IMPACT] = 0.0
    for kk in range(count):
        c = contacts.active[kk]
        a = manifold_int[c, BODY_A]
        b = manifold_int[c, BODY_B]
        for i, other in ((b, a), (a, b)):
            if (
                0 <= i < n_dyn
                and awake_slot[i] >= 0
                and _floor_like_for(i, other, c, n_dyn, states, manifold_int, manifold_float)
            ):
                # CHOICE: only points the solve of this step stops collide in it (those that
                # reach the surface within the step and one substep more: contact_math.arrives;
                # a speculative point further away, made early for a fast body, does not), and
                # a two-point landing takes the impulse that stops both points at once (one
                # point at a time gave a square landing flat 0.8 m v, a 2 x 0.2 plank 0.5 m v)
                p0, p1, _, _ = approach_impulses(c, i, settings, bodies, contacts)
                body_real[i, FLOOR_IMPACT] += p0 + p1
    woken = 0
    for kk in range(count):
        c = contacts.active[kk]
        a = manifold_int[c, BODY_A]
        b = manifold_int[c, BODY_B]
        for held, mover in ((a, b), (b, a)):
            if not (
                0 <= held < n_dyn
                and solver_inv_mass[held] == 0.0
                and 0 <= mover < n_dyn
                and awake_slot[mover] >= 0
            ):
                continue
            if _floor_like_for(mover, held, c, n_dyn, states, manifold_int, manifold_float):
                continue  # landing on its top edge: it acts as the floor
            # a collision in the seed's sense (section 2): stopping the mover against the held
            # body would take more than the threshold impulse (estimated from the velocities
            # before gravity, so merely resting or sliding along it is not a collision)
            p0, p1, _, _ = approach_impulses(c, mover, settings, bodies, contacts)
            # CHOICE: a sliding RS mover is immovable to the solver as well, so nothing would
            # stop it short of the threshold: it slid through the held body (a 1 m box at
            # 0.5 m/s through a frozen one, max_penetration 0; the seed, section 3, gives a
            # collision with an RS body the ordinary processing). Between two immovable bodies
            # any approach is a collision
            both_held = solver_inv_mass[mover] == 0.0 and p0 + p1 > 0.0
            if p0 + p1 <= settings.impulse_threshold and not both_held:
                continue
            # both bodies of the collision end their rest: the held one wakes, and a sliding RS
            # mover (itself immovable to the solver) is released too
            for body in (held, mover):
                if states[body] == _FREE or (body == mover and states[body] != _RS):
                    continue  # (a VS mover stays VS: the seed's 2nd limit)
                wake(body, settings, counters, bodies, contacts, activity)
                solver_inv_mass[body] = inv_mass[body]  # also for an awake RS body
                solver_inv_inertia[body] = inv_inertia[body]
                record(events, counters, body, states[body], _FREE, _IMPACT)
                states[body] = _FREE
                body_int[body, SUPPORT] = -2
                body_int[body, RS_CONTACT_STEPS] = 0
                woken += 1
    return woken


@inline_kernel
def after_solve(settings, counters, bodies, contacts, activity):
    """Section 2's transitions after the solve. Inlined into the step loop, which allocates the
    work array; the walk runs in a lean kernel (no reference counting, see sim/jit)."""
    held_pairs = np.empty((counters[N_ACTIVE], 2), np.int64)
    _after_solve(settings, counters, bodies, contacts, activity, held_pairs)


@lean_kernel
def _after_solve(settings, counters, bodies, contacts, activity, held_pairs):
    position, angle, velocity, angular_velocity = (
        bodies.position,
        bodies.angle,
        bodies.velocity,
        bodies.angular_velocity,
    )
    inv_mass, inv_inertia = bodies.inv_mass, bodies.inv_inertia
    vert_start, local_verts = bodies.vert_start, bodies.local_verts
    manifold_int = contacts.contact_int
    manifold_float = contacts.contact_float
    point_float = contacts.point_float
    states, awake, awake_slot = activity.states, activity.awake, activity.awake_slot
    solver_inv_mass, solver_inv_inertia = activity.solver_inv_mass, activity.solver_inv_inertia
    events, body_real, body_int = activity.events, activity.body_real, activity.body_int
    n_dyn = settings.n_dynamic
    count = counters[N_ACTIVE]
    dt = settings.dt
    g = abs(settings.gravity_y)
    n_awake = counters[N_AWAKE]
    for k in range(n_awake):
        body_int[awake[k], FLOOR_MANIFOLD] = -1
        body_int[awake[k], RS_PARTNER] = -1
    # each moving or sliding body's floor-like manifold this step (the one with most points)
    # and lasting contact between VS and RS bodies (section 5.1)
    for kk in range(count):
        c = contacts.active[kk]
        if not touching(c, contacts):
            continue  # made ahead for a fast body that did not arrive
        a = manifold_int[c, BODY_A]
        b = manifold_int[c, BODY_B]
        for i, other in ((b, a), (a, b)):
            if not (0 <= i < n_dyn and awake_slot[i] >= 0):
                continue
            if (
                _floor_like_for(i, other, c, n_dyn, states, manifold_int, manifold_float)
                and other != body_int[i, LEFT_SUPPORT]
            ):
                best = body_int[i, FLOOR_MANIFOLD]
                if best < 0 or manifold_int[c, POINT_COUNT] > manifold_int[best, POINT_COUNT]:
                    body_int[i, FLOOR_MANIFOLD] = c
            if (
                states[i] == _VS
                and 0 <= other < n_dyn
                and states[other] == _RS
                and body_int[i, SUPPORT] != other
                and _in_contact(c, manifold_int, manifold_float, point_float)
            ):
                body_int[i, RS_PARTNER] = other
    for k in range(n_awake):
        i = awake[k]
        if body_int[i, RS_PARTNER] >= 0:
            body_int[i, RS_CONTACT_STEPS] += 1
        else:
            body_int[i, RS_CONTACT_STEPS] = 0
    n_held = 0
    k = 0
    while k < counters[N_AWAKE]:
        i = awake[k]
        k += 1
        c = body_int[i, FLOOR_MANIFOLD]
        state = states[i]
        if state == _RS:
            if _slide_or_stop(i, c, dt, g, settings, counters, bodies, contacts, activity, True):
                k -= 1  # the body left the awake list; its slot was refilled
            continue
        if c < 0:
            if state == _VS:
                _hold_pivot(
                    i, position, angle, velocity, angular_velocity, inv_mass, inv_inertia, body_real
                )
            continue
        # touching points of the floor-like contact: their world x, and the collision impulse
        lo = np.inf
        hi = -np.inf
        n_touch = 0
        b = manifold_int[c, BODY_B]
        for j in range(manifold_int[c, POINT_COUNT]):
            # CHOICE: a vertex touches when it ends the step within the pair's slop of the
            # surface, pressing or not (a corner that has just landed and swings the body round
            # lifts by a fraction of a millimetre for a step: it is still on the surface)
            if point_float[c, j, END_SEPARATION] <= manifold_float[c, SLOP]:
                x = point_float[c, j, ANCHOR_BX] + position[b, 0]
                lo = min(lo, x)
                hi = max(hi, x)
                n_touch += 1
        support = manifold_int[c, BODY_A] if b == i else b
        if state == _FREE:
            if n_touch == 0 or body_real[i, FLOOR_IMPACT] > settings.impulse_threshold:
                continue  # bouncing by its impulse: stays FREE
        com_x = position[i, 0]
        if n_touch >= 2 and lo <= com_x <= hi:
            # section 4.2: at rest on two or more vertices, centre of mass over the support. It
            # *stays in contact*: set it down on the surface (this step's solve may already have
            # started a bounce, or left it pressed in by up to the slop)
            for j in range(manifold_int[c, POINT_COUNT]):
                if point_float[c, j, END_SEPARATION] <= manifold_float[c, SLOP]:
                    surface = _surface_height(
                        c, j, i, position, angle, manifold_int, manifold_float, point_float
                    )
            cs = np.cos(angle[i])
            sn = np.sin(angle[i])
            lowest = np.inf
            for v in range(vert_start[i], vert_start[i + 1]):
                lowest = min(lowest, sn * local_verts[v, 0] + cs * local_verts[v, 1])
            position[i, 1] = surface - lowest
            body_real[i, HELD_Y] = position[i, 1]
            body_real[i, HELD_ANGLE] = angle[i]
            body_real[i, SLIDE_MU] = manifold_float[c, FRICTION]
            body_int[i, SUPPORT] = support if support >= 0 else -1
            velocity[i, 1] = 0.0
            angular_velocity[i] = 0.0
            solver_inv_mass[i] = 0.0  # immovable to others from now on
            solver_inv_inertia[i] = 0.0
            record(events, counters, i, state, _RS, _TWO_VERTICES_ON_FLOOR)
            states[i] = _RS
            body_int[i, LEFT_SUPPORT] = -2
            if _slide_or_stop(i, c, dt, g, settings, counters, bodies, contacts, activity, False):
                k -= 1
            continue
        if n_touch >= 1:
            # section 4.1 (one vertex), or 4.2 with the centre of mass outside the support: pivot
            # on the touching vertex on the centre of mass's side, and keep rotating
            # (a VS body keeps its pivot, and the pivot its height, until another vertex lands
            # and the centre of mass is outside them: then it pivots on the new outer vertex)
            # CHOICE: only a vertex of the body pivots (section 4.1: the body on one of its
            # vertices). A point on its face over the support's corner is no pivot: holding the
            # body's vertex nearest it hung a box tipping off an edge by its far corner, in mid
            # air. A FREE body so touching stays FREE (the solve tips it); a VS one keeps its pivot.
            pivoted = False
            if state == _FREE or n_touch >= 2:
                pivot_x = hi if com_x > hi else lo
                for j in range(manifold_int[c, POINT_COUNT]):
                    x = point_float[c, j, ANCHOR_BX] + position[b, 0]
                    # only a vertex of i is a pivot: the manifold's points are vertices of its
                    # incident body, so i's when the support holds the reference face
                    if x == pivot_x and manifold_int[c, INCIDENT] == i:
                        _set_pivot(
                            i,
                            point_float[c, j, LOCAL_X],
                            point_float[c, j, LOCAL_Y],
                            position,
                            angle,
                            vert_start,
                            local_verts,
                            body_real,
                        )
                        pivoted = True
                        body_real[i, PIVOT_Y] = _surface_height(
                            c, j, i, position, angle, manifold_int, manifold_float, point_float
                        )
            if state == _FREE and pivoted:
                record(events, counters, i, state, _VS, _ONE_VERTEX_ON_FLOOR)
                states[i] = _VS
                body_int[i, LEFT_SUPPORT] = -2
                body_int[i, SUPPORT] = support if support >= 0 else -1
        if states[i] == _VS:
            _hold_pivot(
                i, position, angle, velocity, angular_velocity, inv_mass, inv_inertia, body_real
            )
            if body_int[i, RS_CONTACT_STEPS] >= 2 and n_held < count:
                held_pairs[n_held, 0] = i
                n_held += 1
    # section 5.1: VS in lasting contact with RS: both held at rest
    for h in range(n_held):
        i = held_pairs[h, 0]
        partner = body_int[i, RS_PARTNER]
        for body in (i, partner):
            if awake_slot[body] >= 0:
                freeze(body, settings, counters, bodies, contacts, activity)
                record(events, counters, body, states[body], states[body], _HELD_BY_CONTACT)
        body_int[i, RS_CONTACT_STEPS] = 0


@inline_kernel
def _in_contact(c, manifold_int, manifold_float, point_float):
    """Does contact c touch: a point within the pair's slop at the end of the step (the rule a
    vertex touches by, section 4), not merely within the speculative reach (``touching``)?"""
    for j in range(manifold_int[c, POINT_COUNT]):
        if point_float[c, j, END_SEPARATION] <= manifold_float[c, SLOP]:
            return True
    return False


@inline_kernel
def _surface_height(c, j, i, position, angle, manifold_int, manifold_float, point_float):
    """Height of the floor-like surface under point j of manifold c: the pivot stays *on* it
    (the vertex may have ended the step a little above or below it)."""
    ref = manifold_int[c, REFERENCE]
    if ref < 0:
        return manifold_float[c, LOCAL_FACE_Y]  # the floor
    if ref != i:  # the support's face: horizontal
        cs = np.cos(angle[ref])
        sn = np.sin(angle[ref])
        return (
            sn * manifold_float[c, LOCAL_FACE_X]
            + cs * manifold_float[c, LOCAL_FACE_Y]
            + position[ref, 1]
        )
    # i holds the reference face; the support's vertex is the incident point
    inc = manifold_int[c, INCIDENT]
    cs = np.cos(angle[inc])
    sn = np.sin(angle[inc])
    return sn * point_float[c, j, LOCAL_X] + cs * point_float[c, j, LOCAL_Y] + position[inc, 1]


@inline_kernel
def _set_pivot(i, lx, ly, position, angle, vert_start, local_verts, body_real):
    """Pivot on body i's vertex nearest to (lx, ly) in its frame (m): the vertex's body-frame
    position and its current height, which it keeps while the body is VS."""
    cs = np.cos(angle[i])
    sn = np.sin(angle[i])
    best = vert_start[i]
    nearest = np.inf
    for v in range(vert_start[i], vert_start[i + 1]):
        d = (local_verts[v, 0] - lx) ** 2 + (local_verts[v, 1] - ly) ** 2
        if d < nearest:
            nearest = d
            best = v
    body_real[i, PIVOT_LX] = local_verts[best, 0]
    body_real[i, PIVOT_LY] = local_verts[best, 1]
    body_real[i, PIVOT_Y] = position[i, 1] + sn * local_verts[best, 0] + cs * local_verts[best, 1]


@inline_kernel
def _hold_pivot(i, position, angle, velocity, angular_velocity, inv_mass, inv_inertia, body_real):
    """VS: the pivot vertex does not move vertically. One exact vertical impulse at the vertex
    zeroes its vertical velocity; a vertical translation puts it back at its height."""
    cs = np.cos(angle[i])
    sn = np.sin(angle[i])
    lx = body_real[i, PIVOT_LX]
    ly = body_real[i, PIVOT_LY]
    rx = cs * lx - sn * ly
    ry = sn * lx + cs * ly
    vy = velocity[i, 1] + angular_velocity[i] * rx  # the vertex's vertical velocity
    k = inv_mass[i] + inv_inertia[i] * rx * rx
    p = -vy / k
    velocity[i, 1] += inv_mass[i] * p
    angular_velocity[i] += inv_inertia[i] * rx * p
    position[i, 1] += body_real[i, PIVOT_Y] - (position[i, 1] + ry)


@inline_kernel
def _slide_or_stop(i, c, dt, g, settings, counters, bodies, contacts, activity, slowed_here):
    """RS: hold the pose's rotation and height, slow the horizontal motion by Coulomb friction,
    freeze the body when it stops, free it when its centre of mass leaves its support (figure 3).
    ``slowed_here``: friction is applied here (the body was RS, immovable to the solver, during
    the step); not in the step a body becomes RS, which the solver solved with friction.
    Returns True when the body left the awake list."""
    position, angle, velocity, angular_velocity = (
        bodies.position,
        bodies.angle,
        bodies.velocity,
        bodies.angular_velocity,
    )
    manifold_int = contacts.contact_int
    point_float = contacts.point_float
    body_real, body_int, states = activity.body_real, activity.body_int, activity.states
    events = activity.events
    position[i, 1] = body_real[i, HELD_Y]
    angle[i] = body_real[i, HELD_ANGLE]
    velocity[i, 1] = 0.0
    angular_velocity[i] = 0.0
    support = body_int[i, SUPPORT]
    if support >= 0:
        # resting on another body: is any of their contact points under the centre of mass?
        lo = np.inf
        hi = -np.inf
        if c >= 0:
            b = manifold_int[c, BODY_B]
            for j in range(manifold_int[c, POINT_COUNT]):
                x = point_float[c, j, ANCHOR_BX] + position[b, 0]
                lo = min(lo, x)
                hi = max(hi, x)
        if not (lo <= position[i, 0] <= hi):
            activity.solver_inv_mass[i] = bodies.inv_mass[i]
            activity.solver_inv_inertia[i] = bodies.inv_inertia[i]
            record(events, counters, i, _RS, _FREE, _COM_OUTSIDE_SUPPORT)
            states[i] = _FREE
            body_int[i, LEFT_SUPPORT] = support  # it tips off that edge, not onto it
            body_int[i, SUPPORT] = -2
            return False
    # Coulomb friction as the solver applies it, substep by substep: this step the solver moved
    # the body at its speed u (it is immovable to the solver), while friction would have slowed
    # it by mu g h in each of the substeps: take back the difference, so that a sliding RS body
    # goes exactly as far as the same body under `off`
    n_sub = settings.substeps
    h = dt / n_sub
    a = body_real[i, SLIDE_MU] * g * h
    vx = velocity[i, 0]
    speed = abs(vx)
    dv = a * n_sub
    if not slowed_here:
        # the solver slowed it this step: it stops now if one more step of friction would
        if speed > dv:
            return False
        velocity[i, 0] = 0.0
        speed = 0.0
    travelled = 0.0
    for j in range(1, n_sub + 1):
        travelled += h * max(speed - j * a, 0.0)
    position[i, 0] += (travelled - dt * speed) if vx > 0 else (dt * speed - travelled)
    if speed > dv:
        velocity[i, 0] = vx - dv if vx > 0 else vx + dv
        return False
    velocity[i, 0] = 0.0
    freeze(i, settings, counters, bodies, contacts, activity)
    record(events, counters, i, _RS, _RS, _STOPPED_SLIDING)
    return True
