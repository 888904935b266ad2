"""A batch whose every lane has a body A that cannot move (the floor, a frozen body) is swept by
kernels that leave A's terms out (``sim.soft_step.batches``, FIXED SIDE). They must give the
numbers of the general kernels, to the bit: each kernel is run on the same random batch as either
kind and everything the solver reads afterwards is compared. And a step's batches get the kind
they should."""

import numpy as np
import pytest

import sim
from sim import soft_step
from sim.data import DPX, DPY, DQC, DQS, STATE_COLUMNS, TURN, VX, VY, W
from sim.soft_step import LANES
from sim.soft_step import layout as L

#: the fields of side A: never read or written by a FIXED_A batch's sweeps
SIDE_FIELDS = ("MA", "IA", "RNA1", "RTA1", "RNA2", "RTA2")
GATHERED = tuple(f"G{k}" for k in range(L.GATHER_FIELDS))


def random_batch(rng, two_points):
    """One batch of LANES contacts whose body A is the dummy row 0 in every lane, with plausible
    random values in every other field; and the body rows (row 0 the dummy: at rest, unturned).
    ``two_points``: which lanes have a second point."""
    wide = np.zeros(L.STRIDE)
    rows = 1 + 2 * LANES
    state = np.zeros((rows, STATE_COLUMNS))
    state[0, DQC] = 1.0
    for r in range(1, rows):
        state[r, VX], state[r, VY], state[r, W] = rng.normal(scale=(1.0, 1.0, 2.0))
        state[r, DPX], state[r, DPY] = rng.normal(scale=0.02, size=2)
        turn = rng.normal(scale=0.05)
        state[r, TURN], state[r, DQC], state[r, DQS] = turn, np.cos(turn), np.sin(turn)
    lane_row = np.zeros(2 * LANES, np.uint64)

    def put(name, lane, value):
        wide[int(getattr(L, name)) + lane] = value

    for lane in range(LANES):
        moving = 1 + lane
        lane_row[LANES + lane] = moving
        angle = rng.uniform(-np.pi, np.pi)
        put("NX", lane, np.cos(angle))
        put("NY", lane, np.sin(angle))
        put("MU", lane, rng.uniform(0.1, 0.9))
        put("E", lane, rng.choice([0.0, 0.4]))
        put("MB", lane, rng.uniform(0.1, 2.0))
        put("IB", lane, rng.uniform(0.1, 3.0))
        put("BIAS_RATE", lane, rng.uniform(10.0, 60.0))
        put("MASS_SCALE", lane, rng.uniform(0.5, 1.0))
        put("IMPULSE_SCALE", lane, rng.uniform(0.0, 0.2))
        for point in ("1", "2") if two_points[lane] else ("1",):
            for name in ("RAX", "RAY", "RBX", "RBY"):
                put(name + point, lane, rng.normal(scale=0.5))
            put("BASE" + point, lane, rng.uniform(-0.03, 0.01))
            put("NMASS" + point, lane, rng.uniform(0.2, 1.0))
            put("ON" + point, lane, 1.0)
            put("PN" + point, lane, rng.uniform(0.0, 0.5))
            put("PT" + point, lane, rng.normal(scale=0.2))
            put("TN" + point, lane, rng.uniform(0.0, 1.0))
            put("TT" + point, lane, rng.normal(scale=0.2))
            put("RELV" + point, lane, rng.uniform(-3.0, 0.5))
            put("LN" + point, lane, rng.uniform(0.0, 0.5))
            # what an arms pass left (the sweeps read it; A's arms are left zero)
            for name in ("RNB", "RTB"):
                put(name + point, lane, rng.normal(scale=0.5))
            put("SEP" + point, lane, rng.uniform(-0.03, 0.01))
    return wide, lane_row, state


def compared(wide):
    """The batch's fields that both kinds must agree on: all but side A's own and the gather
    scratch."""
    skip = set(SIDE_FIELDS) | set(GATHERED)
    keep = [k for k, name in enumerate(L.FIELD_NAMES) if name not in skip]
    return wide.reshape(L.N_FIELDS, LANES)[keep]


def start_velocities(wide, state):
    """The bodies' velocities at the start of the step (row r is body r - 1): each lane's B
    approaching its contact at 4 m/s, so that every lane with restitution bounces."""
    velocity = np.ascontiguousarray(state[1:, VX : VY + 1])
    for lane in range(LANES):
        velocity[lane] = -4.0 * wide[int(L.NX) + lane], -4.0 * wide[int(L.NY) + lane]
    spin = np.ascontiguousarray(state[1:, W])
    return velocity, spin, np.arange(len(state) - 1, dtype=np.int64)


def run_kernels(batch, kind):
    """Each batch kernel on its own copy of ``batch`` (wide, lane_row, state) as a batch of
    ``kind``: {kernel: (wide, state) after it}."""
    batch_kind = np.full(1, kind, np.uint8)
    colours = np.array([0, 1], np.int64)
    flags = np.ones(1, bool)
    inv_h, push = 240.0, 3.0
    kernels = {
        "arms": lambda c: soft_step.arms(1, *c),
        "warm_start": lambda c: soft_step.warm_start(1, colours, *c),
        "solve": lambda c: soft_step.solve(1, colours, *c, inv_h, push),
        "solve_impact": lambda c: soft_step.solve_impact(1, colours, *c[:3], inv_h, push, flags),
        "relax": lambda c: soft_step.relax(1, colours, *c, inv_h, False),
        "relax_hard": lambda c: soft_step.relax_hard(1, colours, *c[:3], inv_h, False, flags),
        "restitution": lambda c: soft_step.restitution(
            1,
            colours,
            *c[:3],
            0.5,
            0.0,
            -9.81,
            1.7e-4,
            np.zeros(len(c[2]), bool),
            start_velocities(c[0], c[2]),
        ),
    }
    out = {}
    for name, kernel in kernels.items():
        wide, lane_row, state = (a.copy() for a in batch)
        kernel((wide, lane_row, state, batch_kind))
        out[name] = (wide, state)
    return out


@pytest.mark.parametrize("seed", range(6))
def test_a_fixed_batch_gives_the_general_kernels_numbers(seed):
    rng = np.random.default_rng(seed)
    two_points = rng.random(LANES) < 0.7
    batch = random_batch(rng, two_points)
    general = run_kernels(batch, L.MOVABLE)
    special = run_kernels(batch, L.FIXED_A)
    for name in general:
        (wide_g, state_g), (wide_s, state_s) = general[name], special[name]
        assert np.array_equal(compared(wide_s), compared(wide_g)), name
        assert np.array_equal(state_s, state_g), name
    # the general kernels did move the bodies, and never the dummy row
    assert not np.array_equal(general["restitution"][1], batch[2])
    assert np.array_equal(special["restitution"][1][0], batch[2][0])


def test_batches_on_the_floor_are_fixed_and_others_are_not():
    # rest_row: every contact is with the floor (body A = -1): every batch FIXED_A. A pyramid:
    # the bottom row's contacts with the floor are, the box-on-box ones are not (and no batch
    # mixes them: contacts with what cannot move get colours of their own).
    row = sim.World(sim.scenes.rest_row(20))
    row.step(2)
    kinds = row.inspect().batch_kinds
    assert len(kinds) == 3 and set(kinds) == {L.FIXED_A}
    pyramid = sim.World(sim.scenes.pyramid(6))
    pyramid.step(2)
    inspection = pyramid.inspect()
    contacts = inspection.contacts  # one row per contact point
    on_floor = len({b for a, b in zip(contacts["body_a"], contacts["body_b"]) if a == -1})
    kinds = inspection.batch_kinds
    assert on_floor == 6 and set(kinds) == {L.MOVABLE, L.FIXED_A}
    assert np.sum(kinds == L.FIXED_A) == 1  # the 6 floor contacts fill one batch
