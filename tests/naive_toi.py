"""Slow, obviously-correct reference for ``sim/continuous.py``: the first time two swept convex
polygons come within a distance, found by sampling the sweep densely.

Plain numpy, written independently of the kernel: no separating axes, no advancement. The distance
between two convex polygons is 0 when they share a point (a vertex inside the other polygon, or
two edges crossing) and otherwise the smallest vertex-to-edge distance either way, which is exact
for disjoint convex polygons (their closest pair always includes a vertex). The sweep follows the
kernel's documented motion model (a convention, restated here): position and angle of each centre
of mass interpolated linearly from the pose at t = 0 to the pose at t = 1, vertices given in the
body frame about the centre of mass.

The first sample whose distance is <= the threshold brackets the crossing with the sample before
it, and bisection narrows that bracket to ~1e-13 in t. A dip below the threshold narrower than the
sample spacing (1 / samples of the step) can be missed; tests that compare against this reference
keep motions where that cannot matter or check the kernel's answer with ``distance`` directly.
"""

import numpy as np

SAMPLES = 20000


def outward_normals(vertices):
    """Unit outward normals of a CCW polygon's edges (edge i runs from vertex i to i+1)."""
    v = np.asarray(vertices, dtype=np.float64)
    d = np.roll(v, -1, axis=0) - v
    n = np.stack([d[:, 1], -d[:, 0]], axis=1)  # the edge direction turned clockwise
    return n / np.linalg.norm(n, axis=1)[:, None]


def centroid(vertices):
    """Area centroid of a polygon (triangles fanned from the vertex mean)."""
    v = np.asarray(vertices, dtype=np.float64)
    hub = v.mean(axis=0)
    p = v - hub
    q = np.roll(p, -1, axis=0)
    area2 = p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]  # twice each fan triangle's signed area
    return hub + ((p + q) * area2[:, None]).sum(axis=0) / (3.0 * area2.sum())


def poses(pose0, pose1, ts):
    """(S, 3) poses at the times ts, interpolated linearly."""
    p0 = np.asarray(pose0, dtype=np.float64)
    p1 = np.asarray(pose1, dtype=np.float64)
    ts = np.asarray(ts, dtype=np.float64)[:, None]
    return (1.0 - ts) * p0 + ts * p1


def world(local, pose_rows):
    """(S, K, 2) world vertices of body-frame polygon ``local`` at each pose row (x, y, angle)."""
    v = np.asarray(local, dtype=np.float64)
    c = np.cos(pose_rows[:, 2])[:, None]
    s = np.sin(pose_rows[:, 2])[:, None]
    x = c * v[None, :, 0] - s * v[None, :, 1] + pose_rows[:, 0:1]
    y = s * v[None, :, 0] + c * v[None, :, 1] + pose_rows[:, 1:2]
    return np.stack([x, y], axis=2)


def _cross(ux, uy, vx, vy):
    return ux * vy - uy * vx


def _point_edge_distances(points, poly):
    """(S, P, K) distance from each point to each edge of each sample's polygon."""
    start = poly[:, None, :, :]  # (S, 1, K, 2)
    d = np.roll(poly, -1, axis=1)[:, None, :, :] - start
    rel = points[:, :, None, :] - start  # (S, P, K, 2)
    u = np.clip((rel * d).sum(axis=3) / (d * d).sum(axis=3), 0.0, 1.0)
    gap = rel - u[..., None] * d
    return np.sqrt((gap * gap).sum(axis=3))


def _inside(points, poly):
    """(S, P): point p lies in (or on) the convex CCW polygon: left of or on every edge."""
    start = poly[:, None, :, :]
    d = np.roll(poly, -1, axis=1)[:, None, :, :] - start
    rel = points[:, :, None, :] - start
    return np.all(_cross(d[..., 0], d[..., 1], rel[..., 0], rel[..., 1]) >= 0.0, axis=2)


def _edges_cross(pa, pb):
    """(S,): some edge of A and some edge of B cross properly (each one's ends strictly on opposite
    sides of the other's line). Touching cases are left to the distance, which is 0 for them; a
    non-strict test would call collinear but disjoint edges crossing."""
    a0 = pa[:, :, None, :]
    a1 = np.roll(pa, -1, axis=1)[:, :, None, :]
    b0 = pb[:, None, :, :]
    b1 = np.roll(pb, -1, axis=1)[:, None, :, :]
    da = a1 - a0
    db = b1 - b0

    def side(o, d, p):
        return _cross(d[..., 0], d[..., 1], p[..., 0] - o[..., 0], p[..., 1] - o[..., 1])

    b_straddles = side(a0, da, b0) * side(a0, da, b1) < 0.0
    a_straddles = side(b0, db, a0) * side(b0, db, a1) < 0.0
    return np.any(a_straddles & b_straddles, axis=(1, 2))


def distances(local_a, local_b, pose_a0, pose_a1, pose_b0, pose_b1, ts):
    """(S,) exact distance between the polygons at each time in ts (0 where they overlap)."""
    pa = world(local_a, poses(pose_a0, pose_a1, ts))
    pb = world(local_b, poses(pose_b0, pose_b1, ts))
    d = np.minimum(
        _point_edge_distances(pa, pb).min(axis=(1, 2)),
        _point_edge_distances(pb, pa).min(axis=(1, 2)),
    )
    overlap = _inside(pa, pb).any(axis=1) | _inside(pb, pa).any(axis=1) | _edges_cross(pa, pb)
    return np.where(overlap, 0.0, d)


def distance(local_a, local_b, pose_a0, pose_a1, pose_b0, pose_b1, t):
    """Exact distance at one time t."""
    return float(distances(local_a, local_b, pose_a0, pose_a1, pose_b0, pose_b1, [t])[0])


def first_time(
    local_a, local_b, pose_a0, pose_a1, pose_b0, pose_b1, threshold, samples=SAMPLES, chunk=2000
):
    """First t in [0, 1] at which the distance is <= threshold, or 1.0 if there is none.

    Returns (t, hit): hit is False when no sample came within threshold."""
    args = (local_a, local_b, pose_a0, pose_a1, pose_b0, pose_b1)
    ts = np.linspace(0.0, 1.0, samples + 1)
    for lo in range(0, len(ts), chunk):
        part = ts[lo : lo + chunk]
        close = np.flatnonzero(distances(*args, part) <= threshold)
        if close.size == 0:
            continue
        i = lo + int(close[0])
        if i == 0:
            return 0.0, True
        a, b = ts[i - 1], ts[i]  # distance > threshold at a, <= threshold at b
        while b - a > 1e-13:
            m = 0.5 * (a + b)
            if distance(*args, m) <= threshold:
                b = m
            else:
                a = m
        return b, True
    return 1.0, False
