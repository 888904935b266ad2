"""Input at the edges of what a number, a policy or a turn can be: refused with a ValueError that
names the field (never a bare OverflowError, a pickling TypeError from inside World(), or a
silently wrong run), and the runs these limits protect."""

import threading

import numpy as np
import pytest

import sim
from sim.body import MAX_ANGLE

HUGE = 10**400  # an int no float can hold: float() raises OverflowError
B = sim.Body.box


def resting_box(**kwargs):
    return B(1, 1, position=(0, 0.5), **kwargs)


@pytest.mark.parametrize(
    "build, match",
    [
        (lambda: B(1, 1, density=HUGE), "body: density is not finite"),
        (lambda: B(1, 1, density=-HUGE), "body: density is not finite"),
        (lambda: B(1, 1, angle=HUGE), "body: angle is not finite"),
        (lambda: B(1, 1, position=(HUGE, 0)), "body: position is not finite"),
        (lambda: B(HUGE, 1), "box: width is not finite"),
        (lambda: sim.Body.regular(5, HUGE), "radius must be > 0 and finite, got an integer beyond"),
        (lambda: sim.Body(vertices=[(0, 0), (HUGE, 0), (0, 1)]), "beyond float's range"),
        (lambda: sim.Scene([resting_box()], gravity=(0, -HUGE)), "scene: gravity is not finite"),
        (lambda: sim.Scene([resting_box()], floor_y=HUGE), "scene: floor_y is not finite"),
        (
            lambda: sim.Scene.from_arrays(B(1, 1).vertices, [(0, 0.5)], density=HUGE),
            "from_arrays: density must be numbers",
        ),
    ],
)
def test_an_integer_beyond_floats_range_is_a_value_error_naming_the_field(build, match):
    with pytest.raises(ValueError, match=match):
        build()


@pytest.mark.parametrize("radius", [True, False, "1", float("inf"), -1.0])
def test_a_regular_polygons_radius_is_a_positive_number_not_a_switch(radius):
    # Body.box(True, 1) was refused while Body.regular(5, True) built a polygon of radius 1
    with pytest.raises(ValueError, match="radius must be > 0 and finite"):
        sim.Body.regular(5, radius)
    assert sim.Body.regular(5, 2).vertices.shape == (5, 2)


def test_an_angle_beyond_max_angle_is_refused_and_one_within_it_still_turns():
    """At 1e15 rad a body spinning at 1 rad/s kept its angle for good (the spacing of floats
    there is 0.125 rad); at MAX_ANGLE a step's turn is resolved."""
    for build in (
        lambda a: B(1, 1, angle=a),
        lambda a: sim.Scene.from_arrays(B(1, 1).vertices, [(0, 0.5)], angle=[a]),
    ):
        with pytest.raises(ValueError, match=r"angle 1000001 rad is beyond 1e\+06 rad"):
            build(MAX_ANGLE + 1.0)
        with pytest.raises(ValueError, match="beyond"):
            build(-2 * MAX_ANGLE)
    spinning = B(1, 1, position=(0, 5), angle=MAX_ANGLE, angular_velocity=1.0)
    world = sim.World(sim.Scene([spinning], gravity=(0, 0)))
    world.step(60)
    assert world.angles[0] - MAX_ANGLE == pytest.approx(1.0, rel=1e-6)


@pytest.mark.parametrize("value", [2.0, True, np.float64(3.0), 0, 2.5])
def test_an_integer_policy_parameter_must_be_an_int_like_the_worlds_counts(value):
    # rest_steps=2.0 was taken where substeps=2.0 is refused; True was "must be a number"
    with pytest.raises(ValueError, match=r"rest_steps must be an integer >= 1 \(and < 2\*\*62\)"):
        sim.World(sim.scenes.single_box(), freeze="extended", rest_steps=value)
    world = sim.World(sim.scenes.single_box(), freeze="extended", rest_steps=np.int64(3))
    assert world.policy_parameters["rest_steps"] == 3


@pytest.mark.parametrize(
    "kwargs, cap",
    [
        ({"substeps": 1001}, "MAX_SUBSTEPS"),
        ({"iterations": 1001}, "MAX_SWEEPS"),
        ({"relax_iterations": 1001}, "MAX_SWEEPS"),
        ({"initial_iterations": 10**6 + 1}, "MAX_INITIAL_ITERATIONS"),
    ],
)
def test_a_count_beyond_its_cap_names_that_cap(kwargs, cap):
    # substeps=1001 was refused "(see sim.validation.MAX_SWEEPS)", the wrong cap
    with pytest.raises(ValueError, match=rf"see sim\.validation\.{cap}\)$"):
        sim.World(sim.scenes.single_box(), **kwargs)


@pytest.mark.parametrize("gravity", [(0.0, 9.81), (9.81, -9.81), (0.0, 0.0), (-1.0, 0.0)])
def test_paper_needs_gravity_straight_down(gravity):
    """The seed's floor test and vertical holds assume gravity along -y: under (0, 9.81) paper
    froze a box on the floor that off sends upward (to y = 5.4 in 1 s)."""
    scene = sim.Scene([resting_box()], gravity=gravity)
    with pytest.raises(ValueError, match=r"freeze='paper' needs gravity straight down"):
        sim.World(scene, freeze="paper")
    for freeze in ("off", "sleep", "extended"):
        sim.World(scene, freeze=freeze)
    sim.World(sim.Scene([resting_box()], gravity=(0.0, -1.62)), freeze="paper")


def test_extended_lets_a_box_fall_upward_under_upward_gravity():
    """What paper could not do: under gravity (0, 9.81) the box leaves the floor, as under off."""
    worlds = {}
    for freeze in ("off", "extended"):
        worlds[freeze] = sim.World(sim.Scene([resting_box()], gravity=(0, 9.81)), freeze=freeze)
        worlds[freeze].step(60)
    assert worlds["off"].positions[0, 1] == pytest.approx(0.5 + 9.81 / 2, abs=0.1)
    assert worlds["extended"].positions[0, 1] == worlds["off"].positions[0, 1]


def test_scene_params_that_cannot_be_copied_are_a_value_error():
    scene = sim.Scene([resting_box()], params={"lock": threading.Lock()})
    with pytest.raises(ValueError, match="scene: params must be plain data that can be copied"):
        sim.World(scene)


@pytest.mark.parametrize("spin", [500.0, 2000.0])
def test_a_spinning_box_far_from_everything_is_not_pushed(spin):
    """A turn carries a point at most the body's width: a 1 m box spinning 4.3 m above the floor
    (its lowest reach), without gravity, makes no contact. Its reach was the arc of the turn (23 m
    at 2000 rad/s): contacts were made with the floor, and at 2000 rad/s it was thrown upward at
    45 m/s."""
    box = B(1, 1, position=(0, 5), angular_velocity=spin)
    world = sim.World(sim.Scene([box], gravity=(0, 0)))
    world.step(10)
    assert len(world.contacts()["body_a"]) == 0
    assert np.array_equal(world.positions[0], [0.0, 5.0])
    assert world.velocities[0].tolist() == [0.0, 0.0] and world.angular_velocities[0] == spin
