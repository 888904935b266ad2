"""sim/continuous.py (time of impact by conservative advancement) against known answers and the
sampling reference in tests/naive_toi.py.

What "right" means for ``time_of_impact(..., target, tolerance, ...) -> (t, separation)``:
  (a) never past the first contact: t <= the reference's first time at distance target, and the
      exact distance at t is >= target (unless the pair started within target + tolerance);
  (b) not early: when it reports a contact, the exact distance at t is <= target + tolerance, so t
      is no earlier than the reference's first time at distance target + tolerance;
  (c) a miss (t = 1, separation > target + tolerance) only when the reference never comes within
      target, and the separation returned is the exact distance at t.
Distances are compared with a slack of 1e-9 of the scene's size and times with 1e-9: far below the
tolerances under test (1e-4 .. 1e-3 of the size), far above float round-off.
"""

import math

import numpy as np
import pytest
from hypothesis import assume, event, given, settings
from hypothesis import strategies as st

import naive_toi  # tests/ is on sys.path under pytest's default rootdir-relative import mode
import sim
from sim.continuous import (
    bounding_radius,
    pose_at,
    separating_gap,
    swept_aabb,
    time_of_impact,
    time_of_impact_counted,
    toi_scratch,
)
from sim.sweep import surely_apart

MAX_ITERATIONS = 500
EPS_T = 1e-9
DT = 1.0 / 60.0  # s, the step the wall scenario is set in


def box(width, height):
    """Body-frame box about its centre, CCW."""
    w, h = 0.5 * width, 0.5 * height
    return np.array([[-w, -h], [w, -h], [w, h], [-w, h]])


def regular(n, radius, phase=0.0):
    """Body-frame regular n-gon about its centre, CCW; vertex 0 at angle ``phase``."""
    t = phase + 2.0 * math.pi * np.arange(n) / n
    return np.stack([radius * np.cos(t), radius * np.sin(t)], axis=1)


class Pair:
    """Two body-frame polygons packed the way the step loop packs bodies (B after a filler body,
    so that row ranges not starting at 0 are exercised), and the reference on the same pair."""

    def __init__(self, local_a, local_b):
        self.a = np.asarray(local_a, dtype=np.float64)
        self.b = np.asarray(local_b, dtype=np.float64)
        filler = box(1.0, 1.0)
        polys = [self.a, filler, self.b]
        self.verts = np.ascontiguousarray(np.vstack(polys))
        self.normals = np.ascontiguousarray(
            np.vstack([naive_toi.outward_normals(p) for p in polys])
        )
        ka, kf = len(self.a), len(filler)
        self.rows = (0, ka, ka + kf, ka + kf + len(self.b))
        self.scratch = toi_scratch(max(ka, len(self.b)))

    def toi(self, pa0, pa1, pb0, pb1, target, tolerance, max_iterations=MAX_ITERATIONS):
        """(t, separation, iterations) from the kernel."""
        a0, a1, b0, b1 = self.rows
        return time_of_impact_counted(
            self.verts,
            self.normals,
            a0,
            a1,
            b0,
            b1,
            pa0,
            pa1,
            pb0,
            pb1,
            target,
            tolerance,
            max_iterations,
            self.scratch,
        )

    def first(self, poses, threshold):
        return naive_toi.first_time(self.a, self.b, *poses, threshold)

    def distance(self, poses, t):
        return naive_toi.distance(self.a, self.b, *poses, t)


def check(pair, poses, target, tolerance, size, max_iterations=MAX_ITERATIONS):
    """Run the kernel on one sweep and assert (a)-(c) of the module docstring against the
    reference. Returns (t, separation, iterations, reference first time at target)."""
    eps = 1e-9 * size
    t, sep, n = pair.toi(*poses, target, tolerance, max_iterations)
    assert 0.0 <= t <= 1.0 and math.isfinite(sep)
    assert n <= max_iterations
    t_ref, hit_ref = pair.first(poses, target)
    d = pair.distance(poses, t)
    started_close = pair.distance(poses, 0.0) <= target + tolerance
    # (a) never past the first contact, never inside
    assert t <= t_ref + EPS_T, (t, t_ref)
    if not (t == 0.0 and started_close):
        assert d >= target - eps, (t, d, target)
    if sep >= 0.0:
        assert abs(sep - d) <= eps, (sep, d)  # the separation is the distance at t
    if sep <= target + tolerance:
        # (b) a contact: genuine, and not before the first time within target + tolerance
        assert d <= target + tolerance + eps, (t, d, target + tolerance)
        t_hi, _ = pair.first(poses, target + tolerance + eps)
        assert t >= t_hi - EPS_T, (t, t_hi)
    elif t == 1.0:
        # (c) a miss
        assert not hit_ref, (t_ref, sep)
    else:
        pytest.fail(f"not converged in {max_iterations} iterations: t={t}, separation={sep}")
    return t, sep, n, t_ref


# ---- a fast box and a thin wall -----------------------------------------------------------------
# 0.2 m box at 200 m/s: 3.33 m per step of 1/60 s, 17 of its own widths, against a 5 cm wall. Every
# length scales with `scale`, so 0.005 is a 1 mm box and 500 a 100 m box.
BOX = 0.2
WALL = (0.05, 2.0)
SPEED = 200.0
SCALES = [0.005, 1.0, 500.0]


def wall_case(scale, gap):
    """Pair and poses: the box's right face starts ``gap`` (m) left of the wall's left face."""
    pair = Pair(box(BOX * scale, BOX * scale), box(WALL[0] * scale, WALL[1] * scale))
    travel = SPEED * DT * scale
    wall_x = 0.5 * BOX * scale + gap + 0.5 * WALL[0] * scale
    return pair, ((0.0, 0.0, 0.0), (travel, 0.0, 0.0), (wall_x, 0.0, 0.0), (wall_x, 0.0, 0.0))


@pytest.mark.parametrize("scale", SCALES)
def test_fast_box_stops_before_a_thin_wall_from_every_phase(scale):
    target, tolerance = 0.005 * scale, 1e-4 * scale
    travel = SPEED * DT * scale
    # the wall anywhere along the step's travel, and a few phases right at the edges
    gaps = np.concatenate(
        [
            np.linspace(0.0, 1.05 * travel, 25),
            [
                0.5 * target,
                target,
                target + 0.5 * tolerance,
                travel + target,
                travel + target + 2.0 * tolerance,
            ],
        ]
    )
    for gap in gaps:
        pair, poses = wall_case(scale, gap)
        t, sep, n, _ = check(pair, poses, target, tolerance, scale)
        # known answer: face against face, the box's right face stops `target` before the wall
        expected = min(max(gap - target, 0.0) / travel, 1.0)
        assert abs(t - expected) <= tolerance / travel + EPS_T, (gap, t, expected)
        right_face = t * travel + 0.5 * BOX * scale
        wall_left = poses[2][0] - 0.5 * WALL[0] * scale
        # before the wall, never in or past it: at least `target` short (or where it started)
        assert wall_left - right_face >= min(gap, target) - 1e-9 * scale
        if target < gap < travel:
            assert wall_left - right_face == pytest.approx(target, abs=tolerance + 1e-9 * scale)
        assert n <= 2  # the rate bound is exact here


@pytest.mark.parametrize("scale", SCALES)
def test_tumbling_fast_box_never_passes_the_wall(scale):
    """The same shot with the box turning 0.5 rad in the step: the rate bound is no longer exact,
    the answer comes from the reference."""
    target, tolerance = 0.005 * scale, 1e-4 * scale
    travel = SPEED * DT * scale
    for gap in np.linspace(0.1 * travel, 0.95 * travel, 9):
        pair, (pa0, pa1, pb0, pb1) = wall_case(scale, gap)
        poses = ((0.0, 0.02 * scale, 0.3), (travel, -0.03 * scale, -0.2), pb0, pb1)
        t, sep, n, t_ref = check(pair, poses, target, tolerance, scale)
        assert sep <= target + tolerance and t_ref < 1.0
        assert n <= 10


@pytest.mark.parametrize("scale", SCALES)
def test_box_passing_beside_the_wall_is_not_stopped(scale):
    target, tolerance = 0.005 * scale, 1e-4 * scale
    travel = SPEED * DT * scale
    pair = Pair(box(BOX * scale, BOX * scale), box(WALL[0] * scale, WALL[1] * scale))
    wall_x = 0.5 * travel
    for clearance in (target + 2.0 * tolerance, 2.0 * target, 0.5 * BOX * scale):
        y = 0.5 * WALL[1] * scale + 0.5 * BOX * scale + clearance  # just over the top
        poses = ((0.0, y, 0.0), (travel, y, 0.0), (wall_x, 0.0, 0.0), (wall_x, 0.0, 0.0))
        t, sep, n, _ = check(pair, poses, target, tolerance, scale)
        assert t == 1.0 and sep > target + tolerance
        # moving parallel to the wall's top face, that face's axis proves the miss at once
        assert n <= 2


# ---- spinning bodies ----------------------------------------------------------------------------
PLANK = (2.0, 0.05)  # m, long and thin, spinning about its centre
POST = 0.1  # m, square post


def plank_contact_angle(scale, post_x, target, start):
    """Known answer: the plank (turning CCW, leading face at distance h from the centre) first
    comes within target of the post's near lower corner c when n(angle).c = h + target, with
    n(angle) = (-sin angle, cos angle): |c| sin(polar(c) - angle) = h + target. The plank is
    symmetric, so either half gets there: the first such angle >= start, modulo pi."""
    h = 0.5 * PLANK[1] * scale
    cx, cy = (post_x - 0.5 * POST) * scale, -0.5 * POST * scale
    angle = math.atan2(cy, cx) - math.asin((h + target) / math.hypot(cx, cy))
    return angle + math.pi * math.ceil((start - angle) / math.pi)


@pytest.mark.parametrize("scale", SCALES)
@pytest.mark.parametrize("turn", [0.5, 3.0, 10.0, 30.0])  # rad per step (30: ~5 turns)
@pytest.mark.parametrize("plank_is", ["A", "B"])
def test_spinning_plank_into_a_post(scale, turn, plank_is):
    target, tolerance = 0.005 * scale, 1e-4 * scale
    plank, post_shape = box(PLANK[0] * scale, PLANK[1] * scale), box(POST * scale, POST * scale)
    start = -0.3 - 0.1 * turn  # rad, plank below the post, turning CCW
    post = (0.85 * scale, 0.0, 0.0)
    spin = ((0.0, 0.0, start), (0.0, 0.0, start + turn))
    if plank_is == "A":
        pair, poses = Pair(plank, post_shape), spin + (post, post)
    else:  # the distance is symmetric: same answer
        pair, poses = Pair(post_shape, plank), (post, post) + spin
    t, sep, n, _ = check(pair, poses, target, tolerance, scale)
    expected = (plank_contact_angle(scale, 0.85, target, start) - start) / turn
    # the stop is within `tolerance` of the distance, i.e. at most tolerance / (the speed of the
    # corner towards the face) early: |c| cos(polar(c) - angle) per radian, ~1% margin
    corner_speed = turn * math.hypot(0.8, 0.05) * scale * 0.99  # m per unit t
    assert expected - tolerance / corner_speed - EPS_T <= t <= expected + EPS_T, (t, expected)
    assert n <= 12


@pytest.mark.parametrize("scale", SCALES)
def test_spinning_plank_past_a_post_out_of_reach(scale):
    target, tolerance = 0.005 * scale, 1e-4 * scale
    pair = Pair(box(PLANK[0] * scale, PLANK[1] * scale), box(POST * scale, POST * scale))
    post = (1.2 * scale, 0.0, 0.0)  # near face at 1.15, the plank reaches 1.0003
    poses = ((0.0, 0.0, 0.0), (0.0, 0.0, 7.0), post, post)
    t, sep, n, _ = check(pair, poses, target, tolerance, scale)
    assert t == 1.0
    assert n <= 200


def test_translating_and_spinning_plank_against_a_moving_post():
    pair = Pair(box(*PLANK), box(POST, POST))
    poses = ((-1.6, 0.3, 0.0), (1.4, -0.2, 4.0), (0.0, 0.0, 0.0), (0.2, 0.3, -0.5))
    t, sep, n, t_ref = check(pair, poses, 0.005, 1e-4, 1.0)
    assert sep <= 0.005 + 1e-4 and 0.0 < t < 1.0


def test_running_out_of_iterations_returns_a_safe_time():
    target, tolerance = 0.005, 1e-4
    pair = Pair(box(*PLANK), box(POST, POST))
    poses = ((0.0, 0.0, -1.3), (0.0, 0.0, 8.7), (0.85, 0.0, 0.0), (0.85, 0.0, 0.0))
    t_full, _, n_full = pair.toi(*poses, target, tolerance)
    assert n_full > 2
    t, sep, n = pair.toi(*poses, target, tolerance, max_iterations=2)
    assert n == 2 and 0.0 < t < t_full
    assert sep > target + tolerance  # reported as not converged
    assert pair.distance(poses, t) == pytest.approx(sep, abs=1e-9)
    t1, sep1, n1 = pair.toi(*poses, target, tolerance, max_iterations=1)
    assert (t1, n1) == (0.0, 1) and sep1 > target + tolerance


# ---- already touching ---------------------------------------------------------------------------
def test_already_within_target_at_the_start_gives_t_zero():
    target, tolerance = 0.005, 1e-4
    pair = Pair(box(0.2, 0.2), box(0.05, 2.0))
    for gap, expected_sep in (
        (0.5 * target, 0.5 * target),  # apart, but within target
        (target + 0.5 * tolerance, target + 0.5 * tolerance),  # in the band
        (0.0, 0.0),  # touching
        (-0.01, -0.01),
    ):  # 1 cm deep
        wall_x = 0.1 + gap + 0.025
        poses = ((0.0, 0.0, 0.0), (3.0, 0.0, 1.0), (wall_x, 0.0, 0.0), (wall_x, 0.0, 0.0))
        t, sep, n = pair.toi(*poses, target, tolerance)
        assert (t, n) == (0.0, 1)
        assert sep == pytest.approx(expected_sep, abs=1e-12)  # overlap: minus the depth
    # moving away from a wall it starts touching: still t = 0 (within target at t = 0)
    poses = ((0.0, 0.0, 0.0), (-3.0, 0.0, 0.0), (0.125, 0.0, 0.0), (0.125, 0.0, 0.0))
    assert pair.toi(*poses, target, tolerance)[0] == 0.0


# ---- hexagon and triangle -----------------------------------------------------------------------
def test_hexagon_corner_onto_triangle_apex():
    """Corner against corner, the case where the SAT gap underestimates the distance (here by
    cos 30 deg and cos 60 deg): the stop must still be within tolerance of the contact."""
    target, tolerance = 0.005, 1e-4
    hexagon = regular(6, 0.3, phase=-math.pi / 2)  # a vertex pointing straight down
    triangle = regular(3, 0.2, phase=math.pi / 2)  # apex pointing straight up
    triangle -= naive_toi.centroid(triangle)
    pair = Pair(hexagon, triangle)
    gap, travel = 1.0, 2.0  # m: apex to corner, descent
    y0 = 0.2 + gap + 0.3  # hexagon centre above the apex
    poses = ((0.0, y0, 0.0), (0.0, y0 - travel, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    t, sep, n, _ = check(pair, poses, target, tolerance, 1.0)
    assert t == pytest.approx((gap - target) / travel, abs=tolerance / travel)
    assert n <= 3


@pytest.mark.parametrize("case", range(6))
def test_spinning_hexagon_against_a_spinning_triangle(case):
    rng = np.random.default_rng(case)
    pair = Pair(regular(6, 0.3, phase=rng.uniform(0, 1)), regular(3, 0.25, phase=rng.uniform(0, 2)))
    angle = rng.uniform(0, 2 * math.pi)
    start = 1.2 * np.array([math.cos(angle), math.sin(angle)])
    end = -start + rng.normal(0.0, 0.2, 2)
    poses = (
        (start[0], start[1], 0.0),
        (end[0], end[1], rng.uniform(-6, 6)),
        (0.0, 0.0, 0.0),
        (0.1, -0.1, rng.uniform(-3, 3)),
    )
    t, sep, n, t_ref = check(pair, poses, 0.002, 1e-4, 1.0)
    assert t_ref < 1.0 and sep <= 0.002 + 1e-4


# ---- random convex polygons and motions ---------------------------------------------------------
@st.composite
def convex_polygons(draw, size):
    """Body-frame convex CCW polygon about its centroid: 3-10 points on an ellipse at random,
    strictly increasing angles (no gap under a tenth of the mean, so no near-duplicates)."""
    n = draw(st.integers(3, 10))
    weights = np.array(draw(st.lists(st.floats(1.0, 10.0), min_size=n, max_size=n)))
    t = (
        draw(st.floats(0.0, 2 * math.pi))
        + 2 * math.pi * (np.cumsum(weights) - weights[0]) / weights.sum()
    )
    aspect = draw(st.floats(0.15, 1.0))
    v = np.stack([size * np.cos(t), aspect * size * np.sin(t)], axis=1)
    return v - naive_toi.centroid(v)


@st.composite
def sweeps(draw):
    """A random pair and sweep, aimed so that about half of them hit: A starts clear of B and
    moves past B's centre with a random miss distance, both turning; B static half of the time."""
    size = 10.0 ** draw(st.floats(-3.0, 2.0))  # m, 1 mm .. 100 m
    a = draw(convex_polygons(size))
    b = draw(convex_polygons(size * draw(st.floats(0.3, 3.0))))
    reach = np.hypot(*a.T).max() + np.hypot(*b.T).max()
    heading = draw(st.floats(0.0, 2 * math.pi))
    direction = np.array([math.cos(heading), math.sin(heading)])
    side = np.array([-direction[1], direction[0]])
    start = -direction * (reach + size * draw(st.floats(0.0, 3.0)))
    miss = side * reach * draw(st.floats(-1.5, 1.5))
    travel = draw(st.floats(0.3, 3.0)) * 2.0 * reach
    end = start + miss + direction * travel
    qa0 = draw(st.floats(-math.pi, math.pi))
    qb0 = draw(st.floats(-math.pi, math.pi))
    pose_b1 = (0.0, 0.0, qb0)
    if draw(st.booleans()):
        pose_b1 = (
            size * draw(st.floats(-2.0, 2.0)),
            size * draw(st.floats(-2.0, 2.0)),
            qb0 + draw(st.floats(-6.0, 6.0)),
        )
    poses = (
        (start[0], start[1], qa0),
        (end[0], end[1], qa0 + draw(st.floats(-8.0, 8.0))),
        (0.0, 0.0, qb0),
        pose_b1,
    )
    target = size * draw(st.floats(0.002, 0.05))
    return Pair(a, b), poses, target, 1e-3 * size, size


@settings(max_examples=120, deadline=None)
@given(sweeps())
def test_random_polygons_and_motions_against_the_reference(case):
    pair, poses, target, tolerance, size = case
    assume(pair.distance(poses, 0.0) > target + tolerance)  # t = 0 cases are tested above
    t, sep, n, t_ref = check(pair, poses, target, tolerance, size)
    event("hit" if sep <= target + tolerance else "miss")
    event(f"iterations {'<= 5' if n <= 5 else '<= 20' if n <= 20 else '> 20'}")


@settings(max_examples=150, deadline=None)
@given(sweeps(), st.floats(0.0, 1.0))
def test_separating_gap_decides_a_deep_overlap_as_a_zero_length_sweep_does(case, t):
    """The step's sweep asks of a fast body and an awake neighbour only whether they end the step
    deep inside each other (``separating_gap`` < -deep), where it used to ask a sweep of zero
    length: overlapping, both give minus the penetration depth (bit for bit); apart, the gap is a
    lower bound on the distance, and > 0 like the sweep's separation."""
    pair, poses, target, tolerance, size = case
    a0, a1, b0, b1 = pair.rows
    pa = pose_at(poses[0], poses[1], t)  # poses along the sweep: overlapping ones among them
    pb = pose_at(poses[2], poses[3], t)
    gap = separating_gap(pair.verts, pair.normals, a0, a1, b0, b1, pa, pb, pair.scratch)
    _, separation, _ = pair.toi(pa, pa, pb, pb, target, tolerance, 1)
    distance = naive_toi.distance(pair.a, pair.b, pa, pa, pb, pb, 0.0)
    event("overlapping" if distance == 0.0 else "apart")
    if separation <= 0.0:
        assert gap == separation
    else:
        assert 0.0 < gap <= separation
        assert gap <= distance + 1e-9 * size


def test_pose_at_is_the_pose_the_sweep_stopped_at():
    """Moving the body back with ``pose_at`` gives the pose whose distance the kernel reported."""
    pair = Pair(box(*PLANK), box(POST, POST))
    poses = ((-1.6, 0.3, 0.2), (1.4, -0.2, 4.0), (0.0, 0.0, 0.0), (0.2, 0.3, -0.5))
    t, sep, _ = pair.toi(*poses, 0.005, 1e-4)
    assert 0.0 < t < 1.0
    stopped_a, stopped_b = pose_at(poses[0], poses[1], t), pose_at(poses[2], poses[3], t)
    assert naive_toi.distance(
        pair.a, pair.b, stopped_a, stopped_a, stopped_b, stopped_b, 0.0
    ) == pytest.approx(sep, abs=1e-12)
    assert pose_at(poses[0], poses[1], 0.0) == poses[0]  # exact at both ends
    assert pose_at(poses[0], poses[1], 1.0) == poses[1]


def test_pose_arrays_and_tuples_give_the_same_answer():
    pair, poses = wall_case(1.0, 1.0)
    as_tuples = pair.toi(*poses, 0.005, 1e-4)
    as_arrays = pair.toi(*[np.array(p, dtype=np.float64) for p in poses], 0.005, 1e-4)
    assert as_tuples == as_arrays
    a0, a1, b0, b1 = pair.rows
    assert (
        time_of_impact(
            pair.verts,
            pair.normals,
            a0,
            a1,
            b0,
            b1,
            *poses,
            0.005,
            1e-4,
            MAX_ITERATIONS,
            pair.scratch,
        )
        == as_tuples[:2]
    )


def test_bad_input_raises_instead_of_returning_nan():
    pair, poses = wall_case(1.0, 1.0)
    bad = ((math.nan, 0.0, 0.0),) + poses[1:]
    with pytest.raises(ValueError, match="non-finite pose"):
        pair.toi(*bad, 0.005, 1e-4)
    for target, tolerance in ((0.0, 1e-4), (0.005, 0.0), (math.inf, 1e-4), (-1.0, 1e-4)):
        with pytest.raises(ValueError, match="target and tolerance"):
            pair.toi(*poses, target, tolerance)
    with pytest.raises(ValueError, match="max_iterations"):
        pair.toi(*poses, 0.005, 1e-4, max_iterations=0)
    a0, a1, b0, b1 = pair.rows
    with pytest.raises(ValueError, match="scratch"):
        time_of_impact(
            pair.verts,
            pair.normals,
            a0,
            a1,
            b0,
            b1,
            *poses,
            0.005,
            1e-4,
            MAX_ITERATIONS,
            toi_scratch(3),
        )


# ---- swept boxes --------------------------------------------------------------------------------
def test_swept_aabb_of_a_translation_is_the_union_of_the_end_boxes():
    verts = box(0.2, 0.1)
    lo_x, lo_y, hi_x, hi_y = swept_aabb(verts, 0, 4, (1.0, 2.0, 0.0), (4.0, 1.0, 0.0), 0.0)
    assert (lo_x, lo_y, hi_x, hi_y) == pytest.approx((0.9, 0.95, 4.1, 2.05), abs=1e-12)
    assert swept_aabb(verts, 0, 4, (1.0, 2.0, 0.0), (4.0, 1.0, 0.0), 0.5) == pytest.approx(
        (0.4, 0.45, 4.6, 2.55), abs=1e-12
    )


def test_swept_aabb_of_a_full_turn_is_the_bounding_circle_box():
    verts = box(2.0, 0.5)
    r = bounding_radius(verts, 0, 4)
    assert r == pytest.approx(math.hypot(1.0, 0.25))
    assert swept_aabb(
        verts, 0, 4, (1.0, -1.0, 0.3), (1.0, -1.0, 0.3 + 2 * math.pi), 0.0
    ) == pytest.approx((1.0 - r, -1.0 - r, 1.0 + r, -1.0 + r), abs=1e-12)


@settings(max_examples=100, deadline=None)
@given(sweeps())
def test_swept_aabb_holds_the_body_all_sweep_and_is_not_loose(case):
    pair, (pa0, pa1, _, _), _, _, size = case
    ka = len(pair.a)
    box_ = swept_aabb(pair.verts, 0, ka, pa0, pa1, 0.0)
    ts = np.linspace(0.0, 1.0, 4001)
    w = naive_toi.world(pair.a, naive_toi.poses(pa0, pa1, ts)).reshape(-1, 2)
    eps = 1e-9 * (size + np.abs(w).max())
    true_box = (w[:, 0].min(), w[:, 1].min(), w[:, 0].max(), w[:, 1].max())
    assert box_[0] <= true_box[0] + eps and box_[1] <= true_box[1] + eps
    assert box_[2] >= true_box[2] - eps and box_[3] >= true_box[3] - eps
    # no looser than either bound it is built from (here: half the turn times the radius)
    r = np.hypot(*pair.a.T).max()
    slack = max(
        true_box[0] - box_[0], true_box[1] - box_[1], box_[2] - true_box[2], box_[3] - true_box[3]
    )
    # (the disc bound: the centroid, the body-frame origin here, is inside the polygon)
    assert slack <= min(0.5 * r * abs(pa1[2] - pa0[2]), r) + eps


# ---- the sweep stage's shortcut: pairs surely apart at the end are not measured ------------------
@settings(max_examples=200, deadline=None)
@given(
    convex_polygons(1.0),
    convex_polygons(1.0),
    st.floats(0.0, 2.5),
    st.floats(0.0, 2 * math.pi),
    st.floats(-math.pi, math.pi),
    st.floats(-math.pi, math.pi),
)
def test_surely_apart_is_never_said_of_touching_polygons(a, b, distance, heading, qa, qb):
    # the shortcut only ever skips a pair that is apart: whenever it says "apart", the exact
    # distance between the polygons is positive (its reach is the sum of their extents, as the
    # stage passes it, without the stage's slop allowance)
    pair = Pair(a, b)
    pose_a = (0.0, 0.0, qa)
    pose_b = (distance * math.cos(heading), distance * math.sin(heading), qb)
    reach = np.hypot(*a.T).max() + np.hypot(*b.T).max()
    apart = surely_apart(pose_a, pose_b, reach)
    event(f"surely apart: {apart}")
    if apart:
        assert pair.distance((pose_a, pose_a, pose_b, pose_b), 0.0) > 0.0


def test_surely_apart_says_nothing_inside_the_circles():
    # two unit boxes 1.2 m apart do not touch, but their circles (radius 0.707 m) meet: the
    # shortcut must leave such a pair to the time-of-impact evaluation
    reach = 2 * math.hypot(0.5, 0.5)
    assert not surely_apart((0.0, 0.0, 0.0), (1.2, 0.0, 0.0), reach)
    assert surely_apart((0.0, 0.0, 0.0), (1.5, 0.0, 0.0), reach)
    assert not surely_apart((0.0, 0.0, 0.0), (1.0, 1.0, 0.0), reach)  # sqrt(2) < 1.414...


def test_a_block_falling_together_is_swept_without_measuring_a_pair():
    # nine unit boxes 2 m apart, all falling at 45 m/s (0.75 m a step at 1/60 s: swept)
    block = [
        sim.Body.box(1.0, 1.0, position=(2.0 * c, 500.0 + 2.0 * r), velocity=(0.0, -45.0))
        for r in range(3)
        for c in range(3)
    ]
    world = sim.World(sim.Scene(bodies=block), dt=DT)
    world.step(5)
    seen = world.inspect()
    assert seen.sweeps == 45  # every box, every step
    assert seen.toi_pairs == 0  # each met its neighbours' boxes, none closer than 2 m
    assert seen.impacts == 0


def test_fast_boxes_closer_than_their_circles_are_still_measured():
    # two boxes falling side by side, their centres 1.05 m apart, do not touch, but the shortcut
    # cannot tell: each sweep measures the other (a shortcut that skipped every awake pair fails
    # here)
    pair = [
        sim.Body.box(1.0, 1.0, position=(1.05 * k, 500.0), velocity=(0.0, -45.0)) for k in range(2)
    ]
    world = sim.World(sim.Scene(bodies=pair), dt=DT)
    world.step(3)
    seen = world.inspect()
    assert seen.sweeps == 6
    assert seen.toi_pairs == 6
    assert seen.impacts == 0
