"""Slow, obviously-correct references for ``sim/geometry.py``, written independently of its code.

Everything here is plain Python/numpy and favours the most direct formulation over speed, so that a
disagreement with the Numba kernels points at the kernels. Where the kernels make a choice that is a
convention rather than geometry (which face is the reference face, how feature ids are packed), the
convention is restated here from the docstrings of ``sim/geometry.py`` and named as such.
"""

import math

import numpy as np

# Conventions copied from the docstrings/comments of sim/geometry.py (not geometry facts):
# B's face becomes the reference face only if its best separation beats A's by this bias.
REFERENCE_ABS_BIAS = 1e-4
REFERENCE_REL_BIAS = 1e-3
# id = ((flip * ID_BASE + reference_edge) * ID_BASE + incident_edge) * 2 + end
ID_BASE = 1024


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


# ------------------------------------------------------------------------------------------------
# Mass properties: triangles fanned from the vertex mean, each triangle's own polar moment from its
# side lengths (J = A (a^2 + b^2 + c^2) / 36), then the parallel-axis theorem per triangle. This
# shares no formula with the kernel's fan-from-vertex-0 second-moment sum.


def mass_properties(vertices, density):
    """(mass, centroid (2,), polar moment about the centroid) of a convex CCW polygon."""
    v = np.asarray(vertices, dtype=np.float64)
    hub = v.mean(axis=0)  # inside any convex polygon, so every fan triangle is positive
    p = v - hub  # work near the origin: the polygon may sit far away
    k = len(p)
    triangles = []
    for i in range(k):
        a = np.zeros(2)
        b = p[i]
        c = p[(i + 1) % k]
        area = 0.5 * _cross(b - a, c - a)
        centre = (a + b + c) / 3.0
        sides_sq = (
            float(np.sum((b - a) ** 2)) + float(np.sum((c - b) ** 2)) + float(np.sum((a - c) ** 2))
        )
        own_polar = area * sides_sq / 36.0
        triangles.append((area, centre, own_polar))
    total_area = sum(t[0] for t in triangles)
    centroid = sum(t[0] * t[1] for t in triangles) / total_area
    polar = sum(
        own + area * float(np.sum((centre - centroid) ** 2)) for area, centre, own in triangles
    )
    return density * total_area, centroid + hub, density * polar


def regular_polygon(n, radius, centre=(0.0, 0.0), phase=0.0):
    """CCW regular n-gon with the given circumradius."""
    t = phase + 2.0 * math.pi * np.arange(n) / n
    return np.stack([centre[0] + radius * np.cos(t), centre[1] + radius * np.sin(t)], axis=1)


def regular_polygon_mass_properties(n, radius, density):
    """Textbook closed form: area (n/2) R^2 sin(2 pi/n), J = m R^2 (2 + cos(2 pi/n)) / 6."""
    area = 0.5 * n * radius**2 * math.sin(2.0 * math.pi / n)
    mass = density * area
    return mass, mass * radius**2 * (2.0 + math.cos(2.0 * math.pi / n)) / 6.0


# ------------------------------------------------------------------------------------------------
# Edges, normals, separating axes


def edges(vertices):
    """List of (start, end) pairs, edge i from vertex i to vertex i+1."""
    v = np.asarray(vertices, dtype=np.float64)
    return [(v[i], v[(i + 1) % len(v)]) for i in range(len(v))]


def outward_normal(start, end):
    """Unit normal of a CCW polygon's edge: the edge direction turned a quarter turn clockwise."""
    d = end - start
    return np.array([d[1], -d[0]]) / math.hypot(d[0], d[1])


def normals(vertices):
    return np.array([outward_normal(a, b) for a, b in edges(vertices)])


def axis_separations(verts1, verts2):
    """For every edge of polygon 1: how far polygon 2 lies beyond that edge's line (signed).

    Entry i is min over polygon 2's vertices q of n_i . (q - start_i): the gap between the edge's
    line and polygon 2's nearest point along the edge's outward normal.
    """
    v1 = np.asarray(verts1, dtype=np.float64)
    v2 = np.asarray(verts2, dtype=np.float64)
    n = normals(v1)
    offsets = v2[None, :, :] - v1[:, None, :]  # (edge i, vertex j, xy)
    return np.min(np.einsum("ijk,ik->ij", offsets, n), axis=1)


def max_separation(verts1, verts2):
    """(best edge of polygon 1, its separation): the SAT answer restricted to polygon 1's axes."""
    s = axis_separations(verts1, verts2)
    return int(np.argmax(s)), float(np.max(s))


def sat_separation(verts_a, verts_b):
    """Largest separation over every edge normal of both polygons: > 0 iff they are disjoint."""
    return max(max_separation(verts_a, verts_b)[1], max_separation(verts_b, verts_a)[1])


# ------------------------------------------------------------------------------------------------
# Distances and overlap, without any separating-axis reasoning


def point_segment_distances(points, vertices):
    """Distances (P, K) from each point to each edge of a polygon, and the edge parameters t.

    t in [0, 1] locates the closest point on the edge (start + t * (end - start)).
    """
    p = np.asarray(points, dtype=np.float64)
    v = np.asarray(vertices, dtype=np.float64)
    start = v
    d = np.roll(v, -1, axis=0) - v
    rel = p[:, None, :] - start[None, :, :]
    t = np.clip(np.einsum("pkx,kx->pk", rel, d) / np.einsum("kx,kx->k", d, d), 0.0, 1.0)
    gap = rel - t[:, :, None] * d[None, :, :]
    return np.hypot(gap[..., 0], gap[..., 1]), t


def polygon_distance(verts_a, verts_b):
    """Euclidean distance between two disjoint convex polygons and how it is attained.

    For disjoint polygons the closest pair always involves a vertex of one polygon, so a brute-force
    minimum over vertex/edge pairs both ways is exact. Returns (distance, t) where t is the edge
    parameter of the closest pair: 0 < t < 1 means the vertex faces the interior of an edge.
    """
    best = (math.inf, 0.0)
    for p_verts, e_verts in ((verts_a, verts_b), (verts_b, verts_a)):
        dist, t = point_segment_distances(p_verts, e_verts)
        i, k = np.unravel_index(np.argmin(dist), dist.shape)
        best = min(best, (float(dist[i, k]), float(t[i, k])))
    return best


def boundary_distance(p, vertices):
    """Distance from a point to the outline of a polygon."""
    return float(np.min(point_segment_distances(np.asarray(p)[None, :], vertices)[0]))


def _left_of(points, vertices):
    """(P, K) cross products: > 0 where point p is strictly left of edge k (inside for CCW)."""
    p = np.asarray(points, dtype=np.float64)
    v = np.asarray(vertices, dtype=np.float64)
    d = np.roll(v, -1, axis=0) - v
    rel = p[:, None, :] - v[None, :, :]
    return d[None, :, 0] * rel[..., 1] - d[None, :, 1] * rel[..., 0]


def polygons_intersect(verts_a, verts_b):
    """True if two convex polygons share a point: a vertex inside the other, or edges crossing.

    No separating axes involved: containment is "left of every CCW edge", and two segments cross
    when each one's ends lie on opposite sides of the other's line.
    """
    va = np.asarray(verts_a, dtype=np.float64)
    vb = np.asarray(verts_b, dtype=np.float64)
    a_in_b = np.any(np.all(_left_of(va, vb) >= 0, axis=1))
    b_in_a = np.any(np.all(_left_of(vb, va) >= 0, axis=1))
    if a_in_b or b_in_a:
        return True
    # sides of A's edge ends relative to B's edges, and of B's edge ends relative to A's edges
    a_start = np.sign(_left_of(va, vb))  # (edge/vertex of A, edge of B)
    a_end = np.roll(a_start, -1, axis=0)
    b_start = np.sign(_left_of(vb, va))  # (vertex of B, edge of A)
    b_end = np.roll(b_start, -1, axis=0)
    a_straddles = a_start != a_end  # A's edge i crosses B's edge k's line
    b_straddles = (b_start != b_end).T  # B's edge k crosses A's edge i's line
    return bool(np.any(a_straddles & b_straddles))


# ------------------------------------------------------------------------------------------------
# Contact manifolds


def choose_reference(verts_a, verts_b):
    """Reference face as documented: A's best face unless B's separates clearly more.

    Returns dict with flip, reference edge, and both polygons' best (edge, separation) for tests
    that need to stay away from the documented decision boundaries.
    """
    edge_a, sep_a = max_separation(verts_a, verts_b)
    edge_b, sep_b = max_separation(verts_b, verts_a)
    flip = int(sep_b > sep_a + REFERENCE_ABS_BIAS + REFERENCE_REL_BIAS * abs(sep_a))
    return {
        "flip": flip,
        "edge": edge_b if flip else edge_a,
        "edge_a": edge_a,
        "sep_a": sep_a,
        "edge_b": edge_b,
        "sep_b": sep_b,
    }


def incident_edge(reference_normal, incident_vertices):
    """Edge of the incident polygon facing the reference face most squarely (smallest n_ref . n)."""
    dots = normals(incident_vertices) @ reference_normal
    return int(np.argmin(dots)), dots


def clip_incident_edge(ref_vertices, ref_edge, inc_vertices, inc_edge):
    """Incident edge cut to the reference face's extent, by parametric (Liang-Barsky) clipping.

    The face's extent is the slab between the lines through its two ends, perpendicular to it.
    Returns [] if the edge misses the slab, else [(point, end)] for end 0 and end 1 of the incident
    edge (a cut end is moved onto the slab boundary but keeps its end number).
    """
    r0, r1 = edges(ref_vertices)[ref_edge]
    p0, p1 = edges(inc_vertices)[inc_edge]
    tangent = (r1 - r0) / math.hypot(*(r1 - r0))
    length = float(tangent @ (r1 - r0))
    s0 = float(tangent @ (p0 - r0))  # position of each end along the face, 0 .. length
    s1 = float(tangent @ (p1 - r0))
    lo, hi = 0.0, 1.0  # parameter range of the incident edge kept so far
    # Each side is written as  lam * rate <= slack  with s(lam) = s0 + lam * (s1 - s0):
    # s >= 0 is -lam*(s1-s0) <= s0, and s <= length is lam*(s1-s0) <= length - s0.
    for rate, slack in ((-(s1 - s0), s0), (s1 - s0, length - s0)):
        if rate == 0.0:
            if slack < 0.0:
                return []
            continue
        lam = slack / rate
        if rate > 0.0:
            hi = min(hi, lam)
        else:
            lo = max(lo, lam)
    if lo > hi:
        return []
    return [(p0 + lo * (p1 - p0), 0), (p0 + hi * (p1 - p0), 1)]


def collide_polygons(verts_a, verts_b, margin):
    """Reference contact manifold, in the kernel's output convention.

    Returns dict(count, flip, edge, normal, points (list), separations (list), ids (list)).
    """
    va = np.asarray(verts_a, dtype=np.float64)
    vb = np.asarray(verts_b, dtype=np.float64)
    choice = choose_reference(va, vb)
    empty = {
        "count": 0,
        "flip": 0,
        "edge": 0,
        "normal": None,
        "points": [],
        "separations": [],
        "ids": [],
        "inc_edge": None,
        "choice": choice,
    }
    if choice["sep_a"] > margin or choice["sep_b"] > margin:
        return empty
    # The preferred face first; if clipping against it keeps no point (a short face the incident
    # edge misses entirely, possible inside the bias band), the other polygon's best face.
    for flip in (choice["flip"], 1 - choice["flip"]):
        ref_edge = choice["edge_b"] if flip else choice["edge_a"]
        ref_v, inc_v = (vb, va) if flip else (va, vb)
        r0, r1 = edges(ref_v)[ref_edge]
        n = outward_normal(r0, r1)
        inc_edge, _ = incident_edge(n, inc_v)
        base = (flip * ID_BASE + ref_edge) * ID_BASE + inc_edge
        points, seps, ids = [], [], []
        for p, end in clip_incident_edge(ref_v, ref_edge, inc_v, inc_edge):
            s = float(n @ (p - r0))  # signed distance to the reference face's line
            if s <= margin:
                points.append(p)
                seps.append(s)
                ids.append(base * 2 + end)
        if points:
            return {
                "count": len(points),
                "flip": flip,
                "edge": ref_edge,
                "normal": -n if flip else n,
                "points": points,
                "separations": seps,
                "ids": ids,
                "inc_edge": inc_edge,
                "choice": choice,
            }
    # Neither face keeps a point: corners approaching each other, each past the other's face
    # end. Apart and within the margin, one point at the closest points (A the reference).
    if max(choice["sep_a"], choice["sep_b"]) > 0.0:
        d, p, q, fa, fb, kind = closest_points(va, vb)
        if d <= margin:
            return {
                "count": 1,
                "flip": 0,
                "edge": -1,
                "normal": (q - p) / d,
                "points": [q],
                "separations": [d],
                "ids": [((2 * ID_BASE + fa) * ID_BASE + fb) * 2 + kind],
                "inc_edge": None,
                "choice": choice,
            }
    return empty


def closest_points(verts_a, verts_b):
    """The closest points of two disjoint convex polygons, by brute force over every (vertex,
    edge) pair both ways, B's vertices against A's edges first, the first strictly nearer pair
    kept (the kernel's order). Returns (distance, point on A, point on B, A's feature, B's
    feature, kind): kind 0 when the point on B is B's vertex fb and the one on A lies on A's edge
    fa, kind 1 when A's vertex fa meets B's edge fb."""
    best = None
    for kind, (v_verts, e_verts) in enumerate(((verts_b, verts_a), (verts_a, verts_b))):
        dist, t = point_segment_distances(v_verts, e_verts)
        for i in range(dist.shape[0]):
            for k in range(dist.shape[1]):
                if best is None or dist[i, k] < best[0]:
                    end = e_verts[(k + 1) % len(e_verts)]
                    on_edge = e_verts[k] + t[i, k] * (end - e_verts[k])
                    best = (float(dist[i, k]), v_verts[i], on_edge, i, k, kind)
    d, vertex, on_edge, i, k, kind = best
    if kind == 0:
        return d, on_edge, vertex, k, i, 0
    return d, vertex, on_edge, i, k, 1


def floor_contacts(vertices, floor_y, margin):
    """Contacts with the half-plane y <= floor_y, as documented for the kernel.

    The incident edge is the one running most nearly left-to-right (for a CCW polygon that is the
    bottom-facing edge); its ends within ``margin`` of the floor are the contacts, id = vertex
    index. Returns (list of (vertex index, point, separation), incident edge, per-edge scores).
    """
    v = np.asarray(vertices, dtype=np.float64)
    scores = np.array([(b - a)[0] / math.hypot(*(b - a)) for a, b in edges(v)])
    e = int(np.argmax(scores))
    out = []
    for j in (e, (e + 1) % len(v)):
        s = float(v[j, 1] - floor_y)
        if s <= margin:
            out.append((j, v[j].copy(), s))
    return out, e, scores


def rotation(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


# ------------------------------------------------------------------------------------------------
# Cone membership (``sim.freeze.certificate``): the Lawson-Hanson active-set non-negative least
# squares, min |G^T w - t| over w >= 0. The wrench t is in the cone of the rows of G exactly when
# that residual is zero. Shares nothing with the certificate's enumeration of triples.


def nnls(G, t, iterations=500):
    """(weights >= 0, residual norm) minimising |G^T w - t| (G: (K, n) generators as rows)."""
    A = np.asarray(G, dtype=np.float64).T  # (n, K): generators as columns
    b = np.asarray(t, dtype=np.float64)
    k = A.shape[1]
    w = np.zeros(k)
    passive = np.zeros(k, bool)
    for _ in range(iterations):
        gradient = A.T @ (b - A @ w)
        candidates = ~passive & (gradient > 1e-12)
        if not candidates.any():
            break
        passive[np.argmax(np.where(candidates, gradient, -np.inf))] = True
        while True:
            z = np.zeros(k)
            z[passive] = np.linalg.lstsq(A[:, passive], b, rcond=None)[0]
            if (z[passive] > 0).all():
                w = z
                break
            blocked = passive & (z <= 0)
            step = np.min(w[blocked] / (w[blocked] - z[blocked]))
            w = w + step * (z - w)
            passive &= w > 1e-15
    return w, float(np.linalg.norm(A @ w - b))


# ------------------------------------------------------------------------------------------------
# A lane's two contact rows (``sim.soft_step.batches.two_row_impulses``): the linear
# complementarity problem z >= 0, w = q + K z >= 0, z w = 0, by projected Gauss-Seidel iterated to
# convergence (each row in turn set to its own answer with the other held). Shares nothing with
# the kernel's enumeration of the four cases.


def complementary_impulses(K, q, sweeps=20000):
    """z >= 0 with w = q + K z >= 0 and z_i w_i = 0 (K symmetric positive definite, (n, n))."""
    K = np.asarray(K, dtype=np.float64)
    q = np.asarray(q, dtype=np.float64)
    z = np.zeros(len(q))
    for _ in range(sweeps):
        for i in range(len(q)):
            z[i] = max(0.0, z[i] - (q[i] + K[i] @ z) / K[i, i])
    return z


# ------------------------------------------------------------------------------------------------
# Lever arms of a contact point after its bodies moved (``sim.soft_step.arms``), from world
# positions: A's anchor point and B's start ``separation`` apart along the normal, both carried
# with their bodies, and the arms shifted to one line of action between them.


def moved_contact_arms(
    centre_a, anchor_a, normal, separation, centre_b, motion_a, motion_b, t, toward
):
    """(arm A, arm B, separation now) of a point after the bodies moved, for an impulse along t.

    centre_a, centre_b: the bodies' centres at the start (m); anchor_a: A's anchor relative to
    its centre (m); the B anchor starts ``separation`` m from A's along ``normal``. motion_a,
    motion_b: (dx, dy, angle) of each body since the start. The arms reach the line along t
    that divides the moved anchors' offset across t at ``toward`` (0: through A's anchor, 1:
    through B's): an impulse and its reaction on one line."""
    n = np.asarray(normal, dtype=np.float64)
    t = np.asarray(t, dtype=np.float64)
    ca = np.asarray(centre_a, dtype=np.float64)
    cb = np.asarray(centre_b, dtype=np.float64)
    ra = np.asarray(anchor_a, dtype=np.float64)
    rb = ca + ra + separation * n - cb  # B's anchor relative to B's centre
    ca_now = ca + np.asarray(motion_a[:2])
    cb_now = cb + np.asarray(motion_b[:2])
    pa = ca_now + rotation(motion_a[2]) @ ra
    pb = cb_now + rotation(motion_b[2]) @ rb
    d = pb - pa
    across = np.array([t[1], -t[0]])
    line = pa + toward * d  # a point of the line of action
    arm_a = pa + float((line - pa) @ across) * across - ca_now
    arm_b = pb + float((line - pb) @ across) * across - cb_now
    return arm_a, arm_b, float(d @ n), rb


def greedy_colours(pairs, movable):
    """{pair: colour} of the solver's constraint colouring (``sim.soft_step.colour``), recomputed
    from scratch: ``pairs`` the active contacts' (body_a, body_b) in active order, ``movable`` the
    bodies the solver moves. Contacts between two movable bodies first, each in the lowest colour
    neither body has yet; then those with an immovable body (the floor is -1), each in the
    lowest colour its movable body has not, counted from the first pass's colours up."""
    used = {}  # body -> set of colours
    out = {}
    n_colours = 0
    for second_pass in (False, True):
        lowest = n_colours if second_pass else 0
        for a, b in pairs:
            ends = [x for x in (a, b) if x in movable]
            if (len(ends) < 2) != second_pass:
                continue
            c = lowest
            while any(c in used.get(x, ()) for x in ends):
                c += 1
            for x in ends:
                used.setdefault(x, set()).add(c)
            out[(a, b)] = c
            n_colours = max(n_colours, c + 1)
    return out
