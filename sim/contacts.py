"""The persistent contact store and the narrowphase that updates it in place.

A contact slot is made when two bodies' fat boxes start to overlap (``broadphase``) and freed when
they stop: in between, every step either body is awake, its manifold (0-2 points) is recomputed
from the current poses, and impulses carry over from the last step's points with the same feature
id (warm starting). Nothing is allocated in the step loop: slots come from a free list, and a full
store makes the step return GROW before anything has changed (the World grows it and retries).

Which contacts are looked at is data, not a test in every loop (as sleeping is in Box2D v3):
``contacts.awake`` lists the slots with at least one awake body. Freezing a body moves its contacts
whose other body cannot move out of that list (``sleep_contacts_of``), waking moves them back
(``wake_contacts_of``); each dynamic body's contacts form a doubly linked list through the slots,
so both cost the body's own contact count. Contacts between resting bodies cost nothing.

Columns are named in ``sim.data`` (BODY_A, NORMAL_X, NORMAL_IMPULSE...). A pair (a, b) has a < b;
a = -1 is the floor; the normal points from A to B.
"""

import numpy as np

from .data import (
    N_SKIPPED,
    ALIVE,
    FIT_C,
    FIT_GAP,
    FIT_MARGIN,
    FIT_S,
    FIT_X,
    FIT_Y,
    N_REFRESHED,
    ANCHOR_AX,
    AWAKE_UNSORTED,
    CARRIED,
    ANCHOR_AY,
    ANCHOR_BX,
    ANCHOR_BY,
    AWAKE_INDEX,
    BODY_A,
    BODY_B,
    FREE_HEAD,
    FRICTION,
    GROW_CONTACTS,
    GROW_NEEDED,
    INCIDENT,
    LOCAL_FACE_X,
    LOCAL_FACE_Y,
    LOCAL_NORMAL_X,
    LOCAL_NORMAL_Y,
    LOCAL_X,
    LOCAL_Y,
    MAX_DEGREE,
    N_ACTIVE,
    N_AWAKE_CONTACTS,
    N_LIVE,
    N_SLOTS,
    NEXT_A,
    NEXT_B,
    NORMAL_IMPULSE,
    NORMAL_VELOCITY,
    NORMAL_X,
    NORMAL_Y,
    POINT_COUNT,
    PREV_A,
    PREV_B,
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
from .jit import inline_kernel, kernel, lean_kernel
from .tolerances import FACE_FRACTION


# ---- the per-body lists -------------------------------------------------------------------------
@inline_kernel
def _next_of(i, s, contact_int):
    """The slot after s in body i's list."""
    return contact_int[s, NEXT_A] if contact_int[s, BODY_A] == i else contact_int[s, NEXT_B]


@inline_kernel
def _set_link(i, s, column_a, column_b, value, contact_int):
    """Set s's NEXT or PREV field on body i's side (column_a when i is BODY_A, else column_b)."""
    if contact_int[s, BODY_A] == i:
        contact_int[s, column_a] = value
    else:
        contact_int[s, column_b] = value


@inline_kernel
def _link(i, s, contacts):
    """Put slot s at the head of dynamic body i's list."""
    ci = contacts.contact_int
    h = contacts.head[i]
    _set_link(i, s, NEXT_A, NEXT_B, h, ci)
    _set_link(i, s, PREV_A, PREV_B, -1, ci)
    if h >= 0:
        _set_link(i, h, PREV_A, PREV_B, s, ci)
    contacts.head[i] = s
    contacts.degree[i] += 1


@inline_kernel
def _unlink(i, s, contacts):
    ci = contacts.contact_int
    if ci[s, BODY_A] == i:
        nxt = ci[s, NEXT_A]
        prv = ci[s, PREV_A]
    else:
        nxt = ci[s, NEXT_B]
        prv = ci[s, PREV_B]
    if prv >= 0:
        _set_link(i, prv, NEXT_A, NEXT_B, nxt, ci)
    else:
        contacts.head[i] = nxt
    if nxt >= 0:
        _set_link(i, nxt, PREV_A, PREV_B, prv, ci)
    contacts.degree[i] -= 1


@inline_kernel
def find(a, b, n_dynamic, contacts):
    """The slot of pair (a, b) (a < b, a = -1 the floor), or -1: a walk of the shorter list."""
    ci = contacts.contact_int
    i = b
    if 0 <= a < n_dynamic and (b >= n_dynamic or contacts.degree[a] < contacts.degree[b]):
        i = a
    if i >= n_dynamic:
        return -1
    s = contacts.head[i]
    while s >= 0:
        if ci[s, BODY_A] == a and ci[s, BODY_B] == b:
            return s
        s = _next_of(i, s, ci)
    return -1


# ---- the awake list -----------------------------------------------------------------------------
@inline_kernel
def _add_awake(s, contacts, counters):
    ci = contacts.contact_int
    if ci[s, AWAKE_INDEX] >= 0:
        return
    k = counters[N_AWAKE_CONTACTS]
    contacts.awake[k] = s
    ci[s, AWAKE_INDEX] = k
    counters[N_AWAKE_CONTACTS] = k + 1
    counters[AWAKE_UNSORTED] += 1


@inline_kernel
def _remove_awake(s, contacts, counters):
    """Swap-remove slot s from the awake list."""
    ci = contacts.contact_int
    k = ci[s, AWAKE_INDEX]
    if k < 0:
        return
    last = counters[N_AWAKE_CONTACTS] - 1
    moved = contacts.awake[last]
    contacts.awake[k] = moved
    ci[moved, AWAKE_INDEX] = k
    ci[s, AWAKE_INDEX] = -1
    counters[N_AWAKE_CONTACTS] = last
    if k != last:
        counters[AWAKE_UNSORTED] += 1


@inline_kernel
def _is_awake(i, n_dynamic, awake_slot):
    return 0 <= i < n_dynamic and awake_slot[i] >= 0


@inline_kernel
def wake_contacts_of(i, contacts, counters):
    """Body i has woken: every contact of its list is awake now."""
    ci = contacts.contact_int
    s = contacts.head[i]
    while s >= 0:
        _add_awake(s, contacts, counters)
        s = _next_of(i, s, ci)


@inline_kernel
def sleep_contacts_of(i, n_dynamic, awake_slot, contacts, counters):
    """Body i has frozen: its contacts whose other body cannot move either leave the awake list
    (with their manifold and impulses kept, to warm start the pair if it wakes)."""
    ci = contacts.contact_int
    s = contacts.head[i]
    while s >= 0:
        other = ci[s, BODY_A] if ci[s, BODY_B] == i else ci[s, BODY_B]
        if not _is_awake(other, n_dynamic, awake_slot):
            _remove_awake(s, contacts, counters)
        s = _next_of(i, s, ci)


@inline_kernel
def _key(s, contact_int, stride):
    """The pair's order: floor pairs first, then by the lower body, then the higher."""
    return (contact_int[s, BODY_A] + 1) * stride + contact_int[s, BODY_B]


@kernel
def sort_awake(n_bodies, contacts, counters):
    """Put the awake contacts back in pair order, if any was added or removed since the last sort.

    The solver's result depends on the order it meets contacts in (Gauss-Seidel, colouring), and
    that order must not depend on history: a stack frozen and woken by an impact must be solved
    exactly as the same stack that never froze, or a freezing policy would differ from ``off`` by
    solver noise, not by freezing. A few new contacts go in by insertion; many (a new World, a
    large wake) by a full sort."""
    if counters[AWAKE_UNSORTED] == 0:
        return
    ci = contacts.contact_int
    awake = contacts.awake
    n = counters[N_AWAKE_CONTACTS]
    stride = n_bodies + 1
    if counters[AWAKE_UNSORTED] > 32:
        keys = np.empty(n, np.int64)
        for k in range(n):
            keys[k] = _key(awake[k], ci, stride)
        order = np.argsort(keys, kind="mergesort")
        tmp = awake[:n].copy()
        for k in range(n):
            awake[k] = tmp[order[k]]
    else:
        for k in range(1, n):  # insertion sort: nearly sorted already
            s = awake[k]
            key = _key(s, ci, stride)
            j = k - 1
            while j >= 0 and _key(awake[j], ci, stride) > key:
                awake[j + 1] = awake[j]
                j -= 1
            awake[j + 1] = s
    for k in range(n):
        ci[awake[k], AWAKE_INDEX] = k
    counters[AWAKE_UNSORTED] = 0


# ---- making and freeing slots -------------------------------------------------------------------
@lean_kernel
def create(a, b, n_dynamic, slop, speculative, contacts, counters):
    """A new contact for pair (a, b), awake, with no points yet. Returns its slot, or -1 when the
    store is full (counters[GROW_NEEDED] says so; nothing was changed)."""
    ci = contacts.contact_int
    cf = contacts.contact_float
    s = counters[FREE_HEAD]
    if s >= 0:
        counters[FREE_HEAD] = ci[s, NEXT_A]
    elif counters[N_SLOTS] < ci.shape[0]:
        s = counters[N_SLOTS]
        counters[N_SLOTS] = s + 1
    else:
        counters[GROW_NEEDED] |= GROW_CONTACTS
        return -1
    ci[s, BODY_A] = a
    ci[s, BODY_B] = b
    ci[s, POINT_COUNT] = 0
    ci[s, REFERENCE] = -1
    ci[s, INCIDENT] = b
    ci[s, AWAKE_INDEX] = -1
    ci[s, ALIVE] = 1
    for j in range(2):
        contacts.point_id[s, j] = -1
        for col in range(contacts.point_float.shape[2]):
            contacts.point_float[s, j, col] = 0.0
    if a >= 0:
        cf[s, SLOP] = min(slop[a], slop[b])
        cf[s, SPECULATIVE] = min(speculative[a], speculative[b])
    else:
        cf[s, SLOP] = slop[b]
        cf[s, SPECULATIVE] = speculative[b]
    for i in (a, b):
        if 0 <= i < n_dynamic:
            _link(i, s, contacts)
            counters[MAX_DEGREE] = max(counters[MAX_DEGREE], contacts.degree[i])
    _add_awake(s, contacts, counters)
    counters[N_LIVE] += 1
    return s


@lean_kernel
def destroy(s, n_dynamic, contacts, counters):
    """Free slot s: out of both bodies' lists and the awake list, onto the free list."""
    ci = contacts.contact_int
    for i in (ci[s, BODY_A], ci[s, BODY_B]):
        if 0 <= i < n_dynamic:
            _unlink(i, s, contacts)
    _remove_awake(s, contacts, counters)
    ci[s, ALIVE] = 0
    ci[s, POINT_COUNT] = 0
    ci[s, NEXT_A] = counters[FREE_HEAD]
    counters[FREE_HEAD] = s
    counters[N_LIVE] -= 1


# ---- narrowphase ---------------------------------------------------------------------------------
@inline_kernel
def _closing_speed(a, b, velocity, angular_velocity, extent):
    """m/s: a bound on how fast any point of a can approach any point of b (a = -1: the floor)
    within the step, whatever else the step does to either: the sum of their speeds, not the
    speed of one relative to the other. Two bodies falling side by side or one behind the other
    do not close at all until the one ahead is stopped, in the middle of the step, by what it
    lands on; a margin from their relative speed then had no contact between them, and a box of a
    pile dropped from 35 m flew on at 26 m/s 5 cm into the one below it, stopped under it."""
    speed = np.sqrt(velocity[b, 0] ** 2 + velocity[b, 1] ** 2)
    reach = abs(angular_velocity[b]) * extent[b]
    if a >= 0:
        speed += np.sqrt(velocity[a, 0] ** 2 + velocity[a, 1] ** 2)
        reach += abs(angular_velocity[a]) * extent[a]
    return speed + reach


#: A manifold is refreshed from its stored points, without the separating-axis search and the
#: clipping, while the pair's relative pose has moved less than this fraction of the pair's slop
#: (and its rotation less than that at the bodies' extents) since the last full narrowphase: a
#: resting pile's contacts then cost a few multiplications each. The stored points are material
#: points of the incident body, so a refreshed manifold is the full one up to how far a clipped
#: point slides along its edge: at most this fraction of the slop.
REFRESH_FRACTION = 0.1


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
        margin = cf[s, SPECULATIVE] + dt * _closing_speed(
            a, b, bodies.velocity, bodies.angular_velocity, bodies.extent
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
    # last step's points, to carry their impulses over by feature id
    n_old = ci[s, POINT_COUNT]
    old_id0 = contacts.point_id[s, 0]
    old_id1 = contacts.point_id[s, 1]
    old_n0 = pf[s, 0, WARM_NORMAL]
    old_t0 = pf[s, 0, WARM_TANGENT]
    old_n1 = pf[s, 1, WARM_NORMAL]
    old_t1 = pf[s, 1, WARM_TANGENT]
    old_c0 = pf[s, 0, CARRIED]
    old_c1 = pf[s, 1, CARRIED]
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
        warm_n = 0.0
        warm_t = 0.0
        carried = 0.0
        if settings.warm_starting:
            if n_old > 0 and old_id0 == ids[j]:
                warm_n = old_n0
                warm_t = old_t0
                carried = old_c0
            elif n_old > 1 and old_id1 == ids[j]:
                warm_n = old_n1
                warm_t = old_t1
                carried = old_c1
        pf[s, j, WARM_NORMAL] = warm_n
        pf[s, j, WARM_TANGENT] = warm_t
        pf[s, j, CARRIED] = carried
        contacts.point_id[s, j] = ids[j]
    return n_points
