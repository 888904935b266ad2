"""Every runner refuses, or reports, what sim.World does, in the same way (``study.peers.guards``,
``study.peers.lifetime``): a step count that is not a count, a setting it does not take, a body
whose mass the engine cannot simulate (and the engine's failure just beyond the range it
accepts), a state gone non-finite, use after ``close()``."""

import numpy as np
import pytest

import sim
from study.peers import box2d_runner, guards, make_runner, pybullet_runner

SYSTEMS = ["sim-off", "pymunk", "pybullet", "box2d"]


def _resting(density, size=1.0):
    """A box on the floor carrying an equal box set off-centre (both at rest)."""
    box = sim.Body.box(size, size, position=(0.0, 0.5 * size), density=density)
    top = sim.Body.box(size, size, position=(0.2 * size, 1.5 * size), density=density)
    return sim.Scene(bodies=[box, top])


def _held(system, density, size=1.0):
    """Does ``system`` keep the resting scene as at density 1000 (within 1% of the size, 2 s)?
    False also when the state goes non-finite (SimulationError)."""

    def run(d):
        with make_runner(system, _resting(d, size)) as runner:
            runner.step(120)
            return np.c_[runner.positions, runner.angles]

    base = run(1000.0)
    try:
        return bool(np.abs(run(density) - base).max() < 0.01 * size)
    except sim.SimulationError:
        return False


@pytest.mark.parametrize("system", SYSTEMS)
@pytest.mark.parametrize("n", [-1, True, 2.0, "3"])
def test_every_runner_refuses_a_step_count_that_is_not_a_count(system, n):
    with make_runner(system, sim.scenes.single_box()) as runner:
        with pytest.raises(ValueError, match="n must be an integer >= 0"):
            runner.step(n)
        assert runner.step_count == 0 and runner.time == 0.0


@pytest.mark.parametrize("system", SYSTEMS)
def test_every_runner_counts_steps_as_an_int(system):
    with make_runner(system, sim.scenes.single_box()) as runner:
        runner.step(np.int64(2)).step(0)
        assert type(runner.step_count) is int and runner.step_count == 2


@pytest.mark.parametrize("system", SYSTEMS)
def test_a_closed_runner_says_so_on_every_use(system):
    runner = make_runner(system, sim.scenes.stack(2))
    runner.step(1)
    runner.positions  # noqa: B018 (read before close: pybullet caches it)
    runner.close()
    runner.close()  # idempotent
    assert runner.closed
    for use in (
        lambda: runner.step(1),
        lambda: runner.positions,
        lambda: runner.angles,
        lambda: runner.velocities,
        lambda: runner.angular_velocities,
        lambda: runner.asleep,
        lambda: runner.contacts(),
    ):
        with pytest.raises(ValueError, match="this runner was closed"):
            use()


@pytest.mark.parametrize(
    "system, setting",
    [("pymunk-sleep", "sleep_tme"), ("box2d", "position_iters"), ("pybullet", "slep")],
)
def test_a_misspelt_setting_is_a_value_error_naming_the_settings(system, setting):
    with pytest.raises(ValueError, match=f"{setting}: not a setting of .* \\(it takes "):
        make_runner(system, sim.scenes.single_box(), **{setting: 1})


@pytest.mark.parametrize(
    "system, low, high",
    # pybullet's low end is sim's, where a 1 m box's moment of inertia (m/6) leaves sim's range
    # first: 10 times as much
    [("box2d", *guards.BOX2D_MASS), ("pybullet", 10 * guards.PYBULLET_MASS[0], 1e11)],
)
def test_a_peer_holds_the_masses_it_accepts_and_refuses_the_rest(system, low, high):
    # 1 m boxes: the mass in kg is the density
    assert high == {"box2d": guards.BOX2D_MASS, "pybullet": guards.PYBULLET_MASS}[system][1]
    for mass in (low, high):
        assert _held(system, mass), mass
    for mass in (low / 100, high * 10):
        with pytest.raises(ValueError, match=f"{system}: body 0 has mass .* runs masses in"):
            make_runner(system, _resting(mass))


@pytest.mark.parametrize("size", [0.1, 10.0])
def test_box2ds_mass_range_holds_at_other_sizes(size):
    density = np.array(guards.BOX2D_MASS) / size**2
    assert _held("box2d", density[0], size) and _held("box2d", density[1], size)


def test_beyond_the_ranges_the_engines_fail(monkeypatch):
    """What the ranges stand on: let through, Box2D's bodies end far off (or NaN) at 1e20 kg and
    at 1e-19 kg, and a 1e12 kg box sinks into pybullet's floor."""
    monkeypatch.setattr(box2d_runner, "BOX2D_MASS", (0.0, np.inf))
    monkeypatch.setattr(pybullet_runner, "PYBULLET_MASS", (0.0, np.inf))
    assert not _held("box2d", 1e20)
    assert not _held("box2d", 1e-19)
    assert not _held("pybullet", 1e12)


@pytest.mark.parametrize("system, mass", [("box2d", 1e20), ("pybullet", 1e-200)])
def test_a_non_finite_peer_state_is_a_simulation_error(system, mass, monkeypatch):
    """Let through, these masses make NaN (found by a reviewer: Box2D and pybullet handed the NaN
    poses back without a word); the runner now stops as sim.World does."""
    monkeypatch.setattr(box2d_runner, "BOX2D_MASS", (0.0, np.inf))
    monkeypatch.setattr(pybullet_runner, "PYBULLET_MASS", (0.0, np.inf))
    monkeypatch.setattr(guards, "MASS_RANGE", (0.0, np.inf))
    with make_runner(system, sim.Scene(bodies=[sim.Body.box(1.0, 1.0, density=mass)])) as runner:
        with pytest.raises(sim.SimulationError, match=f"{system}: body 0 is non-finite"):
            # a peer checks its state as it is read (Box2D reads its velocities in every step)
            runner.step(60)
            runner.positions  # noqa: B018


def test_a_peer_never_hands_out_a_non_finite_state():
    """Checked as it is read, not after every step: reading back 10^4 pymunk bodies' poses after
    each step cost 11 ms against a 0.03 ms frozen step, and doubled the full run's fig_speedup."""
    with make_runner("pymunk", sim.scenes.single_box()) as runner:
        next(iter(runner.space.bodies)).velocity = (float("nan"), 0.0)
        runner.step(1)
        for read in (lambda: runner.positions, lambda: runner.velocities):
            with pytest.raises(
                sim.SimulationError, match="pymunk: body 0 is non-finite after step 1"
            ):
                read()
        assert np.isfinite(runner.angles).all()  # what is finite is still handed out


def test_contacts_of_a_non_finite_state_are_refused_too():
    """Box2D's contacts() handed out NaN points and normals after its state went non-finite (a
    reviewer, 2026-12-07): they are checked as the observables are."""
    with make_runner("box2d", sim.scenes.stack(2)) as runner:
        runner.step(3)
        runner.world.bodies[1].angularVelocity = float("nan")
        with pytest.raises(sim.SimulationError, match="non-finite after step 4"):
            runner.step(1)
        with pytest.raises(sim.SimulationError, match="box2d: contact point .* is non-finite"):
            runner.contacts()


def test_every_runner_keeps_sims_mass_range():
    scene = sim.Scene(bodies=[sim.Body.box(1.0, 1.0, position=(0, 0.5), density=1e-120)])
    for system in ("pymunk", "pybullet", "box2d", "box2d3"):
        with pytest.raises(ValueError, match=f"{system}: body 0 has mass 1e-120 kg"):
            make_runner(system, scene)
