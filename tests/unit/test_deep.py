"""The deep sweeps (sim.soft_step.DEEP_SWEEPS): more biased sweeps for the batches around a
contact deeper than DEEP_SLOPS slops, in the steps that have one, and only there. What they buy
(piles that come to rest) is tested in test_physics (``test_a_dropped_pile_comes_to_rest``,
``test_most_dropped_piles_come_to_rest``): without them pile seed 2 creeps at 1.4e-4 m/s."""

import numpy as np

import sim
from sim import soft_step


def deepest_in_slops(world):
    """The deepest contact point of the last step, at its start, in its pair's slops (0 if none
    is inside its partner)."""
    c = world.contacts()
    if len(c["separation"]) == 0:
        return 0.0
    return float(max(0.0, (-c["separation"] / c["slop"]).max()))


def test_deep_sweeps_run_only_in_steps_with_a_deep_contact():
    w = sim.World(sim.scenes.drop(30, seed=0))
    flagged = 0
    for _ in range(300):
        w.step(1)
        n = w.inspect().n_deep_batches
        assert n <= w.inspect().n_batches
        if n > 0:
            flagged += 1
            # a flagged step has a point deeper than the threshold at the step's start
            assert deepest_in_slops(w) > soft_step.DEEP_SLOPS
    assert flagged > 0  # a pile landing pushes contacts deep


def test_a_placed_pyramid_has_no_deep_contacts():
    w = sim.World(sim.scenes.pyramid(10))
    for _ in range(60):
        w.step(1)
        assert w.inspect().n_deep_batches == 0
    assert deepest_in_slops(w) < soft_step.DEEP_SLOPS


def test_a_deep_contact_is_flagged_in_its_first_step():
    # two unit boxes of equal mass, one placed 25 mm (5 slops) into the other
    size = 1.0
    scene = sim.Scene(
        bodies=[
            sim.Body.box(size, size, position=(0.0, 0.5 * size)),
            sim.Body.box(size, size, position=(0.0, 1.5 * size - 0.025)),
        ]
    )
    w = sim.World(scene, initial_iterations=0, overlap_tolerance=0.05)
    w.step(1)
    assert deepest_in_slops(w) > soft_step.DEEP_SLOPS
    assert w.inspect().n_deep_batches >= 1
    w.step(120)
    assert w.inspect().n_deep_batches == 0  # pushed open
    assert np.isfinite(w.positions).all()
