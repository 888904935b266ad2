"""The "quiet" fast path (``World(fast_paths=...)``, ``kernel.run``): once a step has begun and
ended with every body frozen, the steps after it only count, in that call and later ones.

It is exact: every observable of a World run with it is bit-identical to one run without it, for
every policy, on scenes that freeze at once (placed at rest), freeze after settling (a dropped
pile), and never freeze entirely (``paper`` keeps bodies awake; ``off`` freezes nothing), stepped
in calls of one step and of many. Its count (``inspect().quiet_steps``) has a known answer: a
stack placed at rest freezes in step 1 under ``extended``; step 2 begins frozen and runs in full;
every step after it is skipped."""

import numpy as np
import pytest

import sim
from sim.data import STAGES

#: calls of ``step``, so that several begin on a frozen World
CALLS = (1, 5, 120, 1, 2, 240)


def _run(scene, policy, fast_paths):
    world = sim.World(scene, freeze=policy, fast_paths=fast_paths)
    for n in CALLS:
        world.step(n)
    return world


def _inspection(world):
    """Every field of ``inspect()`` but the fast path's own count, arrays as lists."""
    fields = vars(world.inspect())
    out = {}
    for name, value in fields.items():
        if name == "quiet_steps":
            continue
        if name == "contacts":
            value = {k: np.asarray(v).tolist() for k, v in value.items()}
        elif isinstance(value, np.ndarray):
            value = value.tolist()
        out[name] = value
    return out


def _observables(world):
    return {
        "positions": world.positions.tolist(),
        "angles": world.angles.tolist(),
        "velocities": world.velocities.tolist(),
        "angular_velocities": world.angular_velocities.tolist(),
        "states": world.states.tolist(),
        "events": list(world.events),
        "step_count": world.step_count,
        "time": world.time,
        "penetration": world.penetration,
        "max_penetration": world.max_penetration,
        "kinetic_energy": world.kinetic_energy(),
        "inspection": _inspection(world),
    }


SCENES = {
    "stack": lambda: sim.scenes.stack(4),
    "pyramid": lambda: sim.scenes.pyramid(5),
    "drop": lambda: sim.scenes.drop(8, seed=1),
}


@pytest.mark.parametrize("scene", sorted(SCENES))
@pytest.mark.parametrize("policy", ["off", "sleep", "paper", "extended"])
def test_a_quiet_run_is_bit_identical_to_a_full_one(scene, policy):
    quick = _run(SCENES[scene](), policy, True)
    full = _run(SCENES[scene](), policy, ("friction",))
    assert _observables(quick) == _observables(full)
    assert full.inspect().quiet_steps == 0
    if policy == "extended" and scene != "drop":
        assert quick.inspect().quiet_steps > 0  # the comparison covered skipped steps


def test_every_freezing_policy_reaches_quiet_steps_on_a_settled_pile():
    """The dropped pile of the comparison above comes to rest under sleep and extended (so their
    comparison covered skipped steps); paper keeps some bodies awake, off all of them."""
    counts = {p: _run(SCENES["drop"](), p, True).inspect().quiet_steps for p in sim.POLICY_NAMES}
    assert counts["off"] == 0
    assert counts["sleep"] > 0 and counts["extended"] > 0


def test_a_stack_frozen_in_step_1_skips_every_step_after_step_2():
    world = sim.World(sim.scenes.stack(4), freeze="extended")
    world.step(1)
    assert world.n_awake == 0 and world.inspect().quiet_steps == 0
    world.step(1)  # step 2 begins frozen: it runs in full, and arms the fast path
    assert world.inspect().quiet_steps == 0
    world.step(100)  # 3..102 are skipped
    assert world.inspect().quiet_steps == 100
    world.step(1)
    world.step(50)
    assert world.inspect().quiet_steps == 151
    assert world.step_count == 153
    assert world.why_awake().tolist() == [""] * 4


def test_profile_counts_the_skipped_steps_as_steps():
    """``profile`` reports ms per step: skipped steps are steps, at no stage's cost."""
    world = sim.World(sim.scenes.stack(4), freeze="extended").step(2)
    profile = world.profile(40)
    assert world.inspect().quiet_steps == 40
    assert set(profile) == set(STAGES) | {"total"}
    assert all(v >= 0.0 for v in profile.values())
    assert world.step_count == 42


def test_quiet_is_a_named_fast_path():
    assert "quiet" in sim.World(sim.scenes.stack(2)).fast_paths
    assert sim.World(sim.scenes.stack(2), fast_paths=("friction",)).fast_paths == ("friction",)
    with pytest.raises(ValueError, match="unknown fast path"):
        sim.World(sim.scenes.stack(2), fast_paths=("silent",))
