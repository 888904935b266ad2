"""Fast regression versions of the extremes sweep's key cases (experiments/table_extremes.py), in
sim only, under every freeze policy: no NaN, no explosion, the physical outcome where it is
known, and a clear ValueError instead of garbage when the input is out of range.

Where sim gets the physics wrong, the test states the right physics and is a strict xfail with
the figure measured when it was written (so a fix shows up as an XPASS, and nothing is loosened).
Scenes come from the experiment's builders, so these are the table's cases, shortened. Figures
quoted as "measured" are from solver v2 (soft step, 4 substeps of 1 iteration, dt 1/60 s, scale-
aware tolerances, continuous collision), sim-off unless a policy is named."""

import math
import re

import numpy as np
import pytest

import sim
from study.common import DT
from study.extremes import geometry, rules, scenes, threshold
from study.extremes.judge import KNIFE_TURN, STAND_MOVE, STAND_TURN
from study.overlap import separation

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
        assert w.kinetic_energy() <= rules.EXPLOSION_FACTOR * e_avail, (
            f"explosion at {w.step_count}"
        )
    return w


def assert_stands(w, start, turn=STAND_TURN, rest=None, within=None):
    """No body moved more than half its thinnest width from ``rest`` (default: its start) nor
    turned more than ``turn`` rad (the experiment's "stands"), nor, when given, more than
    ``within`` m (the bound a test sets from what it measured: "stands" alone allows half a box)."""
    pos0, ang0 = start
    target = pos0 if rest is None else np.asarray(rest, float)
    widths = np.array([geometry.thinnest_width(b.vertices) for b in w.scene.bodies])
    moved = np.hypot(*(w.positions - target).T)
    turned = np.abs(np.angle(np.exp(1j * (w.angles - ang0))))
    assert (moved <= STAND_MOVE * widths).all(), f"moved {moved / widths} widths"
    assert (turned <= turn).all(), f"turned {turned} rad"
    if within is not None:
        assert moved.max() <= within, f"moved {moved.max():.3g} m"


def start_of(w):
    return w.positions, w.angles


def overlap_now(w, shapes):
    """m: the deepest overlap at this pose (the experiment's separating-axis measure: body pairs,
    statics and the floor), independent of the solver's own contact data."""
    return geometry.deepest_overlap(shapes, w.positions, w.angles)[0]


def deepest_overlap_over(w, steps):
    """Step ``steps`` steps (finite and explosion-checked); returns (deepest overlap seen at any
    step end, overlap at the last step) in m."""
    shapes = geometry.Shapes(w.scene)
    e_avail = available_energy(w)
    worst = 0.0
    for _ in range(steps):
        w.step(1)
        assert np.isfinite(w.positions).all() and np.isfinite(w.angles).all()
        assert w.kinetic_energy() <= rules.EXPLOSION_FACTOR * e_avail, (
            f"explosion at {w.step_count}"
        )
        worst = max(worst, overlap_now(w, shapes))
    return worst, overlap_now(w, shapes)


# ---- mass, size, shape -------------------------------------------------------------------------
@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("ratio", [1000.0, 0.001])
def test_mass_ratio_1000_both_ways_stands_without_explosion(policy, ratio):
    # measured (3 s, 2026-12-06): the 1000:1 stack (heavy on top) sinks 1.9 mm (off), 10.8 mm
    # (sleep), 0 (paper), 10.0 mm (extended) into its soft contacts; 1:1000 moves < 1e-12 m
    w = world(scenes.mass_stack(ratio), policy)
    start = start_of(w)
    within = 0.02 if ratio > 1 else 1e-9
    assert_stands(run_checked(w, 180), start, turn=1e-9, within=within)


@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("builder", ["plank_flat", "plank_upright"])
def test_plank_100_to_1_stands(policy, builder):
    # measured (3 s, 2026-12-06): no body moves 1e-12 m or turns 1e-19 rad, under every policy
    w = world(scenes.BUILDERS[builder](100), policy)
    start = start_of(w)
    assert_stands(run_checked(w, 180), start, turn=1e-9, within=1e-9)


@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize(
    "builder,arg", [("polygon_on_box", 64), ("collinear_box", 1e-9), ("collinear_box", 1e-2)]
)
def test_64_gon_and_nearly_collinear_polygon_stand(policy, builder, arg):
    # measured (3 s, 2026-12-06): no body moves 4e-13 m or turns 8e-14 rad, under every policy
    w = world(scenes.BUILDERS[builder](arg), policy)
    start = start_of(w)
    assert_stands(run_checked(w, 180), start, turn=1e-9, within=1e-9)


def substeps_named(error):
    """The substeps a step-size refusal says would resolve the scene ("Use substeps >= N")."""
    found = re.search(r"substeps >= (\d+)", str(error))
    assert found, f"the refusal names no substeps: {error}"
    return int(found.group(1))


def test_tenth_of_a_millimetre_boxes_are_refused_at_4_substeps_and_stand_at_the_substeps_named():
    """0.1 mm boxes at dt 1/60 s (before solver v2 the column collapsed: top box ~10 widths
    sideways): refused at World() with "body 0 is 0.0001 m thick: its contacts would need 249 Hz
    ... Use substeps >= 34 (or dt <= 0.00201 s), or larger bodies"; at exactly that many they stand
    (measured: moved 1.3e-12 widths, deepest overlap 4.5e-9 widths in 3 s), and one fewer is still
    refused."""
    with pytest.raises(ValueError, match="substeps") as refused:
        world(scenes.size_stack(1e-4))
    n = substeps_named(refused.value)
    with pytest.raises(ValueError):
        world(scenes.size_stack(1e-4), substeps=n - 1)
    w = world(scenes.size_stack(1e-4), substeps=n)
    start = start_of(w)
    worst, _ = deepest_overlap_over(w, 180)
    assert_stands(w, start)
    assert worst < 1e-6 * 1e-4 and np.abs(w.positions - start[0]).max() < 1e-6 * 1e-4


def test_millimetre_boxes_are_refused_at_4_substeps_and_stand_at_the_substeps_named():
    """1 mm boxes at dt 1/60 s: refused with 4 substeps, the message naming the substeps needed
    (measured: 11); at exactly that many they stand (measured: moved ~2e-12 widths, deepest
    overlap ~3e-9 widths in 3 s), and one fewer is still refused (the number is the least)."""
    with pytest.raises(ValueError, match="substeps") as refused:
        world(scenes.size_stack(1e-3), substeps=4)
    n = substeps_named(refused.value)
    with pytest.raises(ValueError):
        world(scenes.size_stack(1e-3), substeps=n - 1)
    w = world(scenes.size_stack(1e-3), substeps=n)
    start = start_of(w)
    worst, _ = deepest_overlap_over(w, 180)
    assert_stands(w, start, within=1e-6 * 1e-3)
    assert worst < 0.01 * 1e-3, f"overlap {worst / 1e-3:.3g} of the box"


@pytest.mark.parametrize("policy", POLICIES)
def test_centimetre_boxes_stand_with_under_1_percent_penetration(policy):
    # measured: a placed column of three 1 cm boxes does not move (< 1e-10 widths) and overlaps by
    # < 1e-8 of a box in 3 s under every policy (the tolerances scale with the box, sim.tolerances)
    w = world(scenes.size_stack(0.01), policy)
    start = start_of(w)
    worst, _ = deepest_overlap_over(w, 180)
    assert_stands(w, start)
    assert worst < 0.01 * 0.01, f"overlap {worst / 0.01:.3g} of the box"  # the bound
    # and what was measured, guarded: nothing moves or sinks a millionth of a box
    assert worst < 1e-6 * 0.01 and np.abs(w.positions - start[0]).max() < 1e-6 * 0.01


# ---- mass ratios, dropped: the solver builds the stack (no presolved start) ---------------------
@pytest.mark.parametrize("policy", POLICIES)
def test_dropped_100_to_1_stack_stands_with_under_1_percent_final_penetration(policy):
    # measured (3 s): the farthest box ends 1.9 mm (off), 7.6 mm (sleep), 11.6 mm (extended), 0
    # (paper) from the stacked pose (2026-12-06); final overlap 1.8 mm (off), 6.6 mm (sleep), 9.4
    # mm (extended), 0 (paper,
    # which holds the landing boxes); the deepest transient overlap is 65 mm when the heavy box
    # lands (0 under paper). Before soft_step.batches.two_row_impulses: 2.1, 6.5 and 3.3 mm; with
    # the impact sweeps on hard batches too (which would fix the heavy box across a gap,
    # test_physics) 3.0, 11.5 and 16.2 mm. Before contacts with immovable bodies were solved last
    # in each sweep (soft_step.colour) sleep left 11.2 mm: the island fell asleep still pushing out
    # slowly.
    scene = scenes.dropped_mass_stack(100.0)
    w = world(scene, policy)
    start = start_of(w)
    _, final = deepest_overlap_over(w, 180)
    assert_stands(w, start, rest=scene.params["rest_pose"], within=0.02)
    assert final < 0.01 * 1.0, f"final overlap {final:.3g} m of a 1 m box"


@pytest.mark.parametrize("policy", POLICIES)
def test_dropped_1000_to_1_stack_stands_with_under_5_percent_final_penetration(policy):
    # measured (3 s): the heavy box, dropped 0.3 m onto two unit boxes, sinks 0.26 m into the one
    # below when it lands and is pushed out to a final overlap of 30 mm (off, sleep, extended);
    # paper holds each box landing on the frozen one below, so the heavy box lands on immovable
    # boxes (< 0.01 mm). Before the hard batches (soft_step.HARD_RATIO) it crushed the column:
    # final overlap 0.22-0.40 m, the column 0.86-1.04 m off its stacked pose; now 30 mm off it
    # (the heavy box's overlap; 0 under paper, 2026-12-06).
    scene = scenes.dropped_mass_stack(1000.0)
    w = world(scene, policy)
    start = start_of(w)
    _, final = deepest_overlap_over(w, 180)
    assert final < 0.05 * 1.0, f"final overlap {final:.3g} m of a 1 m box"
    assert_stands(w, start, rest=scene.params["rest_pose"], within=0.05)


# ---- without the presolve ----------------------------------------------------------------------
@pytest.mark.parametrize("policy", POLICIES)
def test_50_box_column_without_presolve_stands(policy):
    # measured (5 s, initial_iterations=0, 2026-12-06): the column settles onto its contacts and
    # stands, ending 0.5 mm (off), 21 mm (sleep), 0 (paper), 14 mm (extended) from its pose. On
    # the way its top box sinks 0.35 m (0.24 under paper) by step 30, while the soft contacts take
    # up the load, and comes back (pymunk and pybullet let it fall over, Box2D 2.3 sinks 1.56 m
    # and ends 0.80 m low)
    w = world(scenes.column(50), policy, initial_iterations=0)
    start = start_of(w)
    deepest = 0.0
    for _ in range(300):
        run_checked(w, 1)
        deepest = max(deepest, float(np.hypot(*(w.positions - start[0]).T).max()))
    assert deepest < 0.4, f"sank {deepest:.3g} m on the way"
    assert_stands(w, start, within=0.03)


# ---- a fast pile -------------------------------------------------------------------------------
def test_pile_dropped_from_35_m_never_penetrates_more_than_5_cm():
    # measured: 30 boxes of 0.5 m land at ~26 m/s row on row; the deepest overlap is 11 mm, the
    # final 2.7 mm. It was 14.2 cm with the floor contacts solved first in each sweep (a box of
    # the first row driven into the floor by one of the second landing on it), then 5.2 cm with
    # them last (soft_step.colour): a box of the third row, falling with the one below it, had no
    # speculative contact with it and flew on when that one was stopped mid-step; the margin now
    # counts both bodies' speeds, not their relative speed (narrowphase._closing_reach).
    worst, final = deepest_overlap_over(world(scenes.pile_drop()), 200)
    assert worst <= 0.05, f"overlap {worst:.3g} m"  # the bound
    assert worst <= 0.02 and final <= 0.01, (worst, final)  # the measured 11 and 2.7 mm, guarded


# ---- speed -------------------------------------------------------------------------------------
@pytest.mark.parametrize("policy", POLICIES)
def test_200_m_per_s_projectile_into_a_stack_stays_finite(policy):
    run_checked(world(scenes.projectile_stack(200.0), policy), 180)


@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("speed", [100.0, 200.0])
def test_fast_projectile_does_not_pass_through_an_unmoved_column(policy, speed):
    # measured (3 s, 2026-12-06): at 100 m/s the projectile stops at box 2 and ends on the near
    # side (x = -0.47 m; -0.75 under paper) and the column gives 0.23-0.53 m; at 200 m/s it
    # knocks the column over (boxes moved 1.1-1.9 m) and ends at x = 0.05-0.61 m. Before solver
    # v2 it passed through box 2 at both speeds (ending 45 m and 95 m beyond) while the column
    # moved < 3 mm.
    w = world(scenes.projectile_stack(speed), policy)
    column0 = w.positions[:5]
    w.step(180)
    column_moved = float(np.hypot(*(w.positions[:5] - column0).T).max())
    beyond = w.positions[5, 0] > 0.5 + scenes.PROJECTILE_SIZE / 2
    assert not (beyond and column_moved < 0.01), (w.positions[5], column_moved)
    if speed == 100.0:
        assert w.positions[5, 0] < 0.0 and 0.1 < column_moved < 1.0, (w.positions[5], column_moved)
    else:
        assert column_moved > 0.5, column_moved  # knocked it over


PHASES = 8  # starting phases of the projectile within one step's travel


@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("phase", range(PHASES))
def test_200_m_per_s_projectile_stops_at_a_5_cm_wall_from_any_phase(policy, phase):
    """The projectile (3.3 m per step at 200 m/s, 66x the wall's 5 cm) arrives at a different
    point of a step for each phase (its start moved by phase/PHASES of a step's travel): wherever
    the step boundary falls, its centre never reaches the wall, it ends in front of it, and it
    overlaps the wall by at most the table's degraded threshold (a tenth of the wall's 5 cm).
    Measured (16 phases, every policy): deepest overlap with the wall 3.8 mm, centre never past
    x = -0.125 m (the projectile's face on the wall's face, -0.025 m)."""
    thickness = scenes.WALL[0]
    scene = scenes.projectile_wall(200.0, arrival_s=0.25 + phase / PHASES * DT)
    w = world(scene, policy)
    shapes = geometry.Shapes(scene)
    wall = shapes.statics[:1]
    worst, furthest = 0.0, -math.inf
    for _ in range(30):  # 0.5 s: arrives in step 15 or 16
        w.step(1)
        body = shapes.world(w.positions, w.angles)[:1]
        worst = max(worst, -max(separation(body, wall)[0], separation(wall, body)[0]))
        furthest = max(furthest, w.positions[0, 0])
    assert furthest < -thickness / 2, f"centre reached x = {furthest:.3g} m"
    assert w.positions[0, 0] < 0.0, "not stopped: ends beyond the wall"  # the table's "stopped"
    assert worst <= rules.PENETRATION_REL * thickness, f"overlap with the wall {worst:.3g} m"


def test_a_projectile_stopped_by_a_wall_is_not_kicked_by_its_own_impact():
    """After a 200 m/s projectile stops against a static wall it can only slide down the face
    (friction, nothing presses it) or fall: no spin, and no downward speed beyond free fall.
    Measured before impacts were kept out of warm starting (soft_step.store): kicked to 162 rad/s
    and (-0.8, -10.9) m/s the step after it stopped; now it slides down the face, no spin."""
    w = world(scenes.projectile_wall(200.0, arrival_s=0.25))
    w.step(15)  # it arrives in step 15
    assert abs(w.velocities[0, 0]) < 1.0  # stopped at the wall
    t0, vy0 = w.step_count, w.velocities[0, 1]
    for _ in range(10):
        w.step(1)
        assert abs(w.angular_velocities[0]) < 1.0, f"spins at {w.angular_velocities[0]:.3g} rad/s"
        free_fall = vy0 - G * DT * (w.step_count - t0) - 0.05
        assert w.velocities[0, 1] >= free_fall, f"vy {w.velocities[0, 1]:.3g} m/s"


@pytest.mark.parametrize("speed", [2.0, 1e2, 1e4, 1e6])
def test_a_box_fired_at_the_floor_lands_on_it_in_its_first_step(speed):
    """A 0.2 m box 4.9 m above the floor, fired straight down: it reaches the floor within the
    first step and stays there (restitution 0). The initial solve of the start pose used to warm
    start step 1 with the impulse that its speculative contact with the floor would need, an
    impact, not a load: repeated in each substep, it stopped the box in the air (0.38 m short at
    1e4 m/s, 4.2 m at 1e5) and at 1e6 m/s sent it back up (42.7 m after one step; sideways and
    up at 3e6). Now a point approaching faster than IMPACT_SWEEP_SPEED is not warm started from
    the initial solve, as a step does not warm start an impact."""
    height = 4.9 if speed > 100.0 else 0.02  # 2 m/s from 2 cm: also within one step
    w = sim.World(
        sim.Scene(
            bodies=[sim.Body.box(0.2, 0.2, position=(0.0, 0.1 + height), velocity=(0, -speed))]
        )
    )
    w.step(1)
    assert w.positions[0, 1] == pytest.approx(0.1, abs=1e-4)
    assert np.abs(w.velocities[0]).max() < 1e-6
    w.step(59)
    assert w.positions[0, 1] == pytest.approx(0.1, abs=1e-4)
    assert abs(w.positions[0, 0]) < 1e-9 and abs(w.angles[0]) < 1e-9


# ---- time step ---------------------------------------------------------------------------------
@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("builder", ["column", "dropped_column"])
def test_dt_one_fifteenth_stays_finite(policy, builder):
    run_checked(world(scenes.BUILDERS[builder](10), policy, dt=1 / 15), 75)


@pytest.mark.parametrize("policy", POLICIES)
def test_placed_column_stands_at_dt_one_fifteenth(policy):
    # measured (5 s, 2026-12-06): no box moves 3.2e-7 m (sleep; off 7.8e-8, paper 0)
    w = world(scenes.column(10), policy, dt=1 / 15)
    start = start_of(w)
    w.step(75)
    assert_stands(w, start, within=1e-5)


@pytest.mark.parametrize("policy", POLICIES)
def test_dropped_column_stands_at_dt_one_thirtieth(policy):
    # measured (5 s at dt 1/30 s, 4 substeps): stands; the farthest box ends 1 mm (off), 13 mm
    # (sleep), 0 mm (paper), 14 mm (extended) from the stacked pose, straight down (5, 22, 1 and
    # 21 mm while the column rocked: test_dropped_column_lands_straight). Before solver v2 it
    # collapsed under sim-off at dt 1/30 (10 iterations) while the fine reference, pymunk and
    # pybullet kept it standing.
    scene = scenes.dropped_column(10)
    w = world(scene, policy, dt=1 / 30)
    start = start_of(w)
    run_checked(w, 150)
    assert_stands(w, start, rest=scene.params["rest_pose"], within=0.03)


@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("rate", [30, 60, 480])
def test_dropped_column_lands_straight(policy, rate):
    # Nothing in the dropped column is asymmetric: every box lands flat and centred on the one
    # below, so nothing turns or moves sideways. Measured (sim-off) while a lane's two points were
    # solved one after the other whenever the block was refused (before 2026-12, now
    # soft_step.batches.two_row_impulses): the column rocked, tilting up to 1.6e-3 rad, and ended
    # 8.8 mm to one side at dt 1/480; exactly 0 since, under every policy.
    w = world(scenes.dropped_column(10), policy, dt=1 / rate)
    run_checked(w, 2 * rate)
    assert np.abs(w.angles).max() < 1e-12
    assert np.abs(w.positions[:, 0]).max() < 1e-12


@pytest.mark.parametrize("policy", sorted(set(POLICIES) - {"off"}))
def test_dropped_column_at_dt_one_480th_does_not_chatter(policy):
    # table_extremes' dt axis at its finest step: no body is woken more than the rule allows
    # (rules.MAX_WAKES). Measured before two_row_impulses: under extended the rocking column froze
    # between landings and woke its bottom box 3 times (tipping: the rocking box above moved its
    # centre of pressure past the corner), the one extremes cell sim-off did not fail either.
    w = world(scenes.dropped_column(10), policy, dt=1 / 480)
    wakes = np.zeros(w.n_bodies, int)
    frozen = w.frozen
    for _ in range(5 * 480):
        w.step()
        wakes += frozen & ~w.frozen
        frozen = w.frozen
    assert wakes.max() <= rules.MAX_WAKES


# ---- impacts at the impulse threshold ----------------------------------------------------------
@pytest.fixture(scope="module")
def v_star():
    """The hammer speed at which each policy's impact decision flips (bisection, ~0.4 s each)."""
    out = {}
    for policy in ("paper", "extended"):
        t = threshold.find_threshold({"policy": policy, "steps": 120, "bisection_steps": 45})
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
    w = world(scenes.impact(v_star[policy] * (1 + eps)), policy)
    start = start_of(w)
    decision = threshold.Decision(policy)
    for _ in range(120):
        w.step(1)
        decision.watch(w)
        assert np.isfinite(w.positions).all()
    crossed = decision.finish()
    assert crossed is (eps > 0)  # the decision flips exactly at v*
    changes, wakes = state_changes(w)
    # land, be held, be woken once, re-freeze: at most 3 changes and 1 wake per body
    assert changes.max() <= 3 and wakes.max() <= 1, (changes, wakes, w.events)
    # measured (2026-12-06): every box within 9e-6 m of its stacked pose (0 under paper)
    assert_stands(w, start, rest=w.scene.params["rest_pose"], within=1e-4)


# ---- knife edge --------------------------------------------------------------------------------
def knife(policy, tilt, steps=240):
    w = run_checked(world(scenes.knife_edge(tilt), policy), steps)
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
    assert turned > KNIFE_TURN


@pytest.mark.parametrize(
    "policy",
    [
        pytest.param(
            "sleep",
            marks=pytest.mark.xfail(
                strict=True,
                reason=(
                    "measured: under sleep the box tilted 1e-6 rad off its balance point is "
                    "frozen upright (turns 1.8e-6 rad in 4 s) while the reference falls within "
                    "~4 s: it is slow when the sleep timer runs out; the unstable equilibrium is "
                    "taken for rest"
                ),
            ),
        ),
        # extended was the same (6.5e-9 rad in 4 s) until its rest test became a certificate of
        # equilibrium: one support point holds no moment, so the box is never certified
        "extended",
    ],
)
def test_knife_edge_tilted_by_a_micro_radian_falls_under_freezing(policy):
    _, turned = knife(policy, 1e-6)
    assert turned > KNIFE_TURN


# ---- out-of-range input: a clear ValueError ----------------------------------------------------
@pytest.mark.parametrize(
    "make",
    [
        lambda: sim.Body.box(0.0, 1.0),
        lambda: sim.Body.box(-1.0, 1.0),
        lambda: sim.Body.box(math.nan, 1.0),
        lambda: sim.Body.box(1.0, math.inf),
        lambda: sim.Body.box(1.0, 1.0, density=0.0),
        lambda: sim.Body.box(1.0, 1.0, density=-2.0),
        lambda: sim.Body.box(1.0, 1.0, density=math.nan),
        lambda: sim.Body(vertices=[(0, 0), (1, 0), (2, 0)]),  # collinear: zero area
        lambda: sim.Body(vertices=[(0, 0), (1, 0), (1, 0), (0, 1)]),  # repeated vertex
        lambda: sim.Body(vertices=[(0, 0), (1, 0)]),  # two vertices
        lambda: sim.Body(vertices=[(0, 0), (1, 1e-300), (0, 1e-300)]),  # zero area by underflow
        lambda: sim.Body.regular(2, 1.0),
        lambda: sim.Body.regular(3, 0.0),
        lambda: sim.Body.regular(3, math.nan),
    ],
    ids=[
        "size0",
        "size-",
        "size-nan",
        "size-inf",
        "density0",
        "density-",
        "density-nan",
        "collinear",
        "repeated",
        "two-vertices",
        "underflow",
        "2-gon",
        "radius0",
        "radius-nan",
    ],
)
def test_bad_bodies_raise_value_error(make):
    with pytest.raises(ValueError):
        make()


@pytest.mark.parametrize(
    "settings",
    [
        {"dt": 0.0},
        {"dt": -1 / 60},
        {"dt": math.nan},
        {"dt": math.inf},
        {"iterations": 0},
        {"iterations": -3},
        {"iterations": 1.5},
        {"iterations": math.nan},
        {"iterations": True},
    ],
    ids=lambda s: f"{next(iter(s))}={next(iter(s.values()))}",
)
@pytest.mark.parametrize("policy", POLICIES)
def test_bad_settings_raise_value_error(policy, settings):
    with pytest.raises(ValueError):
        sim.World(scenes.column(3), freeze=policy, **settings)


def test_regular_polygon_with_negative_radius_is_refused():
    with pytest.raises(ValueError):
        sim.Body.regular(3, -1.0)


def test_regular_polygon_with_fractional_vertex_count_is_refused():
    with pytest.raises(ValueError):
        sim.Body.regular(3.5, 1.0)


def test_a_body_beyond_the_solver_range_is_refused_at_build():
    with pytest.raises(ValueError, match="beyond"):
        sim.Body.box(1.0, 1.0, position=(2e12, 0.0))


@pytest.mark.parametrize(
    "speed",
    [
        1e5,
        1e7 * 10**-0.5,  # 3.16e6: clean
        pytest.param(
            10**5.75,
            marks=pytest.mark.xfail(strict=True, reason="measured: 3.6 mm/s left after 3 steps"),
        ),
        pytest.param(
            10**6.75,
            marks=pytest.mark.xfail(strict=True, reason="measured: 0.38 m/s and 0.76 rad/s left"),
        ),
    ],
)
def test_a_flat_face_stopped_from_any_accepted_speed_rests(speed):
    """A 0.2 m box dropped flat onto the floor, restitution 0: after 3 steps it lies on the floor
    at rest, whatever the speed it arrived at (inputs are accepted up to 1e12 m/s). It does at
    most speeds tried, but not at all, erratically with the speed: the residual is ~1e-7 of the
    speed (README, known limits; source not found)."""
    box = sim.Body.box(0.2, 0.2, position=(0, 3), velocity=(0, -speed))
    world = sim.World(sim.Scene([box]))
    world.step(3)
    assert np.hypot(*world.velocities[0]) < 1e-9 and abs(world.angular_velocities[0]) < 1e-9
    assert world.positions[0, 1] == pytest.approx(0.1, abs=1e-4)
