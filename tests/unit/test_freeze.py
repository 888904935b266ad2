"""Freeze policies: the seed's figures under `paper`, accuracy against `off`, the seed's limits
shown honestly, the general rest test and waking of `extended`, the engines' island `sleep`."""

import math

import numpy as np
import pytest

import sim
from sim import State
from conftest import G

FROZEN_POLICIES = ("sleep", "paper", "extended")


def transitions(world, body=None):
    """(body, from, to, cause) of every event, optionally of one body."""
    return [(b, f, t, c) for _, b, f, t, c in world.events if body is None or b == body]


def awake_count(world):
    return world.n_awake


# ---- the seed's figures under `paper` -----------------------------------------------------------
def test_seed_fig1_states_at_the_moment_drawn():
    world = sim.World(sim.scenes.seed_fig1(), freeze="paper")
    world.step(3)
    a, b, c = world.states
    assert (a, b, c) == (State.ROTATION_STABLE, State.VERTICAL_STABLE, State.FREE)


def test_seed_fig1_vertical_stable_vertex_does_not_move_vertically():
    world = sim.World(sim.scenes.seed_fig1(), freeze="paper")
    world.step(1)
    corner = world.vertices(1)[np.argmin(world.vertices(1)[:, 1])]
    for _ in range(20):
        world.step()
        assert world.states[1] == State.VERTICAL_STABLE
        low = world.vertices(1)[np.argmin(world.vertices(1)[:, 1])]
        assert low[1] == pytest.approx(corner[1], abs=1e-9)  # the pivot keeps its height
    assert world.angles[1] < math.radians(30.0) - 0.05  # while the box turns about it


def test_seed_fig2_lands_on_the_top_edge_and_both_end_frozen():
    world = sim.World(sim.scenes.seed_fig2(), freeze="paper")
    world.step(240)
    assert list(world.states) == [State.ROTATION_STABLE, State.ROTATION_STABLE]
    assert awake_count(world) == 0
    assert world.positions[0, 1] == pytest.approx(1.0 + 0.4, abs=0.006)  # on B (1 m), A 0.8 m
    assert abs(world.positions[0, 0]) < 1.0  # over B
    landing = [t for t in transitions(world, 0) if t[3] == "one_vertex_on_floor"]
    assert landing, "A should first touch B's edge with one vertex (it falls tilted 10 degrees)"


def test_seed_fig3_transition_log_is_exactly_the_expected_sequence():
    world = sim.World(sim.scenes.seed_fig3(), freeze="paper")
    world.step(300)
    FREE, VS, RS = State.FREE, State.VERTICAL_STABLE, State.ROTATION_STABLE
    assert transitions(world) == [
        (1, FREE, RS, "two_vertices_on_floor"),  # B rests on the floor
        (1, RS, RS, "stopped_sliding"),  # ... and is frozen at once
        (0, FREE, RS, "two_vertices_on_floor"),  # A rests on B's top edge, sliding
        (0, RS, FREE, "com_outside_support"),  # a0 passes B's edge: A is free
        (0, FREE, VS, "one_vertex_on_floor"),  # A lands on the floor on a corner
        (0, VS, RS, "two_vertices_on_floor"),  # ... tips onto a face
        (0, RS, RS, "stopped_sliding"),  # ... and stops
    ]
    # A is freed when its centre of mass passes B's edge (x = 1): under Coulomb friction
    # x(t) = 0.1 + 2.5 t - mu g t^2 / 2 with mu = 0.2
    mu, v0, x0 = 0.2, 2.5, 0.1
    t = (v0 - math.sqrt(v0**2 - 2 * mu * G * (1.0 - x0))) / (mu * G)
    freed = next(step for step, b, _, _, c in world.events if c == "com_outside_support")
    assert abs(freed - t / world.dt) <= 2
    assert world.positions[0, 1] < 0.5 and world.positions[0, 0] > 1.0  # on the floor


# ---- accuracy against `off` -------------------------------------------------------------------
DETERMINATE = {
    "single_box": lambda: sim.scenes.single_box(),
    "rest_row": lambda: sim.scenes.rest_row(10),
    "stack": lambda: sim.scenes.stack(5),
    "pyramid": lambda: sim.scenes.pyramid(10),
    "arch": lambda: sim.scenes.arch(),
    "sliding_box": lambda: sim.scenes.sliding_box(),
    "seed_fig1": sim.scenes.seed_fig1,
    "seed_fig2": sim.scenes.seed_fig2,
}


# Measured, not hidden: `paper` stops a body's rotation the step its second vertex touches (RS),
# so a box that lands on a corner can end short of where `off` lets it rock and slide. Which
# figure shows it depends on how the landing falls in the steps: seed_fig1's body C missed by
# 2.9 cm with the solver before soft step (0.7 mm now); seed_fig2's body A by 2.3 cm before the
# impact sweeps (soft_step.IMPACT_SWEEP_SPEED), 8.3 mm now (extended 9.5 mm), inside its 1 cm.
# A scene listed here is a strict xfail: if the model changes and it passes, the entry must go.
PAPER_MISSES = set()


@pytest.mark.parametrize(
    "name,policy",
    [
        pytest.param(
            n,
            p,
            marks=pytest.mark.xfail(
                strict=True,
                reason="paper's RS stops rotation at the first two-vertex touch (see PAPER_MISSES)",
            ),
        )
        if (n, p) in PAPER_MISSES
        else (n, p)
        for n in sorted(DETERMINATE)
        for p in FROZEN_POLICIES
    ],
)
def test_final_poses_match_off(name, policy):
    bound, turn_bound = POSE_BOUND.get(name, (1e-6, 1e-6))
    ref = sim.World(DETERMINATE[name]()).step(300)
    world = sim.World(DETERMINATE[name](), freeze=policy).step(300)
    assert np.linalg.norm(world.positions - ref.positions, axis=1).max() < bound
    turn = np.angle(np.exp(1j * (world.angles - ref.angles)))
    assert np.abs(turn).max() < turn_bound


#: (m, rad) bounds on the final pose's distance from off's, where a body moves before it rests.
#: Measured (2026-12-06, worst policy): a scene placed at rest 1.2e-7 m (the default bound, 1e-6);
#: sliding_box 0.16 mm (paper); seed_fig1 0.68 mm and 7.4e-4 rad (paper); seed_fig2 9.5 mm
#: (extended: A lands on a corner, and where it ends depends on the landing's steps; paper 8.3 mm)
POSE_BOUND = {
    "sliding_box": (1e-3, 1e-5),
    "seed_fig1": (3e-3, 3e-3),
    "seed_fig2": (0.01, 1e-3),
}


@pytest.mark.parametrize("policy", FROZEN_POLICIES)
def test_chaotic_scenes_keep_their_outcome(policy):
    # seed_fig3: A ends on the floor beyond B's edge; drop: a settled pile inside the bin
    ref = sim.World(sim.scenes.seed_fig3()).step(300)
    world = sim.World(sim.scenes.seed_fig3(), freeze=policy).step(300)
    for w in (ref, world):
        assert w.positions[0, 1] < 0.5 and w.positions[0, 0] > 1.0
    scene = sim.scenes.drop(20, seed=3)
    walls = sorted(b.position[0] for b in scene.static_bodies)
    ref = sim.World(scene).step(480)
    world = sim.World(scene, freeze=policy).step(480)
    for w in (ref, world):
        assert np.all((w.positions[:, 0] > walls[0]) & (w.positions[:, 0] < walls[1]))
        assert np.all(w.positions[:, 1] > 0.0)
    # the pile's height agrees with off's. Measured (2026-12-06): within 0.1 mm (sleep), 0.2 mm
    # (extended), 0.19 m (paper: its pile takes another path; bodies are ~0.8 m at most)
    bound = 0.4 if policy == "paper" else 0.01
    assert abs(world.positions[:, 1].max() - ref.positions[:, 1].max()) < bound


@pytest.mark.parametrize("policy", ("off",) + FROZEN_POLICIES)
def test_sliding_box_slides_the_analytic_distance(policy):
    speed, mu = 3.0, 0.4
    world = sim.World(sim.scenes.sliding_box(speed=speed, friction=mu), freeze=policy)
    world.step(240)  # 0.76 s of sliding, then 3.2 s to stand (test_physics, slide)
    assert world.positions[0, 0] == pytest.approx(speed**2 / (2 * mu * G), rel=0.03)
    assert abs(world.velocities[0, 0]) < 1e-7


# ---- the seed's limits, shown honestly ----------------------------------------------------------
def knocked_stack(distance=4.0):
    """Two boxes stacked; a heavy projectile, ``distance`` m away, knocks the bottom one out from
    under the top one (it flies 25 m/s, so at 4 m it hits before anything could fall asleep).
    (At 15 m/s `paper` let the base go only 0.86 m: the frozen top box it slides out under is an
    immovable lid that its friction drags on; the base must leave the top box's footprint, 1 m.)"""
    base, top = sim.scenes.stack(2).bodies
    shot = sim.Body.box(
        0.4, 0.4, position=(-distance, 0.25), velocity=(25.0, 0.0), density=40.0, name="shot"
    )
    return sim.Scene(bodies=[base, top, shot], name="knocked_stack")


def test_paper_leaves_the_upper_body_floating_when_its_support_is_knocked_away():
    world = sim.World(knocked_stack(), freeze="paper").step(120)
    assert abs(world.positions[0, 0]) > 1.0  # the base was knocked away
    # documented behaviour of `paper` (the seed's second limit): nothing wakes the top box
    assert world.positions[1, 1] == pytest.approx(1.5, abs=1e-9)
    assert world.states[1] == State.ROTATION_STABLE


@pytest.mark.parametrize("policy", ("off", "sleep", "extended"))
def test_extended_and_sleep_let_the_upper_body_fall(policy):
    world = sim.World(knocked_stack(), freeze=policy).step(120)
    assert abs(world.positions[0, 0]) > 1.0
    assert world.positions[1, 1] < 0.6  # the top box fell to the floor


def test_a_five_box_stack_freezes_whole_under_extended():
    world = sim.World(sim.scenes.stack(5), freeze="extended").step(3)
    assert awake_count(world) == 0
    steps = {step for step, *_ in world.events}
    assert len(steps) == 1  # all in one step
    assert list(world.states) == [State.ROTATION_STABLE] * 5


@pytest.mark.parametrize("policy", ("paper", "extended"))
def test_rest_row_frozen_within_three_steps(policy):
    world = sim.World(sim.scenes.rest_row(50), freeze=policy)
    world.step(3)
    assert awake_count(world) == 0


def test_paper_cannot_freeze_bodies_on_two_supports_or_inclined_faces():
    # the seed's first and third limits: pyramid boxes rest on two boxes, arch blocks on
    # inclined faces; `extended` freezes both
    for scene in (sim.scenes.pyramid(6), sim.scenes.arch()):
        paper = sim.World(scene, freeze="paper").step(60)
        extended = sim.World(scene, freeze="extended").step(60)
        assert awake_count(paper) > 0
        assert awake_count(extended) == 0


# ---- extended: waking ---------------------------------------------------------------------------
def test_extended_wakes_the_whole_stack_in_the_step_of_the_impact():
    world = sim.World(knocked_stack(), freeze="extended").step(120)
    woken = [(step, b, c) for step, b, f, t, c in world.events if t == State.FREE]
    assert [c for _, b, c in woken if b == 0] == ["impact"]
    assert [c for _, b, c in woken if b == 1] == ["support_lost"]
    steps = {step for step, b, c in woken if b in (0, 1)}
    assert len(steps) == 1  # same step, not one layer per step


def test_extended_matches_off_when_a_frozen_stack_is_hit():
    ref = sim.World(knocked_stack()).step(120)
    world = sim.World(knocked_stack(), freeze="extended").step(120)
    # momentum goes into the stack (woken before the solve), not reflected off frozen bodies;
    # measured (2026-12-06): every body within 4.3e-5 m of off's
    np.testing.assert_allclose(world.positions, ref.positions, atol=1e-3)


def test_extended_slow_push_wakes_a_frozen_box():
    # a box pushed sideways slowly (below the impact threshold) by a frictionless sliding box
    pushed = sim.Body.box(1, 1, position=(0.0, 0.5), friction=0.3)
    pusher = sim.Body.box(
        1, 1, position=(-1.6, 0.5), velocity=(1.2, 0.0), density=10.0, friction=0.0
    )
    scene = sim.Scene(bodies=[pushed, pusher], floor_friction=0.3)
    world = sim.World(scene, freeze="extended", impact_speed=100.0).step(90)
    causes = [c for _, b, f, t, c in world.events if b == 0 and t == State.FREE]
    assert causes and causes[0] == "pushed"
    assert world.positions[0, 0] > 0.05  # it moved


@pytest.mark.parametrize("triangle_on_it", [False, True])
def test_extended_a_push_wakes_a_frozen_box_whatever_once_rested_on_it(triangle_on_it):
    """A box frozen in step 1; a frictionless box sliding at 0.5 m/s reaches it at step ~180,
    pushes it 1 mm, and is stopped (off: the same). With a triangle balanced on its apex on the
    box (never certified: one point) that tips off by step ~110, the box took the triangle's
    push into its frozen load and kept it after the triangle had gone, for good: the slider's
    push then stayed inside what the load said the box could bear, and the box stopped it dead.
    An awake body's push is read live, never kept in the load."""
    box = sim.Body.box(1.0, 0.5, position=(0.0, 0.25))
    if triangle_on_it:
        triangle = sim.Body.regular(3, 0.3, position=(0.4, 0.8), angle=math.pi - 2e-3, density=5.0)
    else:
        triangle = sim.Body.regular(3, 0.3, position=(3.0, 0.15), density=5.0)
    slider = sim.Body.box(0.4, 0.4, position=(-2.2, 0.2), velocity=(0.5, 0.0), friction=0.0)
    scene = sim.Scene(bodies=[box, triangle, slider])
    off = sim.World(scene).step(400)
    world = sim.World(scene, freeze="extended").step(400)
    woken = [c for _, b, f, t, c in world.events if b == 0 and t == State.FREE]
    assert woken == ["pushed"]
    assert world.positions[0, 0] == pytest.approx(off.positions[0, 0], abs=2e-4)
    assert off.positions[0, 0] > 5e-4  # it was pushed


def test_extended_tipping_wakes_an_overhanging_plank():
    # a plank resting on a box, its centre of mass over the box (x = 0.3, box edge 0.5), its right
    # end overhanging; a weight lands on the overhang and moves the combined centre past the edge
    base = sim.Body.box(1.0, 1.0, position=(0.0, 0.5))
    plank = sim.Body.box(3.0, 0.2, position=(0.3, 1.1))
    weight = sim.Body.box(0.5, 0.5, position=(1.6, 2.0), density=8.0)
    world = sim.World(
        sim.Scene(bodies=[base, plank, weight]), freeze="extended", impact_speed=1e6
    )  # no impact waking: only the balance test
    world.step(90)
    frozen_first = [step for step, b, f, t, c in world.events if b == 1 and c == "rested"]
    assert frozen_first and frozen_first[0] <= 3
    causes = [c for _, b, f, t, c in world.events if b == 1 and t == State.FREE]
    assert causes[:1] == ["tipping"]
    assert world.angles[1] < -0.2  # the plank tipped over the edge


def test_extended_general_rest_test_freezes_plank_on_two_boxes_and_box_leaning_on_wall():
    left = sim.Body.box(1, 1, position=(-1.5, 0.5))
    right = sim.Body.box(1, 1, position=(1.5, 0.5))
    plank = sim.Body.box(4.0, 0.2, position=(0.0, 1.1))
    world = sim.World(sim.Scene(bodies=[left, right, plank]), freeze="extended").step(10)
    assert awake_count(world) == 0
    wall = sim.Body.box(0.5, 4.0, position=(0.25, 2.0), name="wall", friction=0.6)
    tilt = math.radians(20.0)  # a 0.4 x 2 box leaning on the wall
    w, h = 0.4, 2.0
    lean = sim.Body.box(
        w,
        h,
        angle=tilt,
        friction=0.8,
        position=(
            -(w / 2) * math.cos(tilt) - (h / 2) * math.sin(tilt) - 1e-4,
            (w / 2) * math.sin(tilt) + (h / 2) * math.cos(tilt),
        ),
    )
    scene = sim.Scene(bodies=[lean], static_bodies=[wall], floor_friction=0.8)
    ref = sim.World(scene).step(240)
    world = sim.World(scene, freeze="extended").step(240)
    assert awake_count(world) == 0
    np.testing.assert_allclose(world.positions, ref.positions, atol=0.01)


def test_extended_does_not_freeze_a_box_sliding_down_a_ramp():
    # a 30 degree ramp rising to the right, friction 0.4 < tan 30 = 0.58: the box slides down
    slope = math.radians(30.0)
    ramp = sim.Body(vertices=[(-4.0, 0.0), (4.0, 0.0), (4.0, 8.0 * math.tan(slope))], name="ramp")
    half = 0.25
    surface = np.array([0.0, 4.0 * math.tan(slope)])
    normal = np.array([-math.sin(slope), math.cos(slope)])
    box = sim.Body.box(
        2 * half,
        2 * half,
        angle=slope,
        friction=0.4,
        position=tuple(surface + (half + 1e-4) * normal),
    )
    scene = sim.Scene(bodies=[box], static_bodies=[ramp], floor_friction=0.4)
    ref = sim.World(scene).step(60)
    world = sim.World(scene, freeze="extended").step(60)
    assert world.states[0] == State.FREE and world.velocities[0, 0] < -0.5
    assert not world.events
    np.testing.assert_allclose(world.positions, ref.positions, atol=1e-9)


# ---- sleep ------------------------------------------------------------------------------------
@pytest.mark.parametrize("sleep_time, dt", [(0.5, 1 / 60), (1.0, 1 / 60), (0.5, 0.01), (0.3, 0.1)])
def test_sleep_puts_an_island_to_sleep_after_sleep_time(sleep_time, dt):
    # placed at rest, idle from step 1: asleep in the step its timer reaches sleep_time, exactly
    # (the timer's sum of dt fell short by round-off: 0.5 s at 1/60 s took 31 steps, 1.0 s 60)
    steps = round(sleep_time / dt)
    world = sim.World(sim.scenes.stack(3), dt=dt, freeze="sleep", sleep_time=sleep_time)
    world.step(steps - 1)
    assert awake_count(world) == 3
    world.step(1)
    assert awake_count(world) == 0
    assert {c for *_, c in world.events} == {"timer"}
    assert list(world.states) == [State.SLEEPING] * 3


@pytest.mark.parametrize("sleep_time", [0.0, 1e-9])
def test_sleep_with_no_idle_time_never_sleeps_a_moving_body(sleep_time):
    """sleep_time 0 means idle for one step: a box thrown at 10 m/s flies on (it fell asleep in
    mid-air in its first step), and a stack placed at rest sleeps after its first idle step."""
    thrown = sim.Scene(bodies=[sim.Body.box(1, 1, position=(0, 50), velocity=(10, 0))])
    world = sim.World(thrown, freeze="sleep", sleep_time=sleep_time)
    world.step(5)
    assert awake_count(world) == 1 and world.velocities[0, 0] == pytest.approx(10.0)
    world = sim.World(sim.scenes.stack(3), freeze="sleep", sleep_time=sleep_time)
    world.step(1)
    assert awake_count(world) == 0


def test_sleep_waits_for_the_least_idle_body_of_an_island():
    # B slides on the long box A, which stays idle under it: A's timer runs out at 0.5 s, but
    # the island (A and B touch) sleeps only once B has been idle that long too. B stops after
    # v / (mu g) = 1.02 s, having slid v^2 / (2 mu g) = 0.51 m, as under `off` (measured: the
    # same 0.5074 m, asleep at step 88).
    a = sim.Body.box(3.0, 0.5, position=(0.0, 0.25), friction=0.1)
    b = sim.Body.box(0.5, 0.5, position=(-1.2, 0.75), velocity=(1.0, 0.0), friction=0.1)
    runs = {
        policy: sim.World(sim.Scene(bodies=[a, b], floor_friction=0.6), freeze=policy).step(240)
        for policy in ("off", "sleep")
    }
    slid = {policy: w.positions[1, 0] + 1.2 for policy, w in runs.items()}
    assert slid["off"] == pytest.approx(1.0 / (2 * 0.1 * G), rel=0.01)
    assert slid["sleep"] == pytest.approx(slid["off"], abs=1e-4)
    asleep = {step for step, *_ in runs["sleep"].events}
    assert min(asleep) >= 60  # not before B has stopped


def test_sleep_touch_wakes_the_whole_island():
    world = sim.World(knocked_stack(distance=25.0), freeze="sleep", sleep_time=0.5)
    world.step(40)
    assert awake_count(world) == 1  # the stack is asleep, the shot flies
    world.step(80)
    woken = [(b, c) for _, b, f, t, c in world.events if f == State.SLEEPING]
    assert woken[0] == (0, "touched")
    assert (1, "woken_by_island") in woken


# ---- cost: frozen bodies are out of the hot loops -----------------------------------------------
def test_frozen_bodies_leave_the_awake_list_and_come_back():
    world = sim.World(knocked_stack(), freeze="extended").step(5)
    assert awake_count(world) == 1  # only the projectile
    view = world.inspect()
    assert list(view.awake) == [2]
    assert np.all(view.solver_inv_mass[:2] == 0.0)  # frozen: zero solver mass
    # their contacts with each other and the floor left the awake contacts: only the
    # projectile's are looked at
    assert view.n_awake_contacts < view.n_contacts
    world.step(60)
    view = world.inspect()
    assert world.states[0] == State.FREE  # knocked away, still moving
    assert view.solver_inv_mass[0] == 1.0 / world.masses[0]


@pytest.mark.parametrize("policy", ("off",) + FROZEN_POLICIES)
def test_every_policy_is_deterministic(policy):
    runs = [sim.World(knocked_stack(), freeze=policy).step(150) for _ in range(2)]
    np.testing.assert_array_equal(runs[0].positions, runs[1].positions)
    assert runs[0].events == runs[1].events


@pytest.mark.parametrize("bodies", [1, 2])
def test_extended_does_not_freeze_a_body_drifting_free(bodies):
    # Without gravity a body touching nothing drifts on for ever: slow and steady is not rest.
    # Zero forces "balanced" it, and a box drifting at 1.5 cm/s (under rest_speed) was frozen
    # where it was; two boxes drifting together in contact were frozen as a group.
    boxes = [
        sim.Body.box(1, 1, position=(1.0 * k, 0.0), velocity=(0.015, 0.0)) for k in range(bodies)
    ]
    world = sim.World(sim.Scene(bodies=boxes, floor_y=None, gravity=(0.0, 0.0)), freeze="extended")
    world.step(600)
    assert world.n_awake == bodies
    # alone it has no contact, and the rest test does not look at it; two in contact are
    # tested, and refused by the certificate
    assert set(world.why_awake()) == ({"untouched"} if bodies == 1 else {"uncertified"})
    np.testing.assert_allclose(world.positions[:, 0], np.arange(bodies) + 0.15, atol=1e-9)


def test_extended_never_freezes_a_body_that_a_moving_body_touches():
    # B slides across the top of A for ~0.8 s; A, slow and held by the floor, must wait for B
    a = sim.Body.box(3.0, 0.5, position=(0.0, 0.25), friction=0.2)
    b = sim.Body.box(0.5, 0.5, position=(-1.2, 0.75), velocity=(2.0, 0.0), friction=0.2)
    world = sim.World(sim.Scene(bodies=[a, b]), freeze="extended")
    world.step(30)
    assert abs(world.velocities[1, 0]) > 0.5  # B still sliding on A
    assert not [e for e in world.events if e[1] == 0]  # A has not frozen
    world.step(90)
    rested = {b for _, b, f, t, c in world.events if c == "rested"}
    assert rested == {0, 1}  # both, once B stopped


@pytest.mark.parametrize("threshold,bounces", [(1.0, True), (100.0, False)])
def test_paper_impulse_threshold_decides_bounce_or_stay(threshold, bounces):
    # a 0.25 kg box with restitution 0.7 hits the floor at ~6.3 m/s: an impulse of ~2.7 N s
    box = sim.Body.box(0.5, 0.5, position=(0.0, 2.25), restitution=0.7)
    world = sim.World(sim.Scene(bodies=[box]), freeze="paper", impulse_threshold=threshold)
    heights = []
    for _ in range(150):
        world.step()
        heights.append(world.positions[0, 1] - 0.25)
    low = int(np.argmin(heights[:60]))
    apex = max(heights[low:])
    if bounces:
        assert apex == pytest.approx(0.7**2 * 2.0, rel=0.10)  # as `off` (section 2)
    else:
        assert apex < 0.01  # stays in contact
        assert world.states[0] == State.ROTATION_STABLE


def test_extended_a_centred_load_does_not_tip_what_carries_it():
    # a plank balanced on a narrow pedestal; a centred top plank lands and freezes on it; then a
    # light pebble lands near the plank's end. `off` never moves. The top plank's support impulse
    # must enter the frozen plank's load where it acts (at both ends of the contact), not all at
    # one point: a false moment would make the pebble's touch tip the balanced stack.
    pedestal = sim.Body.box(0.4, 1.0, position=(0.0, 0.5))
    plank = sim.Body.box(4.0, 0.2, position=(0.0, 1.1))
    top = sim.Body.box(2.0, 0.2, position=(0.0, 1.35), density=0.5)
    pebble = sim.Body.box(0.1, 0.1, position=(-1.5, 1.4), density=0.2)
    scene = sim.Scene(bodies=[pedestal, plank, top, pebble])
    ref = sim.World(scene).step(120)
    world = sim.World(scene, freeze="extended").step(120)
    assert np.abs(ref.angles[:3]).max() < 1e-3
    assert not [e for e in world.events if e[3] == State.FREE]  # nothing woke
    np.testing.assert_allclose(world.positions, ref.positions, atol=0.01)


def test_events_carry_the_number_of_the_step_that_made_them():
    # the impact wake (recorded before the solve) and the projectile's first change of velocity
    # (the collision) happen in the same step
    world = sim.World(knocked_stack(), freeze="extended")
    hit = None
    while hit is None:
        before = world.velocities[2, 0]
        world.step()
        if world.velocities[2, 0] < before - 1.0:
            hit = world.step_count
    impact = [step for step, b, f, t, c in world.events if c == "impact"]
    assert impact == [hit]
    assert all(1 <= e[0] <= world.step_count for e in world.events)


@pytest.mark.parametrize("height", [0.5, 1.5, 3.0])
def test_extended_does_not_freeze_an_overlap(height):
    """A box landing flat from a height sinks about v dt into the floor before the contact is
    seen; position correction pushes it back out over a few steps while its velocity is already
    ~0. extended must wait for that (found by fig_tradeoff: frozen at step 35, 13.4 mm deep, for
    good), so the frozen box ends no deeper than off leaves it, within twice the slop."""
    scene = sim.Scene(bodies=[sim.Body.box(1.0, 1.0, position=(0.0, 0.5 + height))])
    ends = {}
    for policy in ("off", "extended"):
        w = sim.World(scene, freeze=policy)
        w.step(240)
        ends[policy] = -float(w.vertices(0)[:, 1].min())  # depth below the floor, m
        if policy == "extended":
            assert w.frozen[0]
    assert ends["extended"] <= 2 * 0.005 + 1e-12
    assert ends["extended"] <= ends["off"] + 0.005


def test_extended_support_sees_a_woken_load_leave():
    """A frozen support's load holds the push of every body frozen on it. When such a body wakes,
    that push must leave the support's load, or the support counts the weight twice (stored and
    live) and cannot see the column above it tip: in the failure catalogue's impact_on_stack a
    hit on a frozen 4-box column toppled boxes 1-3 but never woke the base."""
    from study import scenarios

    case = scenarios.get("impact_on_stack")
    scene = case.build()
    w = sim.World(scene, freeze="extended")
    w.step(int(round(case.seconds * 60)))
    assert case.classify(scene, w.positions, w.angles) == case.expected == "toppled"
    woken = {
        body: cause
        for _, body, before, after, cause in w.events
        if before != after and after == sim.State.FREE
    }
    assert woken.get(0) == "tipping", woken


def _held_up_only_by_still_awake_bodies(world, body, frozen_before, speed_before, still):
    """Did every awake body touching ``body`` in the last step only hold it up (its impulse on
    ``body`` points up), and was each one still (slower than ``still`` m/s) before the step?"""
    points = world.contacts()
    holders = []
    for a, b, n, pn, pt in zip(
        points["body_a"],
        points["body_b"],
        points["normal"],
        points["normal_impulse"],
        points["tangent_impulse"],
    ):
        if body not in (a, b):
            continue
        other = b if a == body else a
        if not 0 <= other < world.n_bodies or frozen_before[other]:
            continue
        impulse = pn * n + pt * np.array([n[1], -n[0]])  # on B; the tangent is perp(n)
        if body == a:
            impulse = -impulse
        holds_up = impulse[1] > 0.1 * np.hypot(*impulse)  # gravity is -y
        holders.append(holds_up and speed_before[other] < still)
    return bool(holders) and all(holders)


def test_extended_does_not_wake_a_body_for_what_holds_it_up():
    # On 6f423e6 a frozen body could rest on an awake body that was still but not certified (on
    # one point, at its friction limit, in a deep contact); what that body applied to hold it up
    # counted as a push, cancelled its weight and woke it as lifted off its supports, and it froze
    # again: in drop(30) seed 4, 88 such wakes in 15 s (the pile was whole at step 712). A body now
    # freezes only with what it rests on (extended_rest.on_the_awake), and none are left.
    world = sim.World(sim.scenes.drop(30, seed=4), freeze="extended")
    still = 0.01  # m/s: half extended's rest_speed
    spurious = []
    for _ in range(15 * 60):
        frozen_before = world.frozen
        speed_before = np.hypot(*world.velocities.T) + np.abs(world.angular_velocities)
        seen = len(world.events)
        world.step()
        for _, body, _, _, cause in world.events[seen:]:
            if (
                cause in ("pushed", "tipping")
                and frozen_before[body]
                and _held_up_only_by_still_awake_bodies(
                    world, body, frozen_before, speed_before, still
                )
            ):
                spurious.append((world.step_count, body, cause))
    assert not spurious, f"{len(spurious)} wakes by a still support, first {spurious[:3]}"


#: the drop(30) seeds whose pile ``extended`` does not freeze whole, measured, each a strict xfail:
#: none of seeds 0-4 since a lane's two points are one complementarity problem
#: (soft_step.batches.two_row_impulses). Seed 2 did not until then: its body 29 (187 g, resting on
#: one point of body 5 and leaning on body 17 with that contact's friction at 100% of its limit)
#: was never certified (the certificate's 5% friction margin refuses it, by design)
UNFROZEN_PILES = {}


def _assert_freezes_whole_and_holds(seed, n=30):
    """drop(n, seed) under extended: every body frozen within 30 s, and still for 1 s more."""
    world = sim.World(sim.scenes.drop(n, seed=seed), freeze="extended")
    for _ in range(30 * 60):
        world.step()
        if world.n_awake == 0:
            break
    assert world.n_awake == 0, f"{world.n_awake} bodies still awake after 30 s"
    world.step(60)
    assert world.n_awake == 0, "the freeze did not hold for 1 s"


def _pile_seeds(count, unfrozen):
    """Seeds 0..count-1, those in ``unfrozen`` (seed: measured reason) as strict xfails."""
    return [
        pytest.param(s, marks=pytest.mark.xfail(strict=True, reason=unfrozen[s]))
        if s in unfrozen
        else s
        for s in range(count)
    ]


@pytest.mark.parametrize("seed", _pile_seeds(5, UNFROZEN_PILES))
def test_extended_freezes_a_settled_pile_whole(seed):
    # 30 polygons dropped into a bin settle within ~3 s in every peer (pymunk-sleep freezes them
    # in 118-186 steps); a rest test that certifies equilibrium must get all of them within 30 s.
    # Measured: 374, 138, 164, 153 and 277 steps (the first step with every body frozen; 172,
    # 176, 217, 179 and 261 at a109017; 194,
    # 242, never, 130 and 412 before two_row_impulses, 376, never, 196, 190 and 225 before the
    # carried split at once, and 240, 145,
    # 188, 187 and 338 before the corner contacts and the deep sweeps). With
    # impulses kept across a change of feature id the piles come fully to rest, and seed 2 then
    # never froze: bodies 4 and 10, exactly still, were refused as a pair (the solver's impulse
    # puts their contact at 98% of its friction limit under body 16's push); groups now grow
    # until they hold (five bodies), with their inside forces solved for. Before
    # wedges were certified as groups (extended_rest.wedges), seed 4 never froze: its bodies 10
    # and 21, still at 1e-15 m/s, were refused one by one (each leans on a body that rests on
    # it), and the bodies under them froze and woke every step (573 times in 10 s). On 6f423e6
    # seed 2 never stayed whole and seed 4 took 712 steps: bodies froze on still, uncertified
    # bodies and were woken by what those held them up with (see
    # test_extended_does_not_wake_a_body_for_what_holds_it_up). Bodies now wait for what they
    # rest on (test_certificate: a frozen body never clamps what it rests on), which is slower
    # than letting them freeze there with that push ignored (180, 182, 450, 142 and 194 at
    # bf3ecaf), and right; with one-point support extents (side supports left out) seed 2 never
    # froze at all.
    _assert_freezes_whole_and_holds(seed)


@pytest.mark.parametrize("seed, before", [(46, 28), (93, 26)])
def test_extended_certifies_a_still_pile_of_more_than_sixteen_bodies_as_one_group(seed, before):
    """drop(30) seeds 46 and 93 come to rest with bodies wedged between each other, their floor
    friction at its limit in the solver's witness: refused one by one, and certified only as
    one group of every still body (28 and 26 of them), whose inside forces are solved for
    (``extended_rest.wedges``). Until 2026-12 a group that grew past 16 members was not judged
    again, and
    ``before`` bodies stayed awake for good, still (1e-12 m/s), past 30 s. Measured now: whole
    at steps 202 and 321 (sleep: 180 and 149)."""
    _assert_freezes_whole_and_holds(seed)


#: drop(200) seeds whose pile ``extended`` does not freeze whole within 30 s (measured 2026-12-08,
#: 639e1b1), each a strict xfail
UNFROZEN_LARGE_PILES = {
    0: "178 of 200 bodies awake at 30 s (sleep: all asleep by step 300): parts of the pile freeze "
    "and are woken again, 1825 freezes and 1823 wakes in the last 150 steps (pushed 180, tipping "
    "112, and 1531 support_lost under them), and the certificate costs 0.34 of a 0.65 ms step",
    2: "186 of 200 bodies awake at 30 s (sleep: all asleep by step 200): the same churn",
}


@pytest.mark.parametrize("seed", _pile_seeds(3, UNFROZEN_LARGE_PILES))
def test_extended_freezes_a_pile_of_two_hundred_whole(seed):
    """The piles of fig_time_to_rest hold 30 bodies; bench_step times 200 settling under
    sim-off only. Seed 1 froze whole by step 1100 (sleep: 200)."""
    _assert_freezes_whole_and_holds(seed, n=200)


def test_extended_wakes_a_column_being_built_only_for_its_landings():
    """A 10-box column dropped box by box (table_extremes' dt axis) at 1/480 s: a step is short
    enough for ``extended`` to certify and freeze the lower boxes between two landings, and the
    landings wake them again (each of the lowest seven once; the lowest 3 times while the column
    rocked, before soft_step.batches.two_row_impulses, which the table's rule counts as
    chattering: test_extremes_regression). Every wake comes within 0.02 s after a box lands
    (box k, falling freely from (k + 1) gaps up, lands at sqrt(2 (k + 1) gap / g); its
    speculative contact may catch it a step early): the landing itself, or the load it sends
    down the column, measured 0 to 9 steps after it. The column stands."""
    from study.extremes.scenes import dropped_column

    dt = 1 / 480
    scene = dropped_column(10)
    landings = [
        math.sqrt(2 * (k + 1) * scene.params["gap"] / G) / dt for k in range(scene.params["height"])
    ]
    world = sim.World(scene, dt=dt, freeze="extended")
    world.step(int(round(1.0 / dt)))
    wakes = [(step, body) for step, body, was, now, _ in world.events if now == State.FREE != was]
    assert wakes
    late = [(s, b) for s, b in wakes if not any(-2 <= s - t <= 0.02 / dt for t in landings)]
    assert not late, f"wakes not within 0.02 s after a landing (step, body): {late}"
    # stands: measured 0.04 mm from the stacked pose (3.0 mm while the column rocked; off 8.8 mm,
    # sideways, then, 0 now)
    assert np.abs(world.positions - scene.params["rest_pose"]).max() < 2e-4


@pytest.mark.parametrize("speed, stays", [(0.9, True), (1.2, False)])
def test_paper_a_flat_landing_s_collision_impulse_is_the_body_s_momentum(speed, stays):
    # A 1 kg square arriving flat at the floor: stopping it takes m v at its two corners together
    # (contact_math.approach_impulses), so at threshold 1 N s it stays in contact (RS in its
    # landing step) at 0.9 m/s and bounces by its impulse at 1.2 m/s. Each corner taken alone,
    # the estimate was 0.8 m v: 0.96 N s at 1.2 m/s, and the box was held at once.
    box = sim.Body.box(1.0, 1.0, position=(0.0, 0.501), velocity=(0.0, -speed))
    world = sim.World(sim.Scene(bodies=[box]), freeze="paper", impulse_threshold=1.0).step(1)
    assert (world.states[0] == State.ROTATION_STABLE) == stays


def test_paper_a_box_tipping_off_an_edge_falls_as_under_off():
    # A 0.8 m box lies on B with its centre of mass 0.1 m past B's edge: it tips off about B's
    # corner, onto the floor. That corner touches A's face, not a vertex of A: no VS pivot
    # (section 4.1). Pivoting on A's vertex nearest the corner, `paper` hung A by its far corner
    # in mid air (-133 degrees at step 120).
    def run(freeze):
        b = sim.Body.box(2.0, 1.0, position=(0.0, 0.5))
        a = sim.Body.box(0.8, 0.4, position=(1.1, 1.2))
        return sim.World(sim.Scene(bodies=[b, a]), freeze=freeze).step(120)

    paper, off = run("paper"), run("off")
    assert off.positions[1, 1] == pytest.approx(0.2, abs=0.01)  # on the floor
    assert np.abs(paper.positions[1] - off.positions[1]).max() < 0.02  # measured 4 mm
    assert abs(math.remainder(paper.angles[1] - off.angles[1], 2 * math.pi)) < 0.01


def test_paper_holds_a_vertical_stable_body_only_against_what_it_touches():
    # Section 5.1 holds a VS body in contact with an RS one. B stands on one corner, tilted 30
    # degrees, 1 cm from the resting box A: not in contact (A's speculative reach is 2 cm, the
    # pair's slop 5 mm). B must go on turning, as it does alone; it was held at step 3, for good.
    tilt = math.radians(30.0)
    lowest = 0.5 * (math.sin(tilt) + math.cos(tilt))
    a = sim.Body.box(1.0, 1.0, position=(0.0, 0.5))
    b = sim.Body.box(1.0, 1.0, position=(0.5 + 0.01 + lowest, lowest), angle=tilt)
    world = sim.World(sim.Scene(bodies=[a, b]), freeze="paper").step(20)
    assert "held_by_contact" not in [c for _, body, _, _, c in world.events if body == 1]
    assert world.angles[1] < tilt - 0.1  # still turning down onto its face


@pytest.mark.parametrize("speed", [0.5, 0.9, 1.5])
def test_paper_a_slow_slider_does_not_pass_through_a_frozen_box(speed):
    """A 1 m box sliding on a frictionless floor into a frozen 1 m box. The slider is sliding
    ROTATION_STABLE under ``paper``, immovable to the solver like the frozen box: below the
    impulse threshold (1 N s) the two were never solved against each other, and the slider
    passed through (at 0.5 and 0.9 m/s, until 2026-12-07). It pushes the box on, as under
    ``off``: equal boxes, a perfectly inelastic hit, both at speed / 2."""
    target = sim.Body.box(1.0, 1.0, position=(0.0, 0.5), friction=0.0)
    mover = sim.Body.box(1.0, 1.0, position=(-1.5, 0.5), velocity=(speed, 0.0), friction=0.0)
    scene = sim.Scene(bodies=[target, mover], floor_friction=0.0)
    finals = {}
    for freeze in ("off", "paper"):
        world = sim.World(scene, freeze=freeze)
        world.step(120)
        finals[freeze] = world.positions[:, 0].copy(), world.velocities[:, 0].copy()
    x, v = finals["paper"]
    assert x[1] < x[0] - 0.99  # the mover is still behind the target
    np.testing.assert_allclose(x, finals["off"][0], atol=0.01)
    np.testing.assert_allclose(v, [speed / 2, speed / 2], atol=0.01)
