"""Continuous collision: the time of impact of a convex polygon swept through one step.

Why: the step loop checks contacts only at the poses the integrator lands on. A 0.2 m box at
200 m/s moves 3.3 m in a step of 1/60 s, so it can be on one side of a 5 cm wall at one step and
on the other side at the next without ever overlapping it (tunnelling). For a body that moved more
than a fraction of its size, the step loop sweeps it from its pose at the start of the step to its
pose at the end against each static or frozen polygon its swept box touches (``swept_aabb``), and
moves it back to the pose at the time of impact (``time_of_impact``). Speculative contacts, whose
reach grows with the approach speed (``sim.contacts``), stop such a box at the wall already (with
continuous=False too); the sweep is the backstop for where the contact solve fails, which
``kernel``'s stage ``continuous`` judges (ARCHITECTURE, continuous collision).

Motion model: within the step, each body's centre of mass moves linearly and its angle changes
linearly, t in [0, 1] being the fraction of the step. A pose is (x m, y m, angle rad) of the centre
of mass; the angle is NOT wrapped: angle1 - angle0 is the rotation during the step.

Method: conservative advancement (Mirtich, "Impulse-based dynamic simulation of rigid body
systems", 1996). At the current t, find a lower bound on the distance between the polygons and a
bound on how fast that distance can shrink, and advance t by the time the distance surely needs to
fall to the target. Repeat until the polygons are within target + tolerance, or t reaches 1.

Lower bound (the gap along an axis). For any fixed unit direction n (world frame, pointing from A
towards B), let gap_n(t) = min over B(t) of n.q - max over A(t) of n.p. Projection onto n shortens
distances, so |q - p| >= n.(q - p) >= gap_n for every p in A, q in B: the distance d(t) >= gap_n(t)
(and d >= 0 >= gap_n when they overlap). The axes tried are
  - every edge normal of A and of B (the SAT axes: the largest SAT gap is > 0 exactly when the
    convex polygons are disjoint, and it is minus the penetration depth when they overlap), and
  - the direction between the closest points of the two polygons, along which the gap IS the
    distance (a plane through each closest point, normal to that direction, supports its polygon).
    Without it the bound is loose when a corner meets a corner: two square corners approaching
    diagonally have SAT gap = distance / sqrt(2), two sharp tips far less, and the sweep would stop
    that much before the contact. Every gap is recomputed from the vertices along the (fixed) axis,
    so an inexact closest-point direction can only make the bound looser, never wrong.

Rate bound. A point of A at r from A's centre of mass moves at v_A + w_A x r per unit t, whose
component along the fixed n is at most n.v_A + |w_A| r <= n.v_A + |w_A| R_A, where R_A is A's
bounding radius (its farthest vertex from the centre of mass) and v_A = (x1 - x0, y1 - y0),
w_A = angle1 - angle0 (per unit t, constant under the motion model). Likewise any point of B moves
along n at least n.v_B - |w_B| R_B. The max over A of n.p and the min over B of n.q are envelopes of
such functions, so for tau >= t
    gap_n(tau) >= gap_n(t) - rate_n (tau - t),  rate_n = max(n.(v_A - v_B), 0) + |w_A| R_A + |w_B|
    R_B.
(Only the positive part of the linear term counts: moving apart along n never closes the gap.)

Why it never steps past the first contact. Let t* be the first time d(t*) = target, and suppose the
current t <= t* with d(t) >= target. Each axis with gap_n(t) > target gives the advance
step_n = (gap_n(t) - target) / rate_n (infinite when rate_n = 0). For tau in [t, t + step_n):
    d(tau) >= gap_n(tau) >= gap_n(t) - rate_n (tau - t) > gap_n(t) - rate_n step_n = target,
so the distance stays above target on that interval, and t* >= t + step_n. This holds for every
such axis on its own, so t* >= t + max_n step_n: the next t is still no later than t*, and by
induction no iterate is. (In floating point the gaps are exact to about 1e-16 times the coordinates,
far below any useful target.) The iteration stops at the first t whose best gap is
<= target + tolerance, or at t = 1; when it runs out of iterations it returns the last t it
evaluated, which is safe by the same argument.

Cost: each iteration transforms both polygons and does O(K_A K_B) work (SAT and vertex/edge
distances). Face-to-face translation converges in 2 iterations (the rate bound is exact). Measured
on 1500 random sweeps of 3-10-gons (tests/unit/test_continuous.py's generator, tolerance 1e-3 of the
size): hits median 6 iterations, 90% <= 13, 99% <= 33, max 59; misses median 3; sweeps turning
< 0.5 rad median 2, max 9; turning 5-20 rad median 10, max 100. The slow case is a fast-spinning
body passing close by without touching: the rotation term |w| R dominates every rate bound (a 2 m
plank turning 30 rad in the step, 0.15 m short of a post: 65 iterations).
Nothing is allocated: the world
vertices go into a caller-owned scratch array (``toi_scratch``).
"""

import math

import numpy as np

from .geometry import closest_vertex_edge, edge_point
from .jit import inline_kernel, lean_kernel


def toi_scratch(max_vertices):
    """Scratch array for ``time_of_impact``: (2 * max_vertices, 2) float64 world vertices, enough
    for any pair of polygons with at most ``max_vertices`` vertices each."""
    return np.empty((2 * int(max_vertices), 2), dtype=np.float64)


@inline_kernel
def bounding_radius(local_verts, r0, r1):
    """Largest distance (m) from the body-frame origin (the centre of mass) to a vertex of the
    polygon in rows r0..r1-1: the farthest point of a convex polygon from any point is a vertex."""
    r2 = 0.0
    for i in range(r0, r1):
        d2 = local_verts[i, 0] * local_verts[i, 0] + local_verts[i, 1] * local_verts[i, 1]
        if d2 > r2:
            r2 = d2
    return math.sqrt(r2)


@inline_kernel
def _lerp(u0, u1, t):
    """u0 at t = 0 and u1 at t = 1 exactly (the form u0 + t (u1 - u0) can miss u1 by an ulp)."""
    return (1.0 - t) * u0 + t * u1


@inline_kernel
def pose_at(pose0, pose1, t):
    """The pose (x m, y m, angle rad) at fraction t of the sweep, interpolated exactly as
    ``time_of_impact`` does: move a body back to its time of impact with this."""
    return (
        _lerp(float(pose0[0]), float(pose1[0]), t),
        _lerp(float(pose0[1]), float(pose1[1]), t),
        _lerp(float(pose0[2]), float(pose1[2]), t),
    )


@inline_kernel
def _place(local_verts, r0, r1, x, y, angle, out, o0):
    """World coordinates of rows r0..r1-1 at pose (x, y, angle) into out rows o0...; m."""
    c = math.cos(angle)
    s = math.sin(angle)
    for i in range(r0, r1):
        lx = local_verts[i, 0]
        ly = local_verts[i, 1]
        out[o0 + i - r0, 0] = c * lx - s * ly + x
        out[o0 + i - r0, 1] = s * lx + c * ly + y


@inline_kernel
def _advance(gap, rate, target):
    """How far t may advance on one axis's guarantee (see the module docstring); 0 if none."""
    if gap <= target:
        return 0.0
    if rate <= 0.0:
        return np.inf
    return (gap - target) / rate


@inline_kernel
def _face_axes(world, p0, p1, q0, q1, local_normals, n0, angle, vx, vy, spin, target):
    """Gaps along the outward edge normals of polygon P (world rows p0..p1-1, body-frame normals
    from row n0 of local_normals, P's angle) to polygon Q (world rows q0..q1-1).

    (vx, vy): P's velocity minus Q's, m per unit t; spin: the rotation part of the rate bound, m per
    unit t. Returns (largest gap m, largest safe advance in t)."""
    c = math.cos(angle)
    s = math.sin(angle)
    best_gap = -np.inf
    best_step = 0.0
    for i in range(p0, p1):
        lnx = local_normals[n0 + i - p0, 0]
        lny = local_normals[n0 + i - p0, 1]
        nx = c * lnx - s * lny
        ny = s * lnx + c * lny
        px = world[i, 0]
        py = world[i, 1]
        gap = np.inf
        for j in range(q0, q1):
            d = nx * (world[j, 0] - px) + ny * (world[j, 1] - py)
            if d < gap:
                gap = d
        if gap > best_gap:
            best_gap = gap
        step = _advance(gap, max(nx * vx + ny * vy, 0.0) + spin, target)
        if step > best_step:
            best_step = step
    return best_gap, best_step


@inline_kernel
def separating_gap(local_verts, local_normals, a0, a1, b0, b1, pose_a, pose_b, scratch):
    """m: the largest gap along an edge normal of either polygon at these poses ((x, y, angle)
    floats): minus the penetration depth when they overlap (exact, as ``time_of_impact``'s
    separation is then), a lower bound on the distance when they are apart.

    Why: the step's sweep asks, of a fast body and an awake neighbour, only whether they end the
    step overlapping deeply. Over the SAT axes alone that is decided exactly, where a
    ``time_of_impact`` of zero length also searched the closest-points direction (a division for
    every vertex and edge) to measure a distance that decides nothing there."""
    ka = a1 - a0
    kb = b1 - b0
    _place(local_verts, a0, a1, pose_a[0], pose_a[1], pose_a[2], scratch, 0)
    _place(local_verts, b0, b1, pose_b[0], pose_b[1], pose_b[2], scratch, ka)
    gap_a, _ = _face_axes(
        scratch, 0, ka, ka, ka + kb, local_normals, a0, pose_a[2], 0.0, 0.0, 0.0, 1.0
    )
    gap_b, _ = _face_axes(
        scratch, ka, ka + kb, 0, ka, local_normals, b0, pose_b[2], 0.0, 0.0, 0.0, 1.0
    )
    return max(gap_a, gap_b)


@inline_kernel
def _closest_offset(world, p0, p1, q0, q1):
    """Shortest offset (m) from a vertex of polygon P (rows p0..p1-1) to an edge of Q (q0..q1-1):
    returns (squared length, x, y), the offset pointing from P's vertex to Q's edge."""
    best, i, j, u = closest_vertex_edge(world, p0, p1, q0, q1)
    x, y = edge_point(world, q0, q1, j, u)
    return best, x - world[p0 + i, 0], y - world[p0 + i, 1]


@inline_kernel
def _gap_along(world, a0, a1, b0, b1, nx, ny):
    """gap_n = min over B's vertices of n.q - max over A's of n.p (m); n a unit vector, A to B."""
    hi_a = -np.inf
    for i in range(a0, a1):
        d = nx * world[i, 0] + ny * world[i, 1]
        if d > hi_a:
            hi_a = d
    lo_b = np.inf
    for j in range(b0, b1):
        d = nx * world[j, 0] + ny * world[j, 1]
        if d < lo_b:
            lo_b = d
    return lo_b - hi_a


@inline_kernel
def _bounds(world, ka, kb, local_normals, a0, b0, angle_a, angle_b, vx, vy, spin, target):
    """At the current t (world vertices of A in rows 0..ka-1, of B in rows ka..ka+kb-1):
    (best lower bound on the distance m, negative = SAT penetration; safe advance in t).
    (vx, vy) is A's velocity minus B's, m per unit t."""
    gap_a, step_a = _face_axes(
        world, 0, ka, ka, ka + kb, local_normals, a0, angle_a, vx, vy, spin, target
    )
    gap_b, step_b = _face_axes(
        world, ka, ka + kb, 0, ka, local_normals, b0, angle_b, -vx, -vy, spin, target
    )
    best = max(gap_a, gap_b)
    step = max(step_a, step_b)
    if best <= 0.0:
        return best, 0.0  # overlapping (SAT is exact for convex polygons)
    # the closest-points direction, from A to B
    da, ax, ay = _closest_offset(world, 0, ka, ka, ka + kb)  # A's vertex to B's edge
    db, bx, by = _closest_offset(world, ka, ka + kb, 0, ka)  # B's vertex to A's edge
    if db < da:
        da = db
        ax = -bx
        ay = -by
    length = math.sqrt(da)
    if length > 0.0:
        nx = ax / length
        ny = ay / length
        gap = _gap_along(world, 0, ka, ka, ka + kb, nx, ny)
        best = max(best, gap)
        step = max(step, _advance(gap, max(nx * vx + ny * vy, 0.0) + spin, target))
    return best, step


@inline_kernel
def _sweep(
    local_verts,
    local_normals,
    a0,
    a1,
    b0,
    b1,
    pose_a0,
    pose_a1,
    pose_b0,
    pose_b1,
    target,
    tolerance,
    max_iterations,
    scratch,
):
    """Conservative advancement; returns (t, separation m, pose evaluations)."""
    ka = a1 - a0
    kb = b1 - b0
    if ka < 3 or kb < 3:
        raise ValueError("time_of_impact: each polygon needs at least 3 rows")
    if scratch.shape[0] < ka + kb:
        raise ValueError("time_of_impact: scratch has fewer rows than the two polygons' vertices")
    if not (
        target > 0.0 and tolerance > 0.0 and math.isfinite(target) and math.isfinite(tolerance)
    ):
        raise ValueError("time_of_impact: target and tolerance must be finite and > 0")
    if max_iterations < 1:
        raise ValueError("time_of_impact: max_iterations must be >= 1")
    # unpack once, as floats: a tuple pose may mix ints and floats, which Numba cannot index
    # with a loop variable
    xa0, ya0, qa0 = float(pose_a0[0]), float(pose_a0[1]), float(pose_a0[2])
    xa1, ya1, qa1 = float(pose_a1[0]), float(pose_a1[1]), float(pose_a1[2])
    xb0, yb0, qb0 = float(pose_b0[0]), float(pose_b0[1]), float(pose_b0[2])
    xb1, yb1, qb1 = float(pose_b1[0]), float(pose_b1[1]), float(pose_b1[2])
    if not math.isfinite(xa0 + ya0 + qa0 + xa1 + ya1 + qa1 + xb0 + yb0 + qb0 + xb1 + yb1 + qb1):
        raise ValueError("time_of_impact: non-finite pose")
    # velocities per unit t (m, rad per step) and the rotation part of every rate bound
    vx = (xa1 - xa0) - (xb1 - xb0)
    vy = (ya1 - ya0) - (yb1 - yb0)
    spin = abs(qa1 - qa0) * bounding_radius(local_verts, a0, a1) + abs(qb1 - qb0) * bounding_radius(
        local_verts, b0, b1
    )
    t = 0.0
    iteration = 0
    while True:
        angle_a = _lerp(qa0, qa1, t)
        angle_b = _lerp(qb0, qb1, t)
        _place(local_verts, a0, a1, _lerp(xa0, xa1, t), _lerp(ya0, ya1, t), angle_a, scratch, 0)
        _place(local_verts, b0, b1, _lerp(xb0, xb1, t), _lerp(yb0, yb1, t), angle_b, scratch, ka)
        separation, step = _bounds(
            scratch, ka, kb, local_normals, a0, b0, angle_a, angle_b, vx, vy, spin, target
        )
        iteration += 1
        if not math.isfinite(separation):
            raise ValueError("time_of_impact: non-finite separation (degenerate polygon?)")
        # out of iterations, this t is still safe: every t evaluated is (module docstring)
        if separation <= target + tolerance or t >= 1.0 or iteration >= max_iterations:
            return t, separation, iteration
        t = min(t + step, 1.0)


@lean_kernel
def time_of_impact(
    local_verts,
    local_normals,
    a0,
    a1,
    b0,
    b1,
    pose_a0,
    pose_a1,
    pose_b0,
    pose_b1,
    target,
    tolerance,
    max_iterations,
    scratch,
):
    """Earliest fraction of the step at which swept convex polygons A and B come within ``target``.

    local_verts, local_normals (V, 2) float64: packed body-frame vertices (m, about each body's
        centre of mass, CCW) and outward unit edge normals; A is rows a0..a1-1, B rows b0..b1-1.
    pose_a0, pose_a1, pose_b0, pose_b1: (x m, y m, angle rad) of each centre of mass at the start
        (t = 0) and end (t = 1) of the step, as 3-tuples of floats or (3,) float64 arrays. Position
        and angle are interpolated linearly; angles are not wrapped (angle1 - angle0 is the turn).
    target (m, > 0): the separation to stop at (e.g. the contact margin); tolerance (m, > 0): how
        far above target the stop may be; max_iterations >= 1: pose evaluations allowed.
    scratch: float64 array with at least (a1 - a0) + (b1 - b0) rows and 2 columns (``toi_scratch``).

    Returns (t, separation): separation (m) is a lower bound on the distance at t, equal to it up
    to round-off (the gap along the closest-points direction), or minus the penetration depth when
    the polygons overlap. Cases:
      - separation <= target + tolerance: contact at t. The distance at t is >= target and none
        of [0, t) comes within target, unless t = 0: they started within target + tolerance.
      - t == 1 and separation > target + tolerance: they stay farther than target all step.
      - t < 1 and separation > target + tolerance: max_iterations ran out; t is safe (before any
        contact) but not converged.
    Raises ValueError on non-finite poses, target or tolerance <= 0, or too small a scratch.
    """
    t, separation, _ = _sweep(
        local_verts,
        local_normals,
        a0,
        a1,
        b0,
        b1,
        pose_a0,
        pose_a1,
        pose_b0,
        pose_b1,
        target,
        tolerance,
        max_iterations,
        scratch,
    )
    return t, separation


@lean_kernel
def time_of_impact_counted(
    local_verts,
    local_normals,
    a0,
    a1,
    b0,
    b1,
    pose_a0,
    pose_a1,
    pose_b0,
    pose_b1,
    target,
    tolerance,
    max_iterations,
    scratch,
):
    """``time_of_impact`` that also returns how many pose evaluations it used: (t, separation,
    n)."""
    return _sweep(
        local_verts,
        local_normals,
        a0,
        a1,
        b0,
        b1,
        pose_a0,
        pose_a1,
        pose_b0,
        pose_b1,
        target,
        tolerance,
        max_iterations,
        scratch,
    )


@lean_kernel
def swept_aabb(local_verts, r0, r1, pose0, pose1, margin):
    """Axis-aligned box (m) holding polygon rows r0..r1-1 at every pose of the sweep from pose0 to
    pose1 (same conventions as ``time_of_impact``), grown by ``margin`` (m, >= 0).
    Returns (min_x, min_y, max_x, max_y).

    The intersection of two boxes that each hold the whole sweep:
    1. The body stays within its bounding radius R of its centre of mass, which moves along the
       segment between the end positions: that segment's box grown by R.
    2. A vertex at body-frame r sits at c(t) + Rot(angle(t)) r; the point at fraction t of the
       straight line between its two end positions is c(t) + ((1-t) Rot(angle0) + t Rot(angle1)) r.
       They differ by |r| |(1-t)(e^(i a(t)) - e^(i a0)) + t (e^(i a(t)) - e^(i a1))|, and a chord is
       no longer than its arc, so by at most |r| (2 t (1-t) |da|) <= R |da| / 2. The straight line
       stays in the box of the two end poses, so that box grown by R |da| / 2 holds every vertex,
       and hence (convexity) the whole polygon.
    """
    x0, y0, q0 = float(pose0[0]), float(pose0[1]), float(pose0[2])
    x1, y1, q1 = float(pose1[0]), float(pose1[1]), float(pose1[2])
    if not (math.isfinite(x0 + y0 + q0 + x1 + y1 + q1) and margin >= 0.0):
        raise ValueError("swept_aabb: non-finite pose or negative margin")
    radius = bounding_radius(local_verts, r0, r1)
    lo_x = np.inf
    lo_y = np.inf
    hi_x = -np.inf
    hi_y = -np.inf
    for end in range(2):
        x = x1 if end else x0
        y = y1 if end else y0
        c = math.cos(q1 if end else q0)
        s = math.sin(q1 if end else q0)
        for i in range(r0, r1):
            wx = c * local_verts[i, 0] - s * local_verts[i, 1] + x
            wy = s * local_verts[i, 0] + c * local_verts[i, 1] + y
            lo_x = min(lo_x, wx)
            lo_y = min(lo_y, wy)
            hi_x = max(hi_x, wx)
            hi_y = max(hi_y, wy)
    grow = 0.5 * radius * abs(q1 - q0)
    lo_x = max(lo_x - grow, min(x0, x1) - radius)
    lo_y = max(lo_y - grow, min(y0, y1) - radius)
    hi_x = min(hi_x + grow, max(x0, x1) + radius)
    hi_y = min(hi_y + grow, max(y0, y1) + radius)
    return lo_x - margin, lo_y - margin, hi_x + margin, hi_y + margin
