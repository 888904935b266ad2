"""``extended``'s wake rules judge a frozen body's load the way the physics does: the supports'
friction cones about their own normals (a slope), the changes on a frozen body reaching the
frozen bodies under it (a tower), and a body frozen with no known support moved by any push
(no gravity). Each scene is run under ``off`` too, and ``extended`` must do what ``off`` does;
where there is an analytic answer, both are checked against it."""

import math

import numpy as np
import pytest

import sim

SLOPE = math.radians(28.0)
SLOPE_FRICTION = 0.6  # tan 28 deg = 0.53: the box alone holds


def _slope_scene(pusher_density):
    """A 1 m box (1 kg) at rest on a 28 degree static slope, and a frictionless 1 m box of
    ``pusher_density`` released 2.2 cm uphill of it, which slides into it and keeps pushing."""
    down = np.array([math.cos(SLOPE), -math.sin(SLOPE)])
    normal = np.array([math.sin(SLOPE), math.cos(SLOPE)])
    ramp = sim.Body.box(40.0, 2.0, position=tuple(-normal), angle=-SLOPE, friction=SLOPE_FRICTION)
    box = sim.Body.box(
        1.0, 1.0, position=tuple(0.5 * normal), angle=-SLOPE, friction=SLOPE_FRICTION
    )
    pusher = sim.Body.box(
        1.0,
        1.0,
        position=tuple(-1.022 * down + 0.5 * normal),
        angle=-SLOPE,
        friction=0.0,
        density=pusher_density,
    )
    scene = sim.Scene(bodies=[box, pusher], static_bodies=[ramp], floor_y=-30.0)
    return scene, down


def _slid(scene, down, freeze, seconds):
    world = sim.World(scene, freeze=freeze)
    start = world.positions.copy()
    world.step(int(round(seconds * 60)))
    return float((world.positions[0] - start[0]) @ down), world


@pytest.mark.parametrize("pusher_density", [0.15, 0.25])
def test_a_box_frozen_on_a_slope_slides_when_a_push_exceeds_its_friction(pusher_density):
    """The box uses 0.53 of its 0.6 friction to hold its own weight on the slope, so a push down
    the slope of (0.6 cos - sin) = 0.06 of its weight moves it. The pusher's weight along the
    slope, 0.07 and 0.12 of the box's, does: Coulomb gives the pair an acceleration of
    g ((1 + k) sin - mu cos) / (1 + k), 0.03 and 0.45 m/s^2. Until 2026-12-07 the frozen box
    judged the push against a cone of 0.6 about its support impulses' direction (straight up),
    held 0.6 of its weight, and stayed frozen on the slope for good."""
    scene, down = _slope_scene(pusher_density)
    seconds = 2.0
    k = pusher_density
    acceleration = 9.81 * ((1 + k) * math.sin(SLOPE) - SLOPE_FRICTION * math.cos(SLOPE)) / (1 + k)
    off, _ = _slid(scene, down, "off", seconds)
    extended, world = _slid(scene, down, "extended", seconds)
    assert world.events and world.events[0][4] == "rested"  # frozen first, then woken
    # the pusher reaches the box after ~0.2 s; from then on the pair accelerates
    assert off > 0.5 * acceleration * (seconds - 0.4) ** 2
    assert extended == pytest.approx(off, abs=0.02 + 0.05 * off)


def test_a_box_frozen_on_a_slope_holds_a_push_its_friction_can_hold():
    """At 20 degrees the box uses 0.36 of its 0.6 friction: the light pusher's weight (0.15 of
    the box's) keeps the pair at rest, and nothing wakes for good."""
    angle = math.radians(20.0)
    down = np.array([math.cos(angle), -math.sin(angle)])
    normal = np.array([math.sin(angle), math.cos(angle)])
    ramp = sim.Body.box(40.0, 2.0, position=tuple(-normal), angle=-angle, friction=0.6)
    box = sim.Body.box(1.0, 1.0, position=tuple(0.5 * normal), angle=-angle, friction=0.6)
    pusher = sim.Body.box(
        1.0,
        1.0,
        position=tuple(-1.002 * down + 0.5 * normal),
        angle=-angle,
        friction=0.0,
        density=0.15,
    )
    scene = sim.Scene(bodies=[box, pusher], static_bodies=[ramp], floor_y=-30.0)
    slid, world = _slid(scene, down, "extended", 3.0)
    assert abs(slid) < 0.01
    assert world.frozen[0]


def _tower(block_x):
    """A pedestal 0.2 m wide, a 1 m plate centred on it, a 2 m plank centred on the plate, and a
    0.3 kg block dropped 2.2 cm onto the plank at ``block_x`` (slow: no impact wake)."""
    bodies = [
        sim.Body.box(0.2, 1.0, position=(0.0, 0.5)),
        sim.Body.box(1.0, 0.2, position=(0.0, 1.1)),
        sim.Body.box(2.0, 0.2, position=(0.0, 1.3)),
        sim.Body.box(0.2, 0.2, position=(block_x, 1.522), density=7.5),
    ]
    return sim.Scene(bodies=bodies)


@pytest.mark.parametrize("block_x", [0.45, -0.6])
def test_a_block_landing_on_a_frozen_tower_tips_it_where_the_towers_balance_is_lost(block_x):
    """The plate, plank and block have their centre of mass at 0.3 x / 0.9 (0.15 m, -0.2 m): past
    the pedestal's edge (0.1 m), so the tower tips, though the plank holds on the plate and the
    block on the plank. Until 2026-12-07 the block's load was judged against the plank's
    supports only, and all four stayed frozen, level, where ``off``'s fell."""
    scene = _tower(block_x)
    finals = {}
    for freeze in ("off", "extended"):
        world = sim.World(scene, freeze=freeze)
        world.step(240)
        finals[freeze] = world.positions.copy(), world.angles.copy()
    assert abs(finals["off"][1][1]) > 1.0  # the plate fell over
    assert abs(finals["extended"][1][1]) > 1.0
    assert np.abs(finals["extended"][0][1] - finals["off"][0][1]).max() < 0.3


def test_a_block_landing_on_a_frozen_tower_within_its_balance_leaves_it_frozen():
    """The same tower with the block at 0.2 m: the centre of mass at 0.067 m, over the pedestal.
    It stands as under ``off`` (tilted ~2 mrad by the soft contacts under the off-centre load),
    and everything freezes again."""
    angles = {}
    for freeze in ("off", "extended"):
        world = sim.World(_tower(0.2), freeze=freeze)
        world.step(240)
        angles[freeze] = world.angles
    assert world.frozen.all()
    assert np.abs(angles["off"]).max() < 0.01
    np.testing.assert_allclose(angles["extended"], angles["off"], atol=2e-3)


def test_a_body_frozen_without_gravity_moves_when_pushed():
    """Without gravity a box frozen against a wall has no support: its load is zero, and any
    push moves it. A box drifting onto it along the wall pushes it along as under ``off``
    (momentum passed on). The wake comes with the push, not before it: until 2026-12-07 a zero
    load counted as "lifted off its supports", the box woke "pushed" when the other came within
    its contact margin, and, judged about a made-up normal, it could hold a push toward one
    side."""
    wall = sim.Body.box(1.0, 10.0, position=(-1.0, 0.0), friction=0.0)
    a = sim.Body.box(1.0, 1.0, position=(0.0, 0.0), friction=0.0)
    b = sim.Body.box(1.0, 1.0, position=(0.0, 1.3), velocity=(0.0, -0.3), friction=0.0)
    scene = sim.Scene(bodies=[a, b], static_bodies=[wall], floor_y=None, gravity=(0.0, 0.0))
    worlds = {}
    for freeze in ("off", "extended"):
        world = sim.World(scene, freeze=freeze)
        world.step(120)
        worlds[freeze] = world
    ext, off = worlds["extended"], worlds["off"]
    assert ext.events[0][4] == "rested"
    np.testing.assert_allclose(ext.velocities, off.velocities, atol=1e-3)
    np.testing.assert_allclose(ext.positions, off.positions, atol=5e-3)
    woken = [step for step, body, _, _, cause in ext.events if body == 0 and cause != "rested"]
    # b starts 0.3 m above a: contact within its margin from step ~50, the push at step ~60
    assert woken and woken[0] >= 58
