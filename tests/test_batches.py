"""How the soft step lays contacts out in batches (sim.soft_step.colour), checked from the public
inspection view against a slow recount."""
import math

import numpy as np

import sim
from sim.soft_step import HARD_RATIO, LANES


def hard_touching_pairs(inspection):
    """The active pairs that touch a body in a contact of mass ratio > HARD_RATIO (both bodies
    moved by the solver): the contacts that get the extra relax sweeps."""
    c = inspection.contacts
    inv = inspection.solver_inv_mass
    pairs = {(int(a), int(b)) for a, b in zip(c["body_a"], c["body_b"])}

    def movable(i):
        return 0 <= i < len(inv) and inv[i] > 0.0      # the floor and static bodies are not

    marked = set()
    for a, b in pairs:
        if movable(a) and movable(b) and (inv[a] > HARD_RATIO * inv[b] or inv[b] > HARD_RATIO * inv[a]):
            marked |= {a, b}
    return [p for p in pairs if any(movable(i) and i in marked for i in p)], len(pairs)


def test_hard_contacts_share_batches():
    """Random polygons (masses 0.005-0.39 kg) settling: the contacts that need the extra sweeps
    are packed first in each colour, so at most one part-filled hard batch per colour. Measured
    before packing: 41 of 51 batches hard (the sweeps went to nearly every contact); after: 13."""
    w = sim.World(sim.scenes.drop(200, seed=0))
    w.step(240)
    info = w.inspect()
    touching, n_pairs = hard_touching_pairs(info)
    assert n_pairs == info.n_active
    assert len(touching) > 0
    assert info.n_hard_batches <= math.ceil(len(touching) / LANES) + info.n_colours
    assert info.n_hard_batches < info.n_batches / 2


def test_uniform_masses_have_no_hard_batches():
    w = sim.World(sim.scenes.pyramid(10))
    w.step(5)
    info = w.inspect()
    assert hard_touching_pairs(info)[0] == []
    assert info.n_hard_batches == 0
    assert info.n_batches > 0


def test_a_heavy_box_on_light_ones_gets_hard_batches():
    light = [sim.Body.box(1, 1, position=(x, 0.5)) for x in (-1.2, 0.0, 1.2)]
    heavy = sim.Body.box(1, 1, position=(0.0, 1.5), density=100.0)
    w = sim.World(sim.Scene(bodies=light + [heavy]))
    w.step(5)
    info = w.inspect()
    assert len(hard_touching_pairs(info)[0]) >= 2       # heavy on light, and light on the floor
    assert info.n_hard_batches >= 1
    assert np.isfinite(w.positions).all()
