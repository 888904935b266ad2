"""study.scenarios: every failure scenario's truth is what physics says, its classifier can
tell the outcomes apart, and its scheduled danger arrives only after the scene has been at rest.

The truth is sim-off at a fine step, exactly as in the failure table (its FULL configuration:
dt 1/480 s, sim's default 4 substeps, 4 biased sweeps per substep). Each scenario also has a
control that must end the *other* way (a tipping body placed short of its tipping angle
stands...), so a classifier that always answered the expected label would fail."""

import math

import numpy as np
import pytest

import sim
from study import scenarios as S
from study.common import DT
from experiments.table_failures import FULL as TRUTH

FINE_DT = DT / TRUTH["truth_divisor"]
ITERATIONS = TRUTH["truth_iterations"]  # biased sweeps per substep
G = 9.81


def run(scene, seconds, dt=FINE_DT, freeze="off", iterations=ITERATIONS):
    world = sim.World(scene, dt=dt, iterations=iterations, freeze=freeze)
    world.step(int(round(seconds / dt)))
    return world


def outcome(name, **overrides):
    scenario = S.get(name)
    scene = scenario.build(**overrides)
    world = run(scene, scenario.duration(scene))
    return (
        scenario.classify(scene, world.positions, world.angles),
        scenario.measure(scene, world.positions, world.angles),
        world,
    )


@pytest.mark.parametrize("name", list(S.SCENARIOS))
def test_truth_is_what_physics_says(name):
    label, _, _ = outcome(name)
    assert label == S.get(name).expected


@pytest.mark.parametrize("name", list(S.SCENARIOS))
def test_the_start_is_not_already_the_expected_outcome(name):
    """The classifier reads the outcome off the pose: the initial pose must not pass for it."""
    scenario = S.get(name)
    scene = scenario.build()
    start_p = np.array([b.position for b in scene.bodies])
    start_a = np.array([b.angle for b in scene.bodies])
    label = scenario.classify(scene, start_p, start_a)
    assert label in scenario.labels and label != scenario.expected


def test_slow_sliding_travels_v2_over_2_mu_g():
    _, fraction, world = outcome("slow_sliding")
    assert abs(fraction - 1.0) < 0.02  # of v^2 / (2 mu g) = 8.2 cm
    assert abs(world.velocities[0, 0]) < 1e-6  # and stopped (after v / (mu g) = 4.1 s)


def test_slope_creep_accelerates_at_g_sin_minus_mu_cos():
    scene = S.get("slope_creep").build()
    theta, mu = scene.params["theta_rad"], scene.params["friction"]
    assert G * (math.sin(theta) - mu * math.cos(theta)) == pytest.approx(0.05, rel=1e-9)
    _, fraction, _ = outcome("slope_creep")
    assert abs(fraction - 1.0) < 0.02  # of a t^2 / 2 = 0.9 m


def test_slope_short_of_its_friction_angle_holds():
    label, fraction, _ = outcome("slope_creep", acceleration=-0.05)
    assert label == "stuck" and abs(fraction) < 0.01


def test_tipping_short_of_the_tipping_angle_stands_back_up():
    label, _, _ = outcome("tipping", past_deg=-5.0)
    assert label == "upright"


def test_plank_with_its_centre_of_mass_inside_stays_balanced():
    label, drop, _ = outcome("unstable_equilibrium", past=-0.02)
    assert label == "balanced" and abs(drop) < 0.01


def test_three_bodies_within_the_edge_stand():
    """offset 0.3: the top two together at 0.45 m, inside the bottom box's edge at 0.5 m."""
    label, _, _ = outcome("three_bodies", offset=0.3)
    assert label == "stood"


def test_overhang_short_of_the_edge_stays_on():
    """A would slide v^2 / (2 mu g) = 0.64 m at 1.58 m/s: its centre stops 0.16 m short of B's
    edge."""
    label, _, _ = outcome("overhang", speed=1.58)
    assert label == "stayed on"


@pytest.mark.parametrize("name", [n for n, s in S.SCENARIOS.items() if s.event_s is not None])
def test_scheduled_danger_arrives_late_into_a_scene_at_rest(name):
    """Until just before ``event_s`` every key body sits where it was placed and is still, so a
    system that freezes resting bodies has had them frozen when the projectile arrives; and the
    projectile arrives (it has moved all the way)."""
    scenario = S.get(name)
    scene = scenario.build()
    key = S.key_bodies(scene)
    world = run(scene, scenario.event_time(scene) - 0.1)
    start = np.array([b.position for b in scene.bodies])
    assert np.abs(world.positions[key] - start[key]).max() < 0.01
    assert np.abs(world.velocities[key]).max() < 0.01
    projectile = [i for i in range(len(scene.bodies)) if i not in key]
    assert projectile
    world.step(int(round(0.7 / FINE_DT)))  # 0.6 s after the arrival
    assert np.abs(world.positions[key] - start[key]).max() > 0.05


def test_every_scenario_starts_without_overlap_and_names_its_bodies():
    for name, scenario in S.SCENARIOS.items():
        scene = scenario.build()
        sim.World(scene)  # raises on interpenetration
        assert all(b.name for b in scene.bodies), name
        assert S.key_bodies(scene), name
        assert scenario.expected in scenario.labels


def test_bad_input_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown scenario"):
        S.get("no_such_scenario")
    with pytest.raises(ValueError, match="unknown parameter"):
        S.get("tipping").build(no_such_parameter=1.0)
    scenario = S.get("three_bodies")
    scene = scenario.build()
    with pytest.raises(ValueError, match="expected positions"):
        scenario.classify(scene, np.zeros((2, 2)), np.zeros(2))
    with pytest.raises(ValueError, match="not finite"):
        scenario.classify(scene, np.full((3, 2), np.nan), np.zeros(3))


@pytest.mark.parametrize("name", list(S.SCENARIOS))
def test_extended_changes_no_outcome(name):
    """Issue 12's bar, as the failure table runs it (dt 1/60 s, the solver's defaults): under
    extended every scenario ends as it does under off. (A group certificate that froze a plank
    tipping off a box's edge together with the box, as one rigid body, broke
    unstable_equilibrium; its second test, each member held with the others immovable, is what
    this guards.)"""
    scenario = S.get(name)
    scene = scenario.build()
    labels = []
    for freeze in ("off", "extended"):
        world = run(scene, scenario.duration(scene), dt=DT, freeze=freeze, iterations=1)
        labels.append(scenario.classify(scene, world.positions, world.angles))
    assert labels[1] == labels[0]
