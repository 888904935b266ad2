"""What the runners record and report must mean the same in every engine: the contact view's pair
order and impulse direction, the bullets a runner does not honour, the sleep speed in effect, and
options that cannot act (refused, not recorded as if used)."""

import math

import numpy as np
import pytest

import sim
from study.common import build
from study.peers import impulse_vectors, make_runner
from study.peers.pymunk_runner import PymunkRunner
from study.peers.pybullet_runner import PybulletRunner

DT = 1 / 60
G = 9.81
ENGINES = ("sim-off", "pymunk", "pybullet", "box2d")


@pytest.mark.parametrize("system", ENGINES)
def test_contacts_name_their_pair_and_push_b_along_the_normal(system):
    """A box resting on the floor: the floor (-1) and the box (0) are the pair, the normal points
    from A to B whichever the engine put first, and the impulse pushes B along it, so the box's
    share points up. Before, pymunk and Box2D gave the floor's impulse (arrows down) and sim and
    pybullet the box's, with no pair to tell them apart."""
    with build(system, sim.scenes.single_box()) as runner:
        runner.step(60)
        c = runner.contacts()
    pairs = set(zip(c["body_a"].tolist(), c["body_b"].tolist()))
    assert pairs in ({(-1, 0)}, {(0, -1)}), pairs
    up_is_b = np.where(c["body_b"] == 0, 1.0, -1.0)  # the box is B: the normal points up
    loaded = c["normal_impulse"] > 0
    assert np.all(c["normal"][loaded, 1] * up_is_b[loaded] > 0.99)


@pytest.mark.parametrize("system", ENGINES)
def test_impulse_arrows_point_into_the_upper_body_in_every_engine(system):
    """stack(2): every arrow goes to the dynamic body of higher index (the floor's onto box 0, box
    0's onto box 1), so all point up, and they add up to what the floor and box 0 carry: 3 m g dt
    over the step (two boxes on the floor, one on box 0)."""
    scene = sim.scenes.stack(2)
    with build(system, scene) as runner:
        runner.step(60)
        arrows = impulse_vectors(runner.contacts(), len(scene.bodies))
    assert np.all(arrows[:, 1] >= -1e-9), arrows
    assert arrows[:, 1].sum() == pytest.approx(3 * 1.0 * G * DT, rel=2e-3)


def test_pymunk_records_the_idle_speed_chipmunk_uses():
    """The space holds 0, which Chipmunk reads as |g| dt (0.1635 m/s at 1/60): a box sliding
    frictionless at 0.12 m/s falls asleep mid-slide, one at 0.2 m/s slides on. The settings said
    0.0 (nothing idle) before."""
    slept = {}
    for speed in (0.12, 0.2):
        box = sim.Body.box(1.0, 1.0, position=(0.0, 0.5), velocity=(speed, 0.0), friction=0.0)
        with build("pymunk-sleep", sim.Scene(bodies=[box], floor_friction=0.0)) as runner:
            runner.step(120)
            slept[speed] = bool(runner.asleep[0])
            recorded = runner.settings["idle_speed_threshold"]
            assert runner.settings["idle_speed_rule"] == "Chipmunk's default, |gravity| * dt"
    assert recorded == pytest.approx(G * DT, rel=1e-12)
    assert slept == {0.12: True, 0.2: False}
    runner = PymunkRunner(sim.scenes.single_box(), sleeping=True, idle_speed=0.05)
    assert runner.settings["idle_speed_threshold"] == 0.05
    assert runner.settings["idle_speed_rule"] == "set"


def test_bullets_are_recorded_as_honoured_or_not():
    """A 10 cm box fired at 100 m/s at a free 5 cm plank (no gravity): sim and Box2D sweep the
    bullet and stop it; pymunk and pybullet let it through and their settings now say that the
    one bullet asked for was not honoured (they recorded nothing before)."""
    bullet = sim.Body.box(0.1, 0.1, position=(-2.0, 1.0), velocity=(100.0, 0.0), bullet=True)
    plank = sim.Body.box(0.05, 2.0, position=(0.0, 1.0))
    scene = sim.Scene(bodies=[bullet, plank], gravity=(0.0, 0.0), floor_y=None)
    for system, honoured in (("sim-off", True), ("box2d", True), ("pymunk", False)) + (
        ("pybullet", False),
    ):
        with build(system, scene) as runner:
            runner.step(6)
            passed = runner.positions[0, 0] > 0.0
            assert runner.settings["bullets"]["asked"] == 1, system
            assert runner.settings["bullets"]["of"] == 2
            assert runner.settings["bullets"]["honoured"] is honoured, system
            assert passed is not honoured, (system, runner.positions[0])
    with build("box2d", scene, continuous=False) as runner:
        assert runner.settings["bullets"]["honoured"] is False


@pytest.mark.parametrize(
    "system, option, value",
    [
        ("pymunk", "sleep_time", 0.1),
        ("pymunk", "idle_speed", 0.5),
        ("pybullet", "sleep_threshold", 0.5),
    ],
)
def test_a_sleep_option_without_sleeping_is_refused(system, option, value):
    """sim refuses sleep_speed under freeze="off"; the peers took their sleep options silently
    with sleeping off (pybullet even recorded the threshold as if used)."""
    with pytest.raises(
        ValueError, match=rf"{option} applies only with sleeping \(system {system}-sleep\)"
    ):
        make_runner(system, sim.scenes.single_box(), **{option: value})
    with make_runner(f"{system}-sleep", sim.scenes.single_box(), **{option: value}) as runner:
        recorded = {"sleep_time": "sleep_time_threshold", "idle_speed": "idle_speed_threshold"}
        assert runner.settings[recorded.get(option, option)] == value


def test_the_runners_own_sleep_defaults_are_kept():
    """Nothing given: pymunk-sleep idles 0.5 s, pybullet-sleep uses Bullet's 0.05 threshold, and
    the runners without sleeping never sleep."""
    assert PymunkRunner(sim.scenes.single_box(), sleeping=True).settings[
        "sleep_time_threshold"
    ] == pytest.approx(0.5)
    assert PymunkRunner(sim.scenes.single_box()).settings["sleep_time_threshold"] == math.inf
    with PybulletRunner(sim.scenes.single_box(), sleeping=True) as runner:
        assert runner.settings["sleep_threshold"] == 0.05
