"""The geometry the extremes judge measures with (numpy, not the solver, so that every system is
measured by the same code): a scene's polygons about their centres of mass (``Shapes``), the
thinnest width of a convex polygon, the deepest overlap at a pose (separating axes over pairs from
a sweep of bounding boxes), and a segment clipped to a box (the projectile's path, for
tunnelling). Polygon padding and the pairwise separation are study.overlap's, shared with
fig_tradeoff."""

import numpy as np

from study.overlap import pad, separation, world_vertices
from sim.geometry import mass_properties


class Shapes:
    """The scene's polygons about their centres of mass (padded to one vertex count by repeating
    the last vertex: a zero-length edge, skipped), masses, moments, thinnest widths, statics."""

    def __init__(self, scene):
        bodies = list(scene.bodies)
        self.n = len(bodies)
        k = max(len(b.vertices) for b in bodies + list(scene.static_bodies))
        self.local = np.empty((self.n, k, 2))  # (N,K,2) m, body frame about the COM
        self.mass = np.empty(self.n)  # (N,) kg
        self.inertia = np.empty(self.n)  # (N,) kg m^2
        self.width = np.empty(self.n)  # (N,) m, thinnest width
        self.half = np.empty((self.n, 2))  # (N,2) m, half extents in the body frame
        for i, b in enumerate(bodies):
            m, c, inertia = mass_properties(b.vertices, b.density)
            v = np.asarray(b.vertices, dtype=float) - c
            self.local[i] = pad(v, k)
            self.mass[i], self.inertia[i] = m, inertia
            self.width[i] = thinnest_width(v)
            self.half[i] = np.abs(v).max(axis=0)
        statics = list(scene.static_bodies)
        self.statics = np.array([pad(world_vertices(b), k) for b in statics]).reshape(
            len(statics), k, 2
        )  # (S,K,2) m
        self.static_width = np.array([thinnest_width(b.vertices) for b in statics])
        self.static_pose = [(np.asarray(b.position, float), b.angle) for b in statics]
        self.static_half = np.array(
            [np.abs(np.asarray(b.vertices, float)).max(axis=0) for b in statics]
        ).reshape(len(statics), 2)
        self.floor_y = scene.floor_y
        self.g = float(np.hypot(*scene.gravity))

    def world(self, positions, angles):
        """(N,K,2) m world vertices at this pose."""
        c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
        x, y = self.local[..., 0], self.local[..., 1]
        return np.stack([c * x - s * y, s * x + c * y], axis=-1) + np.asarray(positions)[:, None]

    def energy(self, positions, velocities, angular_velocities):
        """(kinetic, potential relative to the floor) J."""
        # numpy's sums, not BLAS products: the same bits on every CPU (sim.geometry.place)
        v2 = velocities[:, 0] ** 2 + velocities[:, 1] ** 2
        ke = 0.5 * float((self.mass * v2).sum() + (self.inertia * angular_velocities**2).sum())
        floor = 0.0 if self.floor_y is None else self.floor_y
        pe = self.g * float((self.mass * (positions[:, 1] - floor)).sum())
        return ke, pe


def thinnest_width(vertices):
    """m: the smallest extent of a convex polygon across any of its edge directions (the width)."""
    v = np.asarray(vertices, dtype=float)
    e = np.roll(v, -1, axis=0) - v
    length = np.hypot(e[:, 0], e[:, 1])
    keep = length > 0
    n = np.stack([e[keep, 1], -e[keep, 0]], axis=1) / length[keep, None]
    proj = n[:, :1] * v[:, 0] + n[:, 1:] * v[:, 1]  # (E, K) m; elementwise, no BLAS
    return float((proj.max(axis=1) - proj.min(axis=1)).min())


def clip_to_box(a, b, half):
    """The segment a -> b (m, (2,) each) against the rectangle |x| < half[0], |y| < half[1]
    (Liang-Barsky): None if it misses the rectangle's interior, else (entry face, exit face),
    each (axis, sign) of the face crossed within the segment, or None where the segment starts
    (entry) or ends (exit) inside."""
    t_in, t_out = 0.0, 1.0
    face_in = face_out = None
    d = b - a
    for axis in (0, 1):
        h = half[axis]
        if d[axis] == 0.0:
            if abs(a[axis]) >= h:
                return None
            continue
        t1, t2 = (-h - a[axis]) / d[axis], (h - a[axis]) / d[axis]
        near, far = (t1, t2) if t1 < t2 else (t2, t1)
        sign_near = -1 if d[axis] > 0 else 1  # moving +: enters through the - face
        if near > t_in:
            t_in, face_in = near, (axis, sign_near)
        if far < t_out:
            t_out, face_out = far, (axis, -sign_near)
    if t_in >= t_out:
        return None
    return face_in, face_out


def deepest_overlap(shapes, positions, angles):
    """(deepest overlap m, deepest overlap / thinner width) at this pose, over body pairs (found
    by a sweep over x-sorted bounding boxes), body-static pairs and bodies against the floor."""
    w = shapes.world(positions, angles)
    width = shapes.width
    depth, rel = 0.0, 0.0
    if shapes.floor_y is not None:
        below = shapes.floor_y - w[..., 1].min(axis=1)  # (N,) m
        depth, rel = max(depth, float(below.max())), max(rel, float((below / width).max()))
    polys = np.concatenate([w, shapes.statics]) if len(shapes.statics) else w
    widths = np.concatenate([width, shapes.static_width]) if len(shapes.statics) else width
    n_dyn = len(w)
    lo, hi = polys.min(axis=1), polys.max(axis=1)  # (M,2)
    order = np.argsort(lo[:, 0], kind="stable")
    lo_s, hi_s = lo[order], hi[order]
    # in x-sorted order, body k's candidates are k+1 .. last[k]-1 (their min x <= its max x)
    last = np.searchsorted(lo_s[:, 0], hi_s[:, 0], side="right")
    count = np.maximum(last - np.arange(len(order)) - 1, 0)
    if count.sum():
        first = np.repeat(np.arange(len(order)), count)
        offset = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        second = first + 1 + offset
        i, j = order[first], order[second]
        ok = (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1]) & ((i < n_dyn) | (j < n_dyn))
        i, j = i[ok], j[ok]
        if len(i):
            sep = np.maximum(separation(polys[i], polys[j]), separation(polys[j], polys[i]))
            over = np.maximum(-sep, 0.0)
            depth = max(depth, float(over.max()))
            rel = max(rel, float((over / np.minimum(widths[i], widths[j])).max()))
    return max(depth, 0.0), max(rel, 0.0)
