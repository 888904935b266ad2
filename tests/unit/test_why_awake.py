"""``World.why_awake``: which stage of ``extended``'s rest test keeps each awake body awake.

Each reason is checked on a scene whose answer is known from its physics (a body at the top of
its flight, a hexagon gliding to a stop on ice, a box on a ramp its friction cannot quite hold,
a triangle balanced on its apex), and on a settling pile against what the reason claims (a
"moving" body is at least rest_speed fast, a "deep" one has a contact deeper than twice its
slop)."""

import math

import numpy as np
import pytest

import sim
from conftest import G
from test_certificate import _on_ramp, _triangle_on_its_apex_carrying_a_box

DT = 1.0 / 60.0
REST_SPEED = 0.02  # extended's default rest_speed, m/s
SLIP_SPEED = 1e-3  # extended's default slip_speed, m/s


def _reasons(world, steps):
    """why_awake() after each step, one step at a time."""
    out = []
    for _ in range(steps):
        world.step()
        out.append(list(world.why_awake()))
    return out


@pytest.mark.parametrize(
    "beside_a_wall, at_the_top, pairs", [(True, "changing", {(0, 1)}), (False, "untouched", set())]
)
def test_a_body_at_the_top_of_its_flight_is_not_still(beside_a_wall, at_the_top, pairs):
    """A box thrown up at 3 g dt stops at the end of step 3 (v = v0 - g t, exact for the
    integrator); before and after, faster than rest_speed, it is "moving". Beside a frictionless
    static wall it touches (a contact every step, whose points take no impulse) it is tested every
    step: at the top it is slow, but its velocity changes by g dt a step, so it is "changing".
    Alone it has no contact: nothing can hold it, and the rest test does not look at it:
    "untouched"."""
    box = sim.Body.box(0.5, 0.5, position=(0.0, 3.0), velocity=(0.0, 3 * G * DT), friction=0.0)
    wall = sim.Body.box(1.0, 10.0, position=(0.75, 5.0), friction=0.0, name="wall")
    scene = sim.Scene(bodies=[box], static_bodies=[wall] if beside_a_wall else [])
    world = sim.World(scene, freeze="extended")
    moving = ["moving", "moving"]
    assert [r[0] for r in _reasons(world, 5)] == moving + [at_the_top] + moving
    c = world.contacts()
    assert set(zip(c["body_a"].tolist(), c["body_b"].tolist())) == pairs


def test_a_body_first_tested_is_not_yet_steady():
    """A 10 cm box drifting at 1.9 cm/s (below rest_speed) in zero gravity along a static rail
    1 mm below it (a contact every step, with points and no impulse), off its end, and on to a
    static wall 25 cm ahead. Along the rail it is tested every step, steady, and refused by the
    certificate ("uncertified": nothing holds it against its drift); once its fat box has left
    the rail's it has no contact ("untouched"); in the step its fat box first meets the wall's
    it is "changing" though its velocity never changed: it was not tested in the step before,
    so there is no change to measure (its last test's velocity, along the rail, is the same:
    compared with it, it would pass). Its first step is measured against the velocity it
    started with (``extended.initial``): steady, so "uncertified" at once."""
    speed = 0.019
    box = sim.Body.box(0.1, 0.1, position=(0.0, 3.0), velocity=(speed, 0.0))
    rail = sim.Body.box(1.0, 0.2, position=(-0.5, 3.0 - 0.05 - 0.1 - 0.001), name="rail")
    wall = sim.Body.box(0.2, 1.0, position=(0.35, 3.0), name="wall")
    scene = sim.Scene(bodies=[box], static_bodies=[rail, wall], floor_y=None, gravity=(0.0, 0.0))
    world = sim.World(scene, freeze="extended")
    phases = []  # (reason, contacts, the box's x) at each change of the first two
    while len(phases) < 4 and world.step_count < 900:
        world.step()
        now = (world.why_awake()[0], world.inspect().n_contacts)
        if not phases or phases[-1][:2] != now:
            phases.append((*now, world.positions[0, 0]))
        assert world.velocities[0].tolist() == [speed, 0.0]  # nothing has pushed it
    assert [p[:2] for p in phases] == [
        ("uncertified", 1),  # from the first step, on the rail
        ("untouched", 0),
        ("changing", 1),  # the wall's contact, its first since the rail's
        ("uncertified", 1),
    ]
    assert phases[1][2] > 0.05 and phases[2][2] > phases[1][2] + 0.05  # off the rail, then on


def test_the_first_step_is_measured_from_the_starting_velocity():
    """A box started at 3 m/s into the floor 1 mm below it (restitution 0) is stopped in step 1:
    its velocity changed by 3 m/s, so it is "changing" and stays awake. Its saved "previous"
    velocity had been zero, as if it had started at rest, and it was frozen in step 1. A box
    placed on the floor at rest still freezes in step 1."""
    thrown = sim.Body.box(0.5, 0.5, position=(0.0, 0.251), velocity=(0.0, -3.0), restitution=0.0)
    world = sim.World(sim.Scene(bodies=[thrown]), freeze="extended").step()
    assert abs(world.velocities[0, 1]) < 0.02  # stopped: slow after step 1
    assert world.why_awake().tolist() == ["changing"]
    placed = sim.Body.box(0.5, 0.5, position=(0.0, 0.25))
    world = sim.World(sim.Scene(bodies=[placed]), freeze="extended").step()
    assert world.frozen.tolist() == [True]


@pytest.mark.parametrize("gap,woken_at", [(0.19, 4), (0.25, 5)])
def test_a_body_woken_after_it_froze_is_changing(gap, woken_at):
    """A box resting on the floor freezes in step 3; a small box falling onto it at 3 m/s wakes
    it in step 4 or 5, by the gap. Its first test after waking has no velocity from the step
    before to compare with (it was frozen, and immovable in the solve), so it is "changing",
    whichever the step: woken in the step right after the freeze, it was compared with its
    velocity from before the freeze and passed as steady."""
    a = sim.Body.box(1.0, 0.5, position=(0.0, 0.254))
    b = sim.Body.box(0.3, 0.3, position=(0.0, 0.654 + gap), velocity=(0.0, -3.0))
    world = sim.World(sim.Scene(bodies=[a, b]), freeze="extended")
    frozen = []
    while world.step_count < woken_at:
        world.step()
        frozen.append(bool(world.frozen[0]))
    assert frozen == [False, False] + [True] * (woken_at - 3) + [False]
    assert world.why_awake()[0] == "changing"


def test_a_stack_waits_rest_steps_before_freezing():
    world = sim.World(sim.scenes.stack(3), freeze="extended", rest_steps=4)
    assert _reasons(world, 4) == [["counting"] * 3] * 3 + [[""] * 3]


def test_a_hexagon_gliding_on_ice_is_sliding_from_when_it_is_slow_until_it_stops():
    """v(t) = v0 - mu g t: slower than rest_speed from t = (v0 - rest_speed) / (mu g) (step 92),
    then held awake by its friction at the Coulomb limit ("sliding") until it stops at
    v0 / (mu g) (step 153), and frozen. Once it slips slower than slip_speed (1 mm/s) its
    contact is no longer "sliding", but its momentum is more than its friction can stop in a
    step (mu g dt = 0.33 mm/s), so it is not certified ("uncertified": the certificate's
    MOTION) for the last steps until it stops."""
    speed, mu = 0.05, 0.002
    hexagon = sim.Body.regular(6, 0.4, velocity=(speed, 0.0), friction=mu)
    hexagon.position = (0.0, 0.4 * math.cos(math.pi / 6))
    world = sim.World(sim.Scene(bodies=[hexagon], floor_friction=mu), freeze="extended")
    reasons = [r[0] for r in _reasons(world, 240)]
    slow = (speed - REST_SPEED) / (mu * G) / DT
    stops = speed / (mu * G) / DT
    first_slow = reasons.index("sliding") + 1
    assert abs(first_slow - slow) <= 2
    assert set(reasons[: first_slow - 1]) == {"moving"}
    frozen_at = reasons.index("") + 1
    gliding = reasons[first_slow - 1 : frozen_at - 1]
    last_slip = gliding.index("uncertified") if "uncertified" in gliding else len(gliding)
    assert set(gliding[:last_slip]) == {"sliding"}
    slip_steps = SLIP_SPEED / (mu * G * DT)
    assert set(gliding[last_slip:]) <= {"uncertified"} and len(gliding) - last_slip <= slip_steps
    assert abs(frozen_at - stops) <= 5


def test_a_box_on_a_ramp_just_short_of_holding_is_sliding():
    """tan(slope) = 1.002 mu: it accelerates at g (sin - mu cos) ~ 1 cm/s^2, slower than
    rest_speed for its first 1.5 s, and is kept awake by its sliding contact."""
    mu = 0.6
    slope = math.atan(1.002 * mu)
    accel = G * (math.sin(slope) - mu * math.cos(slope))
    assert accel * 1.5 < REST_SPEED
    world = sim.World(_on_ramp(slope, mu), freeze="extended")
    reasons = [r[0] for r in _reasons(world, 90)]
    assert set(reasons[10:]) == {"sliding"}
    assert not world.frozen[0]


def test_a_triangle_on_its_apex_is_uncertified_and_the_box_on_it_waits_for_it():
    """One support point never certifies rest; the box on the triangle's top is certified, but
    must not freeze on a body that stays awake. The box is placed with its face parallel to the
    triangle's top face, its centre above the apex: 0.5 mm above the face's higher corner. In the
    first step it falls onto the face, and that gap, closing, keeps both awake ("closing")."""
    world = sim.World(_triangle_on_its_apex_carrying_a_box(1e-3), freeze="extended")
    assert _reasons(world, 30) == [["closing", "closing"]] + [["uncertified", "on_awake"]] * 29


def test_a_still_box_waits_for_its_neighbour_while_another_slides_on_what_carries_it():
    """B slides across the long box A; A's contact with B slips at its friction limit, so A is
    "sliding" too; C, still on A's far end, waits for its neighbour A. Once B stops, all freeze."""
    a = sim.Body.box(3.0, 0.5, position=(0.0, 0.25), friction=0.2)
    b = sim.Body.box(0.5, 0.5, position=(-1.2, 0.75), velocity=(2.0, 0.0), friction=0.2)
    c = sim.Body.box(0.3, 0.3, position=(1.3, 0.65), friction=0.2)
    world = sim.World(sim.Scene(bodies=[a, b, c]), freeze="extended")
    world.step(30)
    assert list(world.why_awake()) == ["sliding", "moving", "neighbour"]
    world.step(120)
    assert list(world.why_awake()) == ["", "", ""]
    assert world.frozen.all()


def test_every_awake_body_of_a_settling_pile_has_the_reason_its_state_shows():
    world = sim.World(sim.scenes.drop(30, seed=0), freeze="extended")
    seen = set()
    for _ in range(200):
        world.step()
        reasons = world.why_awake()
        np.testing.assert_array_equal(reasons == "", world.frozen)
        speed = (
            np.hypot(*world.velocities.T)
            + np.abs(world.angular_velocities) * (world.extents[: world.n_bodies])
        )
        np.testing.assert_array_equal(speed >= REST_SPEED, reasons == "moving")
        contacts = world.contacts()
        for body in np.flatnonzero(reasons == "deep"):
            mine = (contacts["body_a"] == body) | (contacts["body_b"] == body)
            assert np.any(contacts["end_separation"][mine] < -2 * contacts["slop"][mine])
        seen.update(reasons.tolist())
    # what a pile waits for once nothing is moving: measured on this seed
    assert {"deep", "neighbour", "sliding"} <= seen


def test_before_its_first_step_no_body_has_been_tested():
    world = sim.World(sim.scenes.stack(2), freeze="extended")
    assert list(world.why_awake()) == ["untested", "untested"]
    world.step()
    assert list(world.why_awake()) == ["", ""]  # placed at rest: certified in the first step


@pytest.mark.parametrize("policy", ["off", "sleep", "paper"])
def test_only_extended_says_why_a_body_is_awake(policy):
    world = sim.World(sim.scenes.stack(2), freeze=policy)
    with pytest.raises(ValueError, match="only freeze='extended'"):
        world.why_awake()


def test_the_deep_and_the_sliding_stage_each_have_their_own_speed():
    """``opening_speed`` sets the deep stage (a contact deeper than twice its slop still opening
    faster than it), ``slip_speed`` the sliding one. One speed served both until 2026-12: a
    larger slip_speed, to let slow slides through, switched the deep stage off as well."""

    def seen(**parameters):
        world = sim.World(sim.scenes.drop(30, seed=0), freeze="extended", **parameters)
        out = set()
        for _ in range(200):
            world.step()
            out.update(world.why_awake().tolist())
        return out

    assert {"deep", "sliding"} <= seen()
    off = 1e3  # m/s: no contact slips or opens this fast
    only_deep = seen(slip_speed=off)
    assert "deep" in only_deep and "sliding" not in only_deep
    only_sliding = seen(opening_speed=off)
    assert "deep" not in only_sliding and "sliding" in only_sliding
