"""Fast regression versions of the extremes sweep's key cases (experiments/table_extremes.py), in
sim only, under every freeze policy: no NaN, no explosion, the physical outcome where it is
known, and a clear ValueError instead of garbage when the input is out of range.

Where sim gets the physics wrong, the test states the right physics and is a strict xfail with
the figure measured when it was written (so a fix shows up as an XPASS, and nothing is loosened).
Scenes come from the experiment's builders, so these are the table's cases, shortened."""
import math

import numpy as np
import pytest

import sim
from experiments import table_extremes as T

POLICIES = sim.POLICY_NAMES
G = 9.81


def world(scene, policy="off", **kw):
    return sim.World(scene, freeze=policy, **kw)


def available_energy(w):
    """J: kinetic + potential above the floor at the start; no motion can release more."""
    return w.kinetic_energy() + G * float(w.masses @ (w.positions[:, 1] - w.scene.floor_y))


def run_checked(w, steps):
    """Step one step at a time; assert the state stays finite and kinetic energy never exceeds
    twice what was available (the experiment's explosion rule). Returns the world."""
    e_avail = available_energy(w)
    for _ in range(steps):
        w.step(1)
        assert np.isfinite(w.positions).all() and np.isfinite(w.velocities).all()
        assert np.isfinite(w.angles).all() and np.isfinite(w.angular_velocities).all()
        assert w.kinetic_energy() <= T.EXPLOSION_FACTOR * e_avail, f"explosion at {w.step_count}"
    return w


def assert_stands(w, start, turn=T.STAND_TURN, rest=None):
    """No body moved more than half its thinnest width from ``rest`` (default: its start) nor
    turned more than ``turn`` rad (the experiment's "stands")."""
    pos0, ang0 = start
    target = pos0 if rest is None else np.asarray(rest, float)
    widths = np.array([T.thinnest_width(b.vertices) for b in w.scene.bodies])
    moved = np.hypot(*(w.positions - target).T)
    turned = np.abs(np.angle(np.exp(1j * (w.angles - ang0))))
    assert (moved <= T.STAND_MOVE * widths).all(), f"moved {moved / widths} widths"
    assert (turned <= turn).all(), f"turned {turned} rad"


def start_of(w):
    return w.positions, w.angles


# ---- mass, size, shape -------------------------------------------------------------------------
@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("ratio", [1000.0, 0.001])
def test_mass_ratio_1000_both_ways_stands_without_explosion(policy, ratio):
    w = world(T.mass_stack(ratio), policy)
    start = start_of(w)
    assert_stands(run_checked(w, 180), start)


@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("builder", ["plank_flat", "plank_upright"])
def test_plank_100_to_1_stands(policy, builder):
    w = world(T.BUILDERS[builder](100), policy)
    start = start_of(w)
    assert_stands(run_checked(w, 180), start)


@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("builder,arg", [("polygon_on_box", 64), ("collinear_box", 1e-9),
                                         ("collinear_box", 1e-2)])
def test_64_gon_and_nearly_collinear_polygon_stand(policy, builder, arg):
    w = world(T.BUILDERS[builder](arg), policy)
    start = start_of(w)
    assert_stands(run_checked(w, 180), start)


@pytest.mark.xfail(strict=True, reason="measured: a column of three 0.1 mm boxes under sim-off "
                   "collapses (top box ends ~10 of its widths sideways, 2.4 widths lower): "
                   "slop 5 mm and speculative distance 2 cm are absolute, 50-200x the box; "
                   "neither a sane result nor a clear error")
def test_tenth_of_a_millimetre_boxes_stand_or_are_refused():
    try:
        w = world(T.size_stack(1e-4))
    except ValueError:
        return                                      # refusing the scene is an acceptable answer
    start = start_of(w)
    w.step(180)
    assert_stands(w, start)


# ---- speed -------------------------------------------------------------------------------------
@pytest.mark.parametrize("policy", POLICIES)
def test_200_m_per_s_projectile_into_a_stack_stays_finite(policy):
    run_checked(world(T.projectile_stack(200.0), policy), 180)


@pytest.mark.xfail(strict=True, reason="measured: sim has no continuous collision detection: the "
                   "0.2 m projectile, 1.7 m per step at 100 m/s and 3.3 m at 200 m/s (dt 1/60), "
                   "ends 45 m and 95 m beyond the column it was fired into while the column's "
                   "boxes moved less than 3 mm: it passed through box 2")
@pytest.mark.parametrize("speed", [100.0, 200.0])
def test_fast_projectile_does_not_pass_through_an_unmoved_column(speed):
    w = world(T.projectile_stack(speed))
    column0 = w.positions[:5]
    w.step(180)
    column_moved = float(np.hypot(*(w.positions[:5] - column0).T).max())
    beyond = w.positions[5, 0] > 0.5 + T.PROJECTILE_SIZE / 2
    assert not (beyond and column_moved < 0.01), (w.positions[5], column_moved)


# ---- time step ---------------------------------------------------------------------------------
@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("builder", ["column", "dropped_column"])
def test_dt_one_fifteenth_stays_finite(policy, builder):
    run_checked(world(T.BUILDERS[builder](10), policy, dt=1 / 15), 75)


@pytest.mark.parametrize("policy", POLICIES)
def test_placed_column_stands_at_dt_one_fifteenth(policy):
    w = world(T.column(10), policy, dt=1 / 15)
    start = start_of(w)
    w.step(75)
    assert_stands(w, start)


@pytest.mark.xfail(strict=True, reason="measured: a column of 10 boxes dropped 0.1 m onto each "
                   "other collapses in sim-off at dt 1/30 s (10 iterations), while the fine "
                   "reference, pymunk and pybullet keep it standing; it stands at dt <= 1/60")
def test_dropped_column_stands_at_dt_one_thirtieth():
    scene = T.dropped_column(10)
    w = world(scene, dt=1 / 30)
    start = start_of(w)
    w.step(150)
    assert_stands(w, start, rest=scene.params["rest_pose"])


# ---- impacts at the impulse threshold ----------------------------------------------------------
@pytest.fixture(scope="module")
def v_star():
    """The hammer speed at which each policy's impact decision flips (bisection, ~0.4 s each)."""
    out = {}
    for policy in ("paper", "extended"):
        t = T.find_threshold({"policy": policy, "steps": 120, "bisection_steps": 45})
        assert math.isfinite(t["v_star"]), t
        out[policy] = t["v_star"]
    return out


def state_changes(w):
    """Per body: number of state changes, number of wakes (to FREE) in world.events."""
    changes = np.zeros(w.n_bodies, int)
    wakes = np.zeros(w.n_bodies, int)
    for _, body, a, b, _ in w.events:
        if a != b:
            changes[body] += 1
            wakes[body] += b == sim.State.FREE
    return changes, wakes


@pytest.mark.parametrize("policy", ["paper", "extended"])
@pytest.mark.parametrize("eps", [-1e-3, -1e-6, 1e-6, 1e-3])
def test_impact_at_threshold_plus_minus_eps_does_not_chatter(v_star, policy, eps):
    w = world(T.impact(v_star[policy] * (1 + eps)), policy)
    start = start_of(w)
    decision = T.Decision(policy)
    for _ in range(120):
        w.step(1)
        decision.watch(w)
        assert np.isfinite(w.positions).all()
    crossed = decision.finish()
    assert crossed is (eps > 0)                   # the decision flips exactly at v*
    changes, wakes = state_changes(w)
    # land, be held, be woken once, re-freeze: at most 3 changes and 1 wake per body
    assert changes.max() <= 3 and wakes.max() <= 1, (changes, wakes, w.events)
    assert_stands(w, start, rest=w.scene.params["rest_pose"])


# ---- knife edge --------------------------------------------------------------------------------
def knife(policy, tilt, steps=240):
    w = run_checked(world(T.knife_edge(tilt), policy), steps)
    turned = abs(w.angles[0] - math.pi / 4 - tilt)
    return w, turned


@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("tilt", [0.0, 1e-6])
def test_knife_edge_is_finite_and_deterministic(policy, tilt):
    a, _ = knife(policy, tilt)
    b, _ = knife(policy, tilt)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.angles, b.angles)


@pytest.mark.parametrize("policy", ["off", "paper"])
def test_knife_edge_tilted_by_a_micro_radian_falls(policy):
    _, turned = knife(policy, 1e-6)
    assert turned > T.KNIFE_TURN


@pytest.mark.parametrize("policy", [
    pytest.param(p, marks=pytest.mark.xfail(strict=True, reason=(
        f"measured: under {p} the box tilted 1e-6 rad off its balance point is frozen upright "
        "(turns < 1e-12 rad in 4 s) while the reference falls within ~4 s: it is slow when the "
        "rest test runs; the unstable equilibrium is taken for rest")))
    for p in ("sleep", "extended")])
def test_knife_edge_tilted_by_a_micro_radian_falls_under_freezing(policy):
    _, turned = knife(policy, 1e-6)
    assert turned > T.KNIFE_TURN


# ---- out-of-range input: a clear ValueError ----------------------------------------------------
@pytest.mark.parametrize("make", [
    lambda: sim.Body.box(0.0, 1.0), lambda: sim.Body.box(-1.0, 1.0),
    lambda: sim.Body.box(math.nan, 1.0), lambda: sim.Body.box(1.0, math.inf),
    lambda: sim.Body.box(1.0, 1.0, density=0.0), lambda: sim.Body.box(1.0, 1.0, density=-2.0),
    lambda: sim.Body.box(1.0, 1.0, density=math.nan),
    lambda: sim.Body(vertices=[(0, 0), (1, 0), (2, 0)]),               # collinear: zero area
    lambda: sim.Body(vertices=[(0, 0), (1, 0), (1, 0), (0, 1)]),       # repeated vertex
    lambda: sim.Body(vertices=[(0, 0), (1, 0)]),                       # two vertices
    lambda: sim.Body(vertices=[(0, 0), (1, 1e-300), (0, 1e-300)]),     # zero area by underflow
    lambda: sim.Body.regular(2, 1.0), lambda: sim.Body.regular(3, 0.0),
    lambda: sim.Body.regular(3, math.nan),
], ids=["size0", "size-", "size-nan", "size-inf", "density0", "density-", "density-nan",
        "collinear", "repeated", "two-vertices", "underflow", "2-gon", "radius0", "radius-nan"])
def test_bad_bodies_raise_value_error(make):
    with pytest.raises(ValueError):
        make()


@pytest.mark.parametrize("settings", [
    {"dt": 0.0}, {"dt": -1 / 60}, {"dt": math.nan}, {"dt": math.inf}, {"iterations": 0},
    {"iterations": -3}, {"iterations": 1.5}, {"iterations": math.nan}, {"iterations": True},
], ids=lambda s: f"{next(iter(s))}={next(iter(s.values()))}")
@pytest.mark.parametrize("policy", POLICIES)
def test_bad_settings_raise_value_error(policy, settings):
    with pytest.raises(ValueError):
        sim.World(T.column(3), freeze=policy, **settings)


def test_regular_polygon_with_negative_radius_is_refused():
    with pytest.raises(ValueError):
        sim.Body.regular(3, -1.0)


def test_regular_polygon_with_fractional_vertex_count_is_refused():
    with pytest.raises(ValueError):
        sim.Body.regular(3.5, 1.0)


def test_a_body_beyond_the_solver_range_is_refused_at_build():
    with pytest.raises(ValueError, match="beyond"):
        sim.Body.box(1.0, 1.0, position=(2e12, 0.0))
