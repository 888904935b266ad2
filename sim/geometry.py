"""Convex-polygon geometry: validation and mass properties (Python, run once per body) and the
collision kernels (Numba, run every step).

Conventions
- Polygons are convex, counter-clockwise, in metres. Edge ``i`` runs from vertex ``i`` to vertex
  ``i+1`` (wrapping); its outward unit normal is ``normals[i]``.
- Collision kernels work in world coordinates on pre-transformed vertex arrays, so they are pure
  functions that tests can compare with the slow references in ``tests/naive.py``.
- A contact normal points from body A to body B; a separation is positive when the shapes are apart.
"""

import math

import numpy as np

from .jit import inline_kernel, kernel, lean_kernel

#: Largest vertex count a polygon may have: feature ids pack vertex indices into 10 bits.
MAX_VERTICES = 1024
#: m; bodies beyond this are treated as diverged by the step loop, and no vertex may lie farther
#: from its body's origin (squares of larger coordinates overflow the convexity test and the mass
#: properties: a square of side 2e155 passed validation with NaN turn angles)
MAX_COORDINATE = 1e12
#: m/s and rad/s: no body may start faster. It would cross the solver's whole range within a
#: second, and its kinetic energy could overflow float64 while its state stays finite
#: (angular_velocity 1e300 rad/s made kinetic_energy() inf).
MAX_SPEED = 1e12


class PolygonError(ValueError):
    """A polygon that the solver cannot use (non-convex, clockwise, degenerate, non-finite)."""


def signed_area(vertices):
    """Shoelace area (m^2), positive for counter-clockwise vertices."""
    v = np.asarray(vertices, dtype=np.float64)
    v = v - v.mean(axis=0)  # about the polygon's own centre: far from the origin, the
    x, y = v[:, 0], v[:, 1]  # shoelace terms would cancel catastrophically
    # elementwise products and numpy's own sums, never np.dot (see mass_properties)
    return 0.5 * float((x * np.roll(y, -1)).sum() - (np.roll(x, -1) * y).sum())


def mass_properties(vertices, density):
    """Mass (kg), centroid (m, shape (2,)) and moment of inertia about the centroid (kg m^2).

    Triangle fan from the first vertex, so that polygons far from the origin keep their precision.

    No BLAS call (np.dot, ``@``): OpenBLAS picks its kernel by CPU, and its kernels round
    differently (an AVX-512 one fuses the multiply and add of a 2-vector dot). A centroid a bit
    off in its last place changed chaotic scenes: drop(30) piles settled differently on an Intel
    AVX-512 machine than on an AMD one, and tests of which piles come to rest failed on one of
    them. Elementwise arithmetic and numpy's sums round the same on every CPU
    (tests/unit/test_determinism.py runs a pile under two OpenBLAS kernels).
    """
    v = np.asarray(vertices, dtype=np.float64)
    origin = v[0]
    p = v - origin
    a = p[1:-1]
    b = p[2:]
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]  # twice each triangle's area
    area = 0.5 * cross.sum()
    centroid = ((a + b) * cross[:, None]).sum(axis=0) / (6.0 * area)
    # second moment of each triangle (origin, a, b) about the fan origin
    i_origin = (
        cross
        * (
            a[:, 0] ** 2
            + a[:, 0] * b[:, 0]
            + b[:, 0] ** 2
            + a[:, 1] ** 2
            + a[:, 1] * b[:, 1]
            + b[:, 1] ** 2
        )
    ).sum() / 12.0
    mass = density * area
    c2 = float(centroid[0] * centroid[0] + centroid[1] * centroid[1])
    inertia = density * i_origin - mass * c2  # parallel axis theorem
    return mass, centroid + origin, inertia


def place(local, position, angle):
    """(K,2) m: body-frame points ``local`` (K,2) m turned by ``angle`` (rad) and moved to
    ``position`` (m). Elementwise, not a matrix product: a BLAS call rounds by the CPU's kernel
    (see ``mass_properties``), and poses compared across machines must agree bit for bit."""
    v = np.asarray(local, dtype=np.float64)
    c, s = math.cos(angle), math.sin(angle)
    x, y = v[:, 0], v[:, 1]
    return np.stack([x * c - y * s, x * s + y * c], axis=1) + np.asarray(position, dtype=np.float64)


def edge_normals(vertices):
    """Outward unit normals (K, 2) of a CCW polygon's edges."""
    v = np.asarray(vertices, dtype=np.float64)
    e = np.roll(v, -1, axis=0) - v
    n = np.stack([e[:, 1], -e[:, 0]], axis=1)
    return n / np.hypot(n[:, 0], n[:, 1])[:, None]


# --------------------------------------------------------------------------------------------
# Kernels. Feature ids identify a contact point by the features that made it, so that the solver
# can carry its impulse to the next step (warm starting):
#   id = ((flip * 1024 + reference_edge) * 1024 + incident_edge) * 2 + end
# end 0/1: the point comes from the incident edge's first/second end. Whether that end was cut by a
# side plane does not enter the id: two equal boxes stacked flush have their corners exactly on
# the side planes, and an id that flipped between "vertex" and "cut" with round-off would lose the
# warm start every few steps and let the stack sway. Floor contacts use the body's vertex index.


@inline_kernel
def _max_separation(verts, normals, a0, a1, b0, b1):
    """Edge of polygon A (rows a0..a1-1 of verts/normals) whose outward normal separates polygon B
    (rows b0..b1-1) the most, and that separation. World coordinates, m. Returns (edge - a0, sep).
    Polygons are addressed by row ranges of the packed arrays, not by slices: a slice is a new
    array object, and creating two per pair cost more than the arithmetic.

    Every edge is scanned in full, without a branch (``min``): stopping an edge's scan as soon as
    it could no longer win saved arithmetic but cost a mispredicted branch almost every time, and
    the narrowphase of a settling pile of 200 polygons (drop(200), steps 2-240) took 37 us a
    step instead of 27."""
    best_edge = 0
    best_sep = -np.inf
    for i in range(a0, a1):
        nx = normals[i, 0]
        ny = normals[i, 1]
        px = verts[i, 0]
        py = verts[i, 1]
        s = np.inf
        for j in range(b0, b1):
            s = min(s, nx * (verts[j, 0] - px) + ny * (verts[j, 1] - py))
        best_edge = i - a0 if s > best_sep else best_edge  # selects, not branches
        best_sep = max(best_sep, s)
    return best_edge, best_sep


@inline_kernel
def _clip(p0x, p0y, p1x, p1y, d0, d1):
    """Clip segment p0-p1 to the side of a plane where the signed distances d0, d1 of its ends
    are <= 0, moving an end that lies outside onto the plane. On scalars, not arrays: array
    stores here made clipping cost five times the SAT it follows.
    Returns (any part inside, p0x, p0y, p1x, p1y)."""
    if d0 > 0.0 and d1 > 0.0:
        return False, p0x, p0y, p1x, p1y
    if d0 > 0.0 or d1 > 0.0:
        f = d0 / (d0 - d1)
        qx = p0x + f * (p1x - p0x)
        qy = p0y + f * (p1y - p0y)
        if d0 > 0.0:
            return True, qx, qy, p1x, p1y
        return True, p0x, p0y, qx, qy
    return True, p0x, p0y, p1x, p1y


@inline_kernel
def closest_vertex_edge(verts, p0, p1, q0, q1):
    """The nearest (vertex of P, point of an edge of Q): P is rows p0..p1-1 and Q rows q0..q1-1
    of ``verts`` (m). Returns (squared distance, vertex i - p0, edge j, u): the point on edge j
    is q_j + u (q_j+1 - q_j), u clamped to [0, 1]; the first strictly nearer pair is kept.
    Shared by the narrowphase's corner contacts (``_closest_points``) and continuous
    collision's closest-point axis (``sim.continuous``)."""
    best = np.inf
    bi = 0
    bj = 0
    bu = 0.0
    k = q1 - q0
    for i in range(p0, p1):
        px = verts[i, 0]
        py = verts[i, 1]
        for j in range(k):
            ax = verts[q0 + j, 0]
            ay = verts[q0 + j, 1]
            jn = j + 1 if j + 1 < k else 0
            ex = verts[q0 + jn, 0] - ax
            ey = verts[q0 + jn, 1] - ay
            u = ((px - ax) * ex + (py - ay) * ey) / (ex * ex + ey * ey)
            u = min(max(u, 0.0), 1.0)
            wx = ax + u * ex - px
            wy = ay + u * ey - py
            d2 = wx * wx + wy * wy
            if d2 < best:
                best = d2
                bi = i - p0
                bj = j
                bu = u
    return best, bi, bj, bu


@inline_kernel
def edge_point(verts, q0, q1, j, u):
    """(x, y) m: the point ``u`` along edge j of the polygon in rows q0..q1-1."""
    jn = j + 1 if j + 1 < q1 - q0 else 0
    ax = verts[q0 + j, 0]
    ay = verts[q0 + j, 1]
    return ax + u * (verts[q0 + jn, 0] - ax), ay + u * (verts[q0 + jn, 1] - ay)


@lean_kernel
def _closest_points(
    verts, a0, a1, b0, b1, margin, out_points, out_separations, out_ids, out_normal
):
    """A one-point manifold at the closest points of two disjoint polygons, if they lie within
    ``margin``: the normal from A's point to B's, the point on B, the separation their distance.

    Why. Clipping against a reference face keeps only the incident edge's part that lies over
    the face. Two corners approaching each other diagonally have no such part: each polygon's
    incident edge lies wholly past the other's face end, so the clip kept no point however close
    the corners were, no speculative contact was made, and a corner met in the step went into the
    other body by up to the step's travel. In a pile of 30 random polygons (drop(30), seed 0) a
    polygon falling at 2.9 m/s, 23 mm above a resting one corner to corner, went 13 mm into it in
    one step, and under the pile's load was pushed out over seconds (Box2D v3 makes the same
    vertex-vertex contact from its segment distance). Returns the point count (0 or 1).

    A kernel of its own, called, not inlined: it runs for a few pairs a step (3 of ~590 in
    drop(200)) and need not weigh on the narrowphase's inlined code. Its search compares squared
    distances: with a square root per (vertex, edge) pair drop(200) cost 6% more a step than
    before the corner contacts, with squared ones 3.5% (measured over seeds 0-4, alternating
    processes; 1.5-2% on the seeds whose chaotic piles make as many full collisions as before)."""
    # B's vertices against A's edges first; A's against B's only if strictly nearer
    db, ib, ja, ua = closest_vertex_edge(verts, b0, b1, a0, a1)
    da, ia, jb, ub = closest_vertex_edge(verts, a0, a1, b0, b1)
    if not (0.0 < min(da, db) <= margin * margin):
        return 0
    if db <= da:  # B's vertex ib, the point on A's edge ja
        qx = verts[b0 + ib, 0]
        qy = verts[b0 + ib, 1]
        px, py = edge_point(verts, a0, a1, ja, ua)
        fa, fb, kind = ja, ib, 0
    else:  # A's vertex ia, the point on B's edge jb
        px = verts[a0 + ia, 0]
        py = verts[a0 + ia, 1]
        qx, qy = edge_point(verts, b0, b1, jb, ub)
        fa, fb, kind = ia, jb, 1
    d = np.hypot(qx - px, qy - py)
    if not (0.0 < d <= margin):
        return 0
    out_points[0, 0] = qx
    out_points[0, 1] = qy
    out_separations[0] = d
    # flip 2: apart from the face-clipping ids ((flip * 1024 + edge) * 1024 + edge) * 2 + end
    out_ids[0] = ((2 * MAX_VERTICES + fa) * MAX_VERTICES + fb) * 2 + kind
    out_normal[0] = (qx - px) / d
    out_normal[1] = (qy - py) / d
    return 1


@inline_kernel
def collide_polygon_rows(
    verts,
    normals,
    a0,
    a1,
    b0,
    b1,
    margin,
    face_tolerance,
    out_points,
    out_separations,
    out_ids,
    out_normal,
):
    """SAT + reference/incident face clipping between convex polygons A and B, given as row ranges
    a0..a1-1 and b0..b1-1 of packed world-coordinate arrays verts/normals (V,2).

    Finds up to two contact points whose separation is at most ``margin`` (m). The reference face is
    A's unless B's best axis separates clearly more: by ``face_tolerance`` (m) plus 0.1% (the bias
    keeps the choice from flickering; it scales with the bodies, see ``sim.tolerances``).

    Outputs (written in place):
      out_points (2,2)  m   contact points on the incident polygon's surface
      out_separations (2,) m  signed distance along the normal (negative = penetration)
      out_ids (2,) int64   feature ids (see module comment)
      out_normal (2,)      unit normal from A to B
    Returns (count, flip, reference_edge, gap): flip = 1 when B holds the reference face; gap (m)
    the largest separation along an edge normal found, a lower bound on the distance between the
    polygons (projection onto an axis never lengthens a distance), which lets the narrowphase skip
    a pair until its bodies have moved that much closer.

    When the polygons are apart and neither face's clip keeps a point (corners approaching each
    other, each past the other's face end: ``_closest_points``), the manifold is one point at
    their closest points, with A as the reference, the normal from A's closest point to B's and
    ``reference_edge`` = -1: the reference feature is then the plane through A's closest point
    (the point less its separation along the normal) normal to it.
    """
    edge_a, sep_a = _max_separation(verts, normals, a0, a1, b0, b1)
    if sep_a > margin:
        return 0, 0, 0, sep_a
    edge_b, sep_b = _max_separation(verts, normals, b0, b1, a0, a1)
    gap = max(sep_a, sep_b)
    if sep_b > margin:
        return 0, 0, 0, gap
    # Prefer A's face unless B's is better by more than a small tolerance: coherent choice frame to
    # frame keeps feature ids, and so warm starting, stable.
    b_first = sep_b > sep_a + face_tolerance + 1e-3 * abs(sep_a)
    for attempt in range(2):
        if b_first == (attempt == 0):
            kept = _clip_against_face(
                verts,
                normals,
                b0,
                b1,
                a0,
                a1,
                edge_b,
                1,
                margin,
                out_points,
                out_separations,
                out_ids,
                out_normal,
            )
            if kept > 0:
                return kept, 1, edge_b, gap
        else:
            kept = _clip_against_face(
                verts,
                normals,
                a0,
                a1,
                b0,
                b1,
                edge_a,
                0,
                margin,
                out_points,
                out_separations,
                out_ids,
                out_normal,
            )
            if kept > 0:
                return kept, 0, edge_a, gap
        # The preferred face may be short, with the other polygon's incident edge entirely past
        # its end (a choice inside the bias band): the shapes still touch, so clip against the
        # other polygon's face before concluding there is no contact.
    if gap > 0.0:
        kept = _closest_points(
            verts, a0, a1, b0, b1, margin, out_points, out_separations, out_ids, out_normal
        )
        if kept > 0:
            return kept, 0, -1, gap
    return 0, 0, 0, gap


@inline_kernel
def _clip_against_face(
    verts,
    normals,
    r0,
    r1,
    i0,
    i1,
    edge,
    flip,
    margin,
    out_points,
    out_separations,
    out_ids,
    out_normal,
):
    """Clip the incident polygon (rows i0..i1-1) against reference edge ``edge`` of the polygon in
    rows r0..r1-1; write the points within ``margin`` and return how many (0-2)."""
    nx = normals[r0 + edge, 0]
    ny = normals[r0 + edge, 1]
    # incident edge: the one whose normal is most anti-parallel to the reference normal
    inc_edge = 0
    lowest = np.inf
    for i in range(i0, i1):
        d = nx * normals[i, 0] + ny * normals[i, 1]
        inc_edge = i - i0 if d < lowest else inc_edge  # selects, not branches
        lowest = min(lowest, d)
    i2 = inc_edge + 1 if inc_edge + 1 < i1 - i0 else 0
    r2 = edge + 1 if edge + 1 < r1 - r0 else 0
    # work on scalars and write the outputs once (see _clip)
    p0x = verts[i0 + inc_edge, 0]
    p0y = verts[i0 + inc_edge, 1]
    p1x = verts[i0 + i2, 0]
    p1y = verts[i0 + i2, 1]
    tx = -ny  # reference face tangent, along the CCW edge direction
    ty = nx
    v1x = verts[r0 + edge, 0]
    v1y = verts[r0 + edge, 1]
    # clip the incident segment to the reference face's side planes: t.(p - v1) >= 0 and
    # t.(p - v2) <= 0, moving an end that lies outside onto the plane
    lo = tx * v1x + ty * v1y
    hi = tx * verts[r0 + r2, 0] + ty * verts[r0 + r2, 1]
    inside, p0x, p0y, p1x, p1y = _clip(
        p0x, p0y, p1x, p1y, lo - (tx * p0x + ty * p0y), lo - (tx * p1x + ty * p1y)
    )  # > 0: before the start
    if not inside:
        return 0
    inside, p0x, p0y, p1x, p1y = _clip(
        p0x, p0y, p1x, p1y, tx * p0x + ty * p0y - hi, tx * p1x + ty * p1y - hi
    )  # > 0: past the end
    if not inside:
        return 0
    face = nx * v1x + ny * v1y
    s0 = nx * p0x + ny * p0y - face
    s1 = nx * p1x + ny * p1y - face
    base = ((flip * 1024 + edge) * 1024 + inc_edge) * 2
    kept = 0
    if s0 <= margin:
        out_points[0, 0] = p0x
        out_points[0, 1] = p0y
        out_separations[0] = s0
        out_ids[0] = base
        kept = 1
    if s1 <= margin:
        out_points[kept, 0] = p1x
        out_points[kept, 1] = p1y
        out_separations[kept] = s1
        out_ids[kept] = base + 1
        kept += 1
    if flip == 1:
        out_normal[0] = -nx
        out_normal[1] = -ny
    else:
        out_normal[0] = nx
        out_normal[1] = ny
    return kept


@inline_kernel
def collide_floor_rows(
    verts, normals, b0, b1, floor_y, margin, out_points, out_separations, out_ids
):
    """Contacts of a convex polygon (rows b0..b1-1 of packed world-coordinate arrays) with the
    half-plane y <= floor_y.

    The floor is the reference face (normal +y, from floor to body); the incident edge is the
    polygon's edge whose normal points most downward, and it always holds the lowest vertex.
    Returns (count, gap): the number of points (0-2) with separation <= margin (ids are vertex
    indices), and the polygon's height above the floor, m (its lowest vertex is on the incident
    edge).
    """
    k = b1 - b0
    inc_edge = 0
    lowest = np.inf
    for i in range(k):
        if normals[b0 + i, 1] < lowest:
            lowest = normals[b0 + i, 1]
            inc_edge = i
    kept = 0
    gap = np.inf
    for m in range(2):
        j = inc_edge + m
        if j >= k:
            j -= k
        s = verts[b0 + j, 1] - floor_y
        gap = min(gap, s)
        if s <= margin:
            out_points[kept, 0] = verts[b0 + j, 0]
            out_points[kept, 1] = verts[b0 + j, 1]
            out_separations[kept] = s
            out_ids[kept] = j
            kept += 1
    return kept, gap


# ---- the same kernels on separate per-polygon arrays, for tests and one-off use --------------
@kernel
def max_separation(verts1, normals1, verts2):
    """Edge of polygon 1 whose outward normal separates polygon 2 the most, and that separation.

    verts1 (K1,2), normals1 (K1,2), verts2 (K2,2): world coordinates, m. Returns (edge, sep).
    """
    k1 = verts1.shape[0]
    verts = np.concatenate((verts1, verts2))
    normals = np.concatenate((normals1, np.zeros_like(verts2)))
    return _max_separation(verts, normals, 0, k1, k1, verts.shape[0])


@kernel
def collide_polygons(
    verts_a,
    normals_a,
    verts_b,
    normals_b,
    margin,
    out_points,
    out_separations,
    out_ids,
    out_normal,
    face_tolerance=1e-4,
):
    """``collide_polygon_rows`` on two separate polygons (K,2) arrays; same outputs and return.
    ``face_tolerance`` defaults to the value a 1 m body gets (``sim.tolerances``)."""
    ka = verts_a.shape[0]
    verts = np.concatenate((verts_a, verts_b))
    normals = np.concatenate((normals_a, normals_b))
    return collide_polygon_rows(
        verts,
        normals,
        np.int64(0),  # not a literal (sim/jit, LITERALS)
        ka,
        ka,
        verts.shape[0],
        margin,
        face_tolerance,
        out_points,
        out_separations,
        out_ids,
        out_normal,
    )


@kernel
def collide_floor(verts, normals, floor_y, margin, out_points, out_separations, out_ids):
    """``collide_floor_rows`` on one polygon's (K,2) arrays; same outputs and return."""
    return collide_floor_rows(
        verts, normals, 0, verts.shape[0], floor_y, margin, out_points, out_separations, out_ids
    )


@kernel
def transform(local, px, py, c, s, out):
    """World coordinates of body-frame points: out = R(c, s) @ local + (px, py). Shapes (K,2)."""
    for i in range(local.shape[0]):
        x = local[i, 0]
        y = local[i, 1]
        out[i, 0] = c * x - s * y + px
        out[i, 1] = s * x + c * y + py


@kernel
def rotate(local, c, s, out):
    """Rotate body-frame directions (K,2) into the world frame."""
    for i in range(local.shape[0]):
        x = local[i, 0]
        y = local[i, 1]
        out[i, 0] = c * x - s * y
        out[i, 1] = s * x + c * y
