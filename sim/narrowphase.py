"""The narrowphase: every awake contact's manifold (0-2 points) at the current poses, in place.

Split from ``contacts.py`` by job, as Box2D v3 keeps its manifold functions apart from its contact
bookkeeping: ``contacts.py`` makes, links, frees and orders the slots (which pairs are looked
at); this module only computes what a looked-at pair touches (the points, their anchors and
separations, the impulses carried over by feature id), and touches no list. The step calls
``update_manifolds`` once per step, after the broadphase.

A pair that has hardly moved relative to itself since its last full narrowphase is refreshed from
its stored material points (``REFRESH_FRACTION``), and a pair that was apart is skipped while its
last separating-axis gap, less how far it has since moved, exceeds its margin (ARCHITECTURE
§2.2). Columns are named in ``sim.data``; a pair (a, b) has a < b, a = -1 is the floor, and the
normal points from A to B.
"""

import numpy as np

from .data import (
    ALIVE,
    ANCHOR_AX,
    ANCHOR_AY,
    ANCHOR_BX,
    ANCHOR_BY,
    BODY_A,
    BODY_B,
    CARRIED,
    FIT_C,
    FIT_GAP,
    FIT_MARGIN,
    FIT_S,
    FIT_X,
    FIT_Y,
    FRICTION,
    INCIDENT,
    LOCAL_FACE_X,
    LOCAL_FACE_Y,
    LOCAL_NORMAL_X,
    LOCAL_NORMAL_Y,
    LOCAL_X,
    LOCAL_Y,
    NORMAL_IMPULSE,
    NORMAL_VELOCITY,
    NORMAL_X,
    NORMAL_Y,
    N_ACTIVE,
    N_AWAKE_CONTACTS,
    N_REFRESHED,
    N_SKIPPED,
    POINT_COUNT,
    REFERENCE,
    RESTITUTION,
    SEPARATION,
    SLOP,
    SPECULATIVE,
    TANGENT_IMPULSE,
    WARM_NORMAL,
    WARM_TANGENT,
)
from .geometry import collide_floor_rows, collide_polygon_rows
from .jit import inline_kernel, lean_kernel
from .tolerances import FACE_FRACTION, turn_reach


@inline_kernel
def _closing_reach(a, b, velocity, angular_velocity, extent, dt):
    """m: a bound on how far any point of a can approach any point of b (a = -1: the floor)
    within the step of dt s, whatever else the step does to either: the sum of their speeds times
    dt, not the speed of one relative to the other, plus how far each one's turn can carry a
    point (``tolerances.turn_reach``). Two bodies falling side by side or one behind the other
    do not close at all until the one ahead is stopped, in the middle of the step, by what it
    lands on; a margin from their relative speed then had no contact between them, and a box of a
    pile dropped from 35 m flew on at 26 m/s 5 cm into the one below it, stopped under it."""
    speed = np.sqrt(velocity[b, 0] ** 2 + velocity[b, 1] ** 2)
    reach = turn_reach(angular_velocity[b], extent[b], dt)
    if a >= 0:
        speed += np.sqrt(velocity[a, 0] ** 2 + velocity[a, 1] ** 2)
        reach += turn_reach(angular_velocity[a], extent[a], dt)
    return speed * dt + reach


#: A manifold is refreshed from its stored points, without the separating-axis search and the
#: clipping, while the pair's relative pose has moved less than this fraction of the pair's slop
#: (and its rotation less than that at the bodies' extents) since the last full narrowphase: a
#: resting pile's contacts then cost a few multiplications each. The stored points are material
#: points of the incident body, so a refreshed manifold is the full one up to how far a clipped
#: point slides along its edge: at most this fraction of the slop.
REFRESH_FRACTION = 0.1
#: cos of the largest turn of a pair's normal over which a point whose feature id changed still
#: takes over the impulses of an old point in its place (``_match``): 8 degrees
MATCH_TURN = np.cos(np.radians(8.0))


@inline_kernel
def _moved(x, y, c, sn, s, cf, extent_b):
    """m: how far any point of B can have moved in A's frame since the pair's last full
    narrowphase, given B's relative pose now (x, y, c, sn): the translation plus the chord of the
    turn at B's extent (2 |sin(turn / 2)| = sqrt(2 - 2 cos(turn)))."""
    dx = x - cf[s, FIT_X]
    dy = y - cf[s, FIT_Y]
    cos_turn = c * cf[s, FIT_C] + sn * cf[s, FIT_S]
    return np.sqrt(dx * dx + dy * dy) + np.sqrt(max(0.0, 2.0 - 2.0 * cos_turn)) * extent_b


@inline_kernel
def _relative_pose(a, b, position, rotation):
    """B's pose in A's frame (x, y m, cos, sin); the floor's frame is the world's."""
    if a < 0:
        return position[b, 0], position[b, 1], rotation[b, 0], rotation[b, 1]
    ca = rotation[a, 0]
    sa = rotation[a, 1]
    dx = position[b, 0] - position[a, 0]
    dy = position[b, 1] - position[a, 1]
    cb = rotation[b, 0]
    sb = rotation[b, 1]
    return ca * dx + sa * dy, -sa * dx + ca * dy, ca * cb + sa * sb, ca * sb - sa * cb


@lean_kernel
def update_manifolds(settings, bodies, geometry, contacts, counters):
    """The manifold of every awake contact at the current poses (world vertices in ``geometry``
    up to date for every body involved); those with points are listed in ``contacts.active``.
    The speculative margin is the pair's resting reach plus the distance the pair can close in
    one step, so a contact exists before bodies meet however fast they move. A pair that has
    hardly moved relative to itself is refreshed, not recomputed (REFRESH_FRACTION); a pair that
    was apart is skipped while its last separating-axis gap, less how far B has since moved in A's
    frame, still exceeds the margin: the shapes are then surely farther apart than the margin, so
    the full narrowphase would find no point that could touch this step (in a settling pile of 200
    polygons about a third of the live pairs are apart). Returns the number of active contacts."""
    ci = contacts.contact_int
    cf = contacts.contact_float
    dt = settings.dt
    n_active = 0
    refreshed = 0
    skipped = 0
    for k in range(counters[N_AWAKE_CONTACTS]):
        s = contacts.awake[k]
        a = ci[s, BODY_A]
        b = ci[s, BODY_B]
        margin = cf[s, SPECULATIVE] + _closing_reach(
            a, b, bodies.velocity, bodies.angular_velocity, bodies.extent, dt
        )
        x, y, c, sn = _relative_pose(a, b, bodies.position, geometry.rotation)
        tol = REFRESH_FRACTION * cf[s, SLOP]
        reach = bodies.extent[b] + (bodies.extent[a] if a >= 0 else 0.0)
        turned = abs(sn * cf[s, FIT_C] - c * cf[s, FIT_S]) * reach  # |sin of the turn| * r
        if ci[s, ALIVE] == 2 and ci[s, POINT_COUNT] == 0:
            if cf[s, FIT_GAP] - _moved(x, y, c, sn, s, cf, bodies.extent[b]) > margin:
                skipped += 1
                continue
        if (
            ci[s, ALIVE] == 2
            and margin <= cf[s, FIT_MARGIN] + tol
            and turned < tol
            and abs(x - cf[s, FIT_X]) + abs(y - cf[s, FIT_Y]) < tol
        ):
            n = _refresh(s, settings, bodies, geometry, contacts)
            refreshed += 1
        else:
            n = _collide(s, margin, settings, bodies, geometry, contacts)
            cf[s, FIT_X] = x
            cf[s, FIT_Y] = y
            cf[s, FIT_C] = c
            cf[s, FIT_S] = sn
            cf[s, FIT_MARGIN] = margin
            ci[s, ALIVE] = 2  # has a full narrowphase to refresh from
        if n > 0:
            contacts.active[n_active] = s
            n_active += 1
    counters[N_ACTIVE] = n_active
    counters[N_REFRESHED] = refreshed
    counters[N_SKIPPED] = skipped
    return n_active


@inline_kernel
def _refresh(s, settings, bodies, geometry, contacts):
    """Contact s's points at the current poses from its stored features: each point is a
    material point of the incident body (LOCAL_X/Y), measured against the reference face
    (LOCAL_FACE, LOCAL_NORMAL in the reference body's frame; the floor's in the world). Impulses
    stay with their points. Returns the point count."""
    ci = contacts.contact_int
    cf = contacts.contact_float
    pf = contacts.point_float
    n_points = ci[s, POINT_COUNT]
    if n_points == 0:
        return 0
    position = bodies.position
    rotation = geometry.rotation
    a = ci[s, BODY_A]
    b = ci[s, BODY_B]
    ref = ci[s, REFERENCE]
    inc = ci[s, INCIDENT]
    lnx = cf[s, LOCAL_NORMAL_X]
    lny = cf[s, LOCAL_NORMAL_Y]
    lfx = cf[s, LOCAL_FACE_X]
    lfy = cf[s, LOCAL_FACE_Y]
    if ref >= 0:
        cr = rotation[ref, 0]
        sr = rotation[ref, 1]
        nx = cr * lnx - sr * lny
        ny = sr * lnx + cr * lny
        fx = cr * lfx - sr * lfy + position[ref, 0]
        fy = sr * lfx + cr * lfy + position[ref, 1]
    else:  # the floor: the world frame
        nx = lnx
        ny = lny
        fx = lfx
        fy = lfy
    cf[s, NORMAL_X] = nx if ref == a else -nx  # the normal points from A to B
    cf[s, NORMAL_Y] = ny if ref == a else -ny
    ci_ = rotation[inc, 0]
    si_ = rotation[inc, 1]
    for j in range(n_points):
        lx = pf[s, j, LOCAL_X]
        ly = pf[s, j, LOCAL_Y]
        ix = ci_ * lx - si_ * ly + position[inc, 0]
        iy = si_ * lx + ci_ * ly + position[inc, 1]
        sep = (ix - fx) * nx + (iy - fy) * ny
        _anchor(s, j, a, b, ref, ix, iy, sep, nx, ny, position, pf)
        pf[s, j, NORMAL_IMPULSE] = 0.0
        pf[s, j, TANGENT_IMPULSE] = 0.0
        pf[s, j, NORMAL_VELOCITY] = 0.0
    return n_points


@inline_kernel
def _anchor(s, j, a, b, ref, ix, iy, sep, ref_nx, ref_ny, position, pf):
    """Point j's anchors and separation, from the incident point (ix, iy) at ``sep`` from the
    reference face (normal ref_nx, ref_ny).

    Each body's anchor sits on its own surface: the incident point, and its projection on the
    reference face. (Halfway between the surfaces, as Box2D does, puts the anchor of a contact
    made ahead of a fast body far outside both bodies: its impulses then turn them about a point
    in the air.)"""
    rx = ix - sep * ref_nx
    ry = iy - sep * ref_ny
    if ref == a:
        ax_ = rx
        ay_ = ry
        bx_ = ix
        by_ = iy
    else:
        ax_ = ix
        ay_ = iy
        bx_ = rx
        by_ = ry
    if a >= 0:
        pf[s, j, ANCHOR_AX] = ax_ - position[a, 0]
        pf[s, j, ANCHOR_AY] = ay_ - position[a, 1]
    else:
        pf[s, j, ANCHOR_AX] = 0.0
        pf[s, j, ANCHOR_AY] = 0.0
    pf[s, j, ANCHOR_BX] = bx_ - position[b, 0]
    pf[s, j, ANCHOR_BY] = by_ - position[b, 1]
    pf[s, j, SEPARATION] = sep


@inline_kernel
def _nearest(bx, by, n_old, bx0, by0, bx1, by1, free0, free1, tol):
    """The free old point (0, 1) whose anchor on B lies within ``tol`` of (bx, by), the nearer if
    both do; -1 if none."""
    d0 = np.hypot(bx - bx0, by - by0) if free0 else np.inf
    d1 = np.hypot(bx - bx1, by - by1) if (free1 and n_old > 1) else np.inf
    if d0 <= d1 and d0 <= tol:
        return 0
    if d1 < d0 and d1 <= tol:
        return 1
    return -1


@inline_kernel
def _match(n_old, id0, id1, bx0, by0, bx1, by1, turn_cos, n_new, ids, nbx0, nby0, nbx1, nby1, tol):
    """Which of last step's points (0, 1; -1: none) each new point takes its impulses from.

    By feature id first, as Box2D does. A point whose id is new takes those of an unclaimed old
    point still in the same place (its anchor on B within the pair's slop ``tol``), if the
    normal has turned by less than MATCH_TURN: the ids change when the other body's face becomes
    the reference face, which a resting pair with two nearly parallel faces does whenever its
    full narrowphase runs again, and a point restarted cold there lost its load and its friction
    at once (a sliver wedged between two heavy polygons in a pile was kicked to 16 mm/s: Bullet
    matches its manifold points by distance for the same reason)."""
    m0 = -1
    m1 = -1
    if ids[0] == id0:
        m0 = 0
    elif n_old > 1 and ids[0] == id1:
        m0 = 1
    if n_new > 1:
        if ids[1] == id0 and m0 != 0:
            m1 = 0
        elif n_old > 1 and ids[1] == id1 and m0 != 1:
            m1 = 1
    if turn_cos < MATCH_TURN:
        return m0, m1
    if m0 < 0:
        m0 = _nearest(nbx0, nby0, n_old, bx0, by0, bx1, by1, m1 != 0, m1 != 1, tol)
    if n_new > 1 and m1 < 0:
        m1 = _nearest(nbx1, nby1, n_old, bx0, by0, bx1, by1, m0 != 0, m0 != 1, tol)
    return m0, m1


@inline_kernel
def _collide(s, margin, settings, bodies, geometry, contacts):
    """Contact s's manifold from scratch: separating axes and clipping (``geometry``), impulses
    carried over from last step's points by feature id. Returns the point count."""
    ci = contacts.contact_int
    cf = contacts.contact_float
    pf = contacts.point_float
    points = contacts.scratch_points
    seps = contacts.scratch_separations
    ids = contacts.scratch_ids
    normal = contacts.scratch_normal
    position = bodies.position
    vert_start = bodies.vert_start
    world_verts = geometry.world_verts
    world_normals = geometry.world_normals
    rotation = geometry.rotation
    a = ci[s, BODY_A]
    b = ci[s, BODY_B]
    vb0 = vert_start[b]
    vb1 = vert_start[b + 1]
    if a < 0:
        n_points, gap = collide_floor_rows(
            world_verts, world_normals, vb0, vb1, settings.floor_y, margin, points, seps, ids
        )
        flip = 0
        edge = 0
        normal[0] = 0.0
        normal[1] = 1.0
        mu = np.sqrt(settings.floor_friction * bodies.friction[b])
        e = max(settings.floor_restitution, bodies.restitution[b])
    else:
        n_points, flip, edge, gap = collide_polygon_rows(
            world_verts,
            world_normals,
            vert_start[a],
            vert_start[a + 1],
            vb0,
            vb1,
            margin,
            FACE_FRACTION * cf[s, SLOP],
            points,
            seps,
            ids,
            normal,
        )
        mu = np.sqrt(bodies.friction[a] * bodies.friction[b])
        e = max(bodies.restitution[a], bodies.restitution[b])
    # last step's points, to carry their impulses over (``_match``)
    n_old = ci[s, POINT_COUNT]
    old_id0 = contacts.point_id[s, 0]
    old_id1 = contacts.point_id[s, 1]
    old_n0 = pf[s, 0, WARM_NORMAL]
    old_t0 = pf[s, 0, WARM_TANGENT]
    old_n1 = pf[s, 1, WARM_NORMAL]
    old_t1 = pf[s, 1, WARM_TANGENT]
    old_c0 = pf[s, 0, CARRIED]
    old_c1 = pf[s, 1, CARRIED]
    old_bx0 = pf[s, 0, ANCHOR_BX]
    old_by0 = pf[s, 0, ANCHOR_BY]
    old_bx1 = pf[s, 1, ANCHOR_BX]
    old_by1 = pf[s, 1, ANCHOR_BY]
    old_nx = cf[s, NORMAL_X]
    old_ny = cf[s, NORMAL_Y]
    ci[s, POINT_COUNT] = n_points
    cf[s, FIT_GAP] = gap
    if n_points == 0:
        contacts.point_id[s, 0] = -1  # apart: nothing to warm start from
        contacts.point_id[s, 1] = -1
        return 0
    cf[s, NORMAL_X] = normal[0]
    cf[s, NORMAL_Y] = normal[1]
    cf[s, FRICTION] = mu
    cf[s, RESTITUTION] = e
    if a < 0:
        ref = -1
        inc = b
        cf[s, LOCAL_NORMAL_X] = 0.0
        cf[s, LOCAL_NORMAL_Y] = 1.0
        cf[s, LOCAL_FACE_X] = 0.0
        cf[s, LOCAL_FACE_Y] = settings.floor_y
        ref_nx = 0.0
        ref_ny = 1.0
    elif edge < 0:
        # corners apart (geometry._closest_points): A is the reference, its feature the plane
        # through its closest point, normal to the line between the closest points; kept in A's
        # frame like a face, so that a refresh measures the point against the turned plane
        ref = a
        inc = b
        ref_nx = normal[0]
        ref_ny = normal[1]
        fx = points[0, 0] - seps[0] * ref_nx - position[a, 0]
        fy = points[0, 1] - seps[0] * ref_ny - position[a, 1]
        ca = rotation[a, 0]
        sa = rotation[a, 1]
        cf[s, LOCAL_NORMAL_X] = ca * ref_nx + sa * ref_ny  # R^T n
        cf[s, LOCAL_NORMAL_Y] = -sa * ref_nx + ca * ref_ny
        cf[s, LOCAL_FACE_X] = ca * fx + sa * fy
        cf[s, LOCAL_FACE_Y] = -sa * fx + ca * fy
    else:
        if flip == 1:
            ref = b
            inc = a
        else:
            ref = a
            inc = b
        r = vert_start[ref] + edge
        cf[s, LOCAL_NORMAL_X] = bodies.local_normals[r, 0]
        cf[s, LOCAL_NORMAL_Y] = bodies.local_normals[r, 1]
        cf[s, LOCAL_FACE_X] = bodies.local_verts[r, 0]
        cf[s, LOCAL_FACE_Y] = bodies.local_verts[r, 1]
        ref_nx = world_normals[r, 0]
        ref_ny = world_normals[r, 1]
    ci[s, REFERENCE] = ref
    ci[s, INCIDENT] = inc
    ci_ = rotation[inc, 0]
    si_ = rotation[inc, 1]
    for j in range(n_points):
        _anchor(s, j, a, b, ref, points[j, 0], points[j, 1], seps[j], ref_nx, ref_ny, position, pf)
        dx = points[j, 0] - position[inc, 0]
        dy = points[j, 1] - position[inc, 1]
        pf[s, j, LOCAL_X] = ci_ * dx + si_ * dy  # R^T (p - x)
        pf[s, j, LOCAL_Y] = -si_ * dx + ci_ * dy
        pf[s, j, NORMAL_IMPULSE] = 0.0
        pf[s, j, TANGENT_IMPULSE] = 0.0
        pf[s, j, NORMAL_VELOCITY] = 0.0
        contacts.point_id[s, j] = ids[j]
    m0 = -1
    m1 = -1
    if settings.warm_starting and n_old > 0:
        m0, m1 = _match(
            n_old,
            old_id0,
            old_id1,
            old_bx0,
            old_by0,
            old_bx1,
            old_by1,
            old_nx * normal[0] + old_ny * normal[1],
            n_points,
            ids,
            pf[s, 0, ANCHOR_BX],
            pf[s, 0, ANCHOR_BY],
            pf[s, 1, ANCHOR_BX],
            pf[s, 1, ANCHOR_BY],
            cf[s, SLOP],
        )
    for j in range(n_points):
        m = m0 if j == 0 else m1
        pf[s, j, WARM_NORMAL] = old_n0 if m == 0 else (old_n1 if m == 1 else 0.0)
        pf[s, j, WARM_TANGENT] = old_t0 if m == 0 else (old_t1 if m == 1 else 0.0)
        pf[s, j, CARRIED] = old_c0 if m == 0 else (old_c1 if m == 1 else 0.0)
    return n_points
