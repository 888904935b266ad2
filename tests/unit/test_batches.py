"""How the soft step lays contacts out in batches (sim.soft_step.colour), checked from the public
inspection view against a slow recount; and the arms pass against a slow recomputation."""

import math

import numpy as np
import pytest

# tests/ is on sys.path (pytest's rootdir-relative imports)
from naive import complementary_impulses, greedy_colours, moved_contact_arms

import sim
from sim import soft_step
from sim.data import DPX, DPY, DQC, DQS, STATE_COLUMNS
from sim.soft_step import HARD_RATIO, LANES
from sim.soft_step import batches
from sim.soft_step import layout as L


def hard_touching_pairs(inspection):
    """The active pairs that touch a body in a contact of mass ratio > HARD_RATIO (both bodies
    moved by the solver): the contacts that get the extra relax sweeps."""
    c = inspection.contacts
    inv = inspection.solver_inv_mass
    pairs = {(int(a), int(b)) for a, b in zip(c["body_a"], c["body_b"])}

    def movable(i):
        return 0 <= i < len(inv) and inv[i] > 0.0  # the floor and static bodies are not

    marked = set()
    for a, b in pairs:
        if (
            movable(a)
            and movable(b)
            and (inv[a] > HARD_RATIO * inv[b] or inv[b] > HARD_RATIO * inv[a])
        ):
            marked |= {a, b}
    return [p for p in pairs if any(movable(i) and i in marked for i in p)], len(pairs)


def test_hard_contacts_share_batches():
    """Random polygons (masses 0.005-0.39 kg) settling: the contacts that need the extra sweeps
    are packed first in each colour, so at most one part-filled hard batch per colour. Measured
    before packing: 41 of 51 batches hard (the sweeps went to nearly every contact); after: 13."""
    w = sim.World(sim.scenes.drop(200, seed=0))
    w.step(240)
    info = w.inspect()
    touching, n_pairs = hard_touching_pairs(info)
    assert n_pairs == info.n_active
    assert len(touching) > 0
    assert info.n_hard_batches <= math.ceil(len(touching) / LANES) + info.n_colours
    assert info.n_hard_batches < info.n_batches / 2


def test_uniform_masses_have_no_hard_batches():
    w = sim.World(sim.scenes.pyramid(10))
    w.step(5)
    info = w.inspect()
    assert hard_touching_pairs(info)[0] == []
    assert info.n_hard_batches == 0
    assert info.n_batches > 0


def test_a_heavy_box_on_light_ones_gets_hard_batches():
    light = [sim.Body.box(1, 1, position=(x, 0.5)) for x in (-1.2, 0.0, 1.2)]
    heavy = sim.Body.box(1, 1, position=(0.0, 1.5), density=100.0)
    w = sim.World(sim.Scene(bodies=light + [heavy]))
    w.step(5)
    info = w.inspect()
    assert len(hard_touching_pairs(info)[0]) >= 2  # heavy on light, and light on the floor
    assert info.n_hard_batches >= 1
    assert np.isfinite(w.positions).all()


def test_contacts_with_what_cannot_move_are_solved_last():
    """Box2D v3's order: in every sweep the contacts between two movable bodies come first, then
    those with the floor, a static body or a frozen one, so that a sweep ends with the bodies
    pushed out of their supports (solved first, a support was undone by the contacts above it:
    a box of a pile landing at 26 m/s drove the one under it 14 cm into the floor)."""
    for scene, freeze in (
        (sim.scenes.pyramid(8), "off"),
        (sim.scenes.drop(60, seed=2), "off"),
        (sim.scenes.drop(60, seed=2), "paper"),
    ):
        world = sim.World(scene, freeze=freeze)
        seen = 0
        for _ in range(12):
            world.step(9)
            events = len(world.events)
            world.step(1)
            if len(world.events) > events:
                continue  # a body froze or woke after the colouring: the view is later
            i = world.inspect()
            movable = set(int(b) for b in i.awake) & set(np.flatnonzero(i.solver_inv_mass > 0))
            between = [c for (a, b), c in i.pair_colour.items() if a in movable and b in movable]
            support = [
                c for (a, b), c in i.pair_colour.items() if not (a in movable and b in movable)
            ]
            assert len(i.pair_colour) == i.n_active
            if between and support:
                assert max(between) < min(support), (world.step_count, freeze)
                seen += 1
        assert seen > 0


def falling_boxes():
    """Equal unit boxes (one mass, so the colouring may be kept: see below) landing over ~2 s: a
    row of 4 on the floor, 3 dropped over its gaps, 2 over theirs, one more beside them."""
    boxes = [sim.Body.box(1, 1, position=(1.125 * k, 0.5)) for k in range(4)]
    boxes += [sim.Body.box(1, 1, position=(1.125 * k + 0.5625, 2.0 + 0.3 * k)) for k in range(3)]
    boxes += [sim.Body.box(1, 1, position=(1.125 * k + 1.125, 4.0 + 0.5 * k)) for k in range(2)]
    boxes += [sim.Body.box(1, 1, position=(6.0, 1.5))]
    return sim.Scene(bodies=boxes, name="falling_boxes")


def test_every_step_s_colouring_is_the_one_colouring_from_scratch_gives():
    """``soft_step.colour`` keeps the step before's colouring when the active contacts and the
    rows of their bodies are the same (a resting stack); it must still be what colouring this
    step from scratch gives (``naive.greedy_colours``) while contacts come and go, bodies freeze
    and wake, and ``paper`` holds a box still (ROTATION_STABLE: immovable while awake). Worlds
    with masses beyond HARD_RATIO always colour afresh (their hard batches depend on the
    masses), so these scenes have one mass each. Checked after every step in which no body froze
    or woke (such a step coloured before the change: its view is later than its colouring)."""
    checked = 0
    for scene, freeze, steps in (
        (falling_boxes(), "off", 200),
        (falling_boxes(), "extended", 200),
        (falling_boxes(), "sleep", 200),
        (falling_boxes(), "paper", 200),
        (sim.scenes.seed_fig3(), "paper", 150),
        (sim.scenes.pyramid(6), "paper", 100),
        (sim.scenes.pyramid(6), "off", 40),
    ):
        world = sim.World(scene, freeze=freeze)
        assert world.masses.max() <= HARD_RATIO * world.masses.min()
        for _ in range(steps):
            events = len(world.events)
            world.step(1)
            if len(world.events) > events:
                continue
            i = world.inspect()
            pairs = list(dict.fromkeys(zip(i.contacts["body_a"], i.contacts["body_b"])))
            pairs = [(int(a), int(b)) for a, b in pairs]
            movable = {int(b) for b in i.awake if i.solver_inv_mass[b] > 0.0}
            assert i.pair_colour == greedy_colours(pairs, movable), (
                scene.name,
                freeze,
                world.step_count,
            )
            checked += 1
    assert checked > 900


def cross(r, d):
    """r x d of 2-vectors (the z component)."""
    return float(r[0] * d[1] - r[1] * d[0])


def test_the_arms_pass_matches_a_slow_recomputation_from_world_positions():
    """``soft_step.arms`` (once per pose; the sweeps read what it leaves) against
    ``naive.moved_contact_arms``: random anchors, normals, start separations and motions, lane 7
    against the dummy row (the floor: it never moves); the normal's line of action anywhere from
    A's anchor to B's (lanes 0 and 1 at the ends), friction's half way. For both points of every
    lane: the arms crossed with the normal and with the tangent, and the separation now."""
    rng = np.random.default_rng(5)
    wide = np.zeros(L.STRIDE)
    state = np.zeros((2 * LANES + 1, STATE_COLUMNS))
    state[0, DQC] = 1.0  # the dummy row: no motion
    lane_row = np.zeros(2 * LANES, dtype=np.uint64)
    expected = {}
    for lane in range(LANES):
        ra_row = 0 if lane == 7 else 1 + 2 * lane
        rb_row = 2 + 2 * lane
        lane_row[lane], lane_row[LANES + lane] = ra_row, rb_row
        angle = rng.uniform(-np.pi, np.pi)
        n = np.array([np.cos(angle), np.sin(angle)])
        t = np.array([n[1], -n[0]])
        wide[L.NX + lane], wide[L.NY + lane] = n
        toward = (0.0, 1.0)[lane] if lane < 2 else rng.uniform()
        wide[L.TOWARD + lane] = toward
        ca, cb = rng.normal(size=2), rng.normal(size=2)
        motions = {}
        for row in (ra_row, rb_row):
            m = (0.0, 0.0, 0.0) if row == 0 else (*rng.normal(scale=0.05, size=2), rng.normal(0.2))
            motions[row] = m
            state[row, DPX], state[row, DPY] = m[0], m[1]
            state[row, DQC], state[row, DQS] = np.cos(m[2]), np.sin(m[2])
        for point in (0, 1):
            p = int(L.POINT2) * point + lane
            anchor_a = rng.normal(scale=0.5, size=2)
            separation = rng.uniform(-0.02, 0.02)
            moved = (ca, anchor_a, n, separation, cb, motions[ra_row], motions[rb_row])
            na, nb, sep, rb = moved_contact_arms(*moved, n, toward)
            fa, fb, _, _ = moved_contact_arms(*moved, t, 0.5)
            wide[p + L.RAX1], wide[p + L.RAY1] = anchor_a
            wide[p + L.RBX1], wide[p + L.RBY1] = rb
            wide[p + L.BASE1] = separation - float((rb - anchor_a) @ n)
            expected[p] = {
                L.RNA1: cross(na, n),
                L.RNB1: cross(nb, n),
                L.RTA1: cross(fa, t),
                L.RTB1: cross(fb, t),
                L.SEP1: sep,
            }
    soft_step.arms(1, wide, lane_row, state, np.zeros(1, np.uint8))  # a MOVABLE batch
    for p, fields in expected.items():
        for field, value in fields.items():
            name = L.FIELD_NAMES[int(field) // LANES]
            assert wide[p + field] == pytest.approx(value, rel=1e-9, abs=1e-12), (p, name)


# ---- a lane's two rows: one complementarity problem ------------------------------------------
def _two_row_cases(seed, n):
    """n random lanes: (a, r, K) with K symmetric positive definite (two points of random arms on
    bodies of random masses) and impulses a >= 0."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        inv_mass = rng.uniform(0.0, 2.0, 2)
        inv_inertia = rng.uniform(0.05, 12.0, 2)
        arms = rng.uniform(-1.0, 1.0, (2, 2))  # (point, body): arm x normal
        K = inv_mass.sum() + np.einsum("b,pb,qb->pq", inv_inertia, arms, arms)
        yield rng.uniform(0.0, 1.0, 2) * rng.integers(0, 2, 2), rng.normal(0.0, 2.0, 2), K


def test_two_rows_are_solved_as_one_complementarity_problem():
    # Impulses new >= 0 whose residuals w = r + K (new - a) are >= 0, each zero where the other is
    # not: every case (both points, one, neither) against a slow reference that shares nothing with
    # the enumeration (tests/naive.py). The rule before 2026-12 (the block, else one point after
    # the other) gets 130 of these 500 lanes wrong.
    for a, r, K in _two_row_cases(0, 500):
        new = np.array(
            batches.two_row_impulses(a[0], a[1], r[0], r[1], K[0, 0], K[0, 1], K[1, 1], True)
        )
        expected = complementary_impulses(K, r - K @ a)
        assert new == pytest.approx(expected, abs=1e-9 * (1.0 + np.abs(expected).max()))


def test_a_one_point_lane_is_its_first_row_alone():
    for a, r, K in _two_row_cases(1, 100):
        new = batches.two_row_impulses(a[0], 0.0, r[0], 0.0, K[0, 0], K[0, 1], 0.0, False)
        assert new == (pytest.approx(max(0.0, a[0] - r[0] / K[0, 0]), rel=1e-12, abs=1e-15), 0.0)


@pytest.mark.parametrize("approach", [-1.0, 1.0])
def test_two_coincident_points_carry_the_load_once(approach):
    # Two points at one place (K singular: the block is refused): whichever carries it, the pair
    # takes the impulse one row would, not twice that.
    k = 3.0
    a1, a2, r = 0.2, 0.1, approach
    new = batches.two_row_impulses(a1, a2, r, r, k, k, k, True)
    assert min(new) >= 0.0
    assert sum(new) == pytest.approx(max(0.0, a1 + a2 - r / k), rel=1e-12)


@pytest.mark.parametrize("approach", [-1.0, -1e-3])
@pytest.mark.parametrize("start", [(0.0, 0.0), (0.3, 0.1)])
def test_two_nearly_equal_rows_that_both_push_share_one_impulse(approach, start):
    # A plank 0.1 m wide standing on its end (arms +-0.05 m, 5.5 m below the centre of mass):
    # K is too near singular for the block (condition > MAX_CONDITION), and neither point alone
    # holds, since each alone leaves the other pulled. The pair is then solved as one row, the
    # impulse split equally: both push, and their mean residual is zero. The answer "neither"
    # (before 2026-12-06) let such a plank fall through the floor.
    m, inertia = 1.0, (0.1**2 + 11.0**2) / 12.0
    k11 = k22 = 1.0 / m + 0.05**2 / inertia
    k12 = 1.0 / m - 0.05**2 / inertia
    assert k11 * k11 >= soft_step.MAX_CONDITION * (k11 * k22 - k12 * k12)  # the block refused
    a = np.array(start)
    r = np.array([approach, approach])
    new = np.array(batches.two_row_impulses(a[0], a[1], r[0], r[1], k11, k12, k22, True))
    K = np.array([[k11, k12], [k12, k22]])
    w = r + K @ (new - a)
    assert new[0] == new[1] > 0.0
    assert w.mean() == pytest.approx(0.0, abs=1e-12 * abs(approach))
    # the rows differ only by the turn that equalising the split gives: (k11 - k12) (a1 - a2)
    assert w[0] - w[1] == pytest.approx((k11 - k12) * (a[1] - a[0]), abs=1e-12)


@pytest.mark.parametrize("where", ["a1", "r2", "k12"])
def test_a_nan_in_the_rows_comes_through(where):
    # Every case's test fails on a NaN, so without care the lane would answer "neither pushing"
    # with clean zeros and hide it; the answer carries it instead (as _fmax does).
    args = dict(a1=0.2, a2=0.1, r1=0.5, r2=-0.5, k11=3.0, k12=1.0, k22=3.0, real2=True)
    args[where] = math.nan
    assert np.isnan(batches.two_row_impulses(**args)).any()
