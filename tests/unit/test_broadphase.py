"""The grid broadphase against brute force: every overlapping box found once, whatever the layout
(compact: dense table; flung apart: hashed; boxes covering many cells: the large list; query boxes
far larger than the grid), and a body flung absurdly fast gives a run, not a crash or a
MemoryError."""

import numpy as np
import pytest

import sim
from sim.broadphase import LARGE_CELLS, build_grid, grid_buffers, query_box
from sim.data import (
    DENSE,
    MAX_X,
    MAX_Y,
    MIN_X,
    MIN_Y,
    N_BUCKETS,
    N_ENTRIES,
    NEEDED_BUCKETS,
    NEEDED_ENTRIES,
)

CELL = 1.0


def random_boxes(rng, n, spread, large_every=0):
    lo = rng.uniform(-spread, spread, (n, 2))
    size = rng.uniform(0.05, 2.0, (n, 2))
    if large_every:
        size[::large_every] *= 40.0  # 80 m: thousands of cells
    boxes = np.zeros((n, 4))
    boxes[:, MIN_X], boxes[:, MIN_Y] = lo[:, 0], lo[:, 1]
    boxes[:, MAX_X], boxes[:, MAX_Y] = lo[:, 0] + size[:, 0], lo[:, 1] + size[:, 1]
    return boxes


def built(boxes):
    which = np.arange(len(boxes), dtype=np.int64)
    grid = grid_buffers(4, 4)
    while not build_grid(which, len(which), boxes, CELL, grid):
        grid = grid_buffers(int(grid.info[NEEDED_ENTRIES]), int(grid.info[NEEDED_BUCKETS]))
    return grid


def brute(boxes, q):
    return sorted(
        j
        for j in range(len(boxes))
        if not (
            q[MIN_X] > boxes[j, MAX_X]
            or q[MAX_X] < boxes[j, MIN_X]
            or q[MIN_Y] > boxes[j, MAX_Y]
            or q[MAX_Y] < boxes[j, MIN_Y]
        )
    )


@pytest.mark.parametrize(
    "spread,large_every,dense", [(20.0, 0, 1), (1e6, 0, 0), (20.0, 7, 1), (1e6, 5, 0)]
)
def test_queries_find_every_overlap_once(spread, large_every, dense):
    rng = np.random.default_rng(int(spread) + large_every)
    boxes = random_boxes(rng, 300, spread, large_every)
    grid = built(boxes)
    assert grid.info[DENSE] == dense
    assert grid.info[N_ENTRIES] > 0
    out = np.zeros(len(boxes), np.int64)
    queries = list(random_boxes(rng, 200, spread))
    # query boxes far larger than the grid (a fast body's sweep), and beyond every cell
    queries += [
        np.array([-1e30, -1e30, 1e30, 1e30]),
        np.array([-3e6, -5.0, 3e6, 5.0]),
        np.array([1e13, 1e13, 1e13 + 1, 1e13 + 1]),
        np.array([-1e19, 0.0, 1e19, 0.1]),
    ]
    for q in queries:
        n = query_box(grid, boxes, q[MIN_X], q[MIN_Y], q[MAX_X], q[MAX_Y], CELL, out)
        assert sorted(out[:n]) == brute(boxes, q)


def test_a_box_of_more_than_large_cells_is_entered_once():
    boxes = random_boxes(np.random.default_rng(1), 2, 1.0)
    boxes[0, MAX_X] = boxes[0, MIN_X] + 10 * LARGE_CELLS * CELL
    grid = built(boxes)
    cells_of_1 = (np.floor(boxes[1, MAX_X]) - np.floor(boxes[1, MIN_X]) + 1) * (
        np.floor(boxes[1, MAX_Y]) - np.floor(boxes[1, MIN_Y]) + 1
    )
    assert grid.info[N_ENTRIES] == cells_of_1 + 1
    n_buckets = grid.info[N_BUCKETS]
    assert list(grid.entry_body[grid.start[n_buckets] : grid.start[n_buckets + 1]]) == [0]


@pytest.mark.parametrize("speed", [1e6, 1e8, 1e10])
def test_a_body_flung_absurdly_fast_is_simulated(speed):
    # before: 1e8 m/s (1.7e6 m per step) asked the grid for 9e9 entries (MemoryError); a body
    # flung 1e19 m in a step made the cell loops read outside the table (a segfault on CI)
    rocket = sim.Body.box(1, 1, position=(0.0, 0.5), velocity=(speed, 0.0), name="rocket")
    other = sim.Body.box(1, 1, position=(5.0, 0.5), name="other")
    w = sim.World(sim.Scene(bodies=[rocket, other]))
    w.step(3)
    assert np.isfinite(w.positions).all()
    assert w.positions[:, 0].max() > 3 * speed / 60 / 2  # it flew (the other box was hit)


@pytest.mark.parametrize("n_bodies", [300, 2**31])
@pytest.mark.parametrize("n_changed", [5, 500])
def test_the_awake_contacts_are_put_in_pair_order(n_bodies, n_changed):
    # sort_awake's three ways (insertion for a few changes; for many, keys packed with their
    # slots and sorted in place, or, when key * capacity would overflow int64 (2**31 bodies),
    # a heapsort of keys and slots side by side) all give the order of (body A, body B)
    from sim.buffers import new_contacts
    from sim.contacts import sort_awake
    from sim.data import AWAKE_INDEX, AWAKE_UNSORTED, BODY_A, BODY_B, N_AWAKE_CONTACTS, N_COUNTERS

    rng = np.random.default_rng(n_changed)
    capacity = 1000
    contacts = new_contacts(capacity, 300)
    pairs = set()
    while len(pairs) < 600:
        a, b = sorted(rng.integers(-1, 300, 2).tolist())
        if a != b:
            pairs.add((a, b))
    pairs = sorted(pairs)
    slots = rng.permutation(capacity)[: len(pairs)]
    for (a, b), s in zip(pairs, slots):
        contacts.contact_int[s, BODY_A] = a
        contacts.contact_int[s, BODY_B] = b
    order = list(slots)  # in pair order, then n_changed of them moved
    for _ in range(n_changed):
        i, j = rng.integers(0, len(order), 2)
        order[i], order[j] = order[j], order[i]
    contacts.awake[: len(order)] = order
    counters = np.zeros(N_COUNTERS, np.int64)
    counters[N_AWAKE_CONTACTS] = len(order)
    counters[AWAKE_UNSORTED] = n_changed
    sort_awake(n_bodies, contacts, counters)
    got = contacts.awake[: len(order)]
    np.testing.assert_array_equal(got, slots)
    np.testing.assert_array_equal(contacts.contact_int[got, AWAKE_INDEX], np.arange(len(order)))
    assert counters[AWAKE_UNSORTED] == 0


@pytest.mark.parametrize("pattern", ["appended", "removed", "both", "reversed", "two_high"])
def test_a_nearly_sorted_awake_list_is_merged_into_order(pattern):
    # the packed path sorts only the keys out of order and merges them back: what the store's
    # own changes leave (new contacts appended at the end, removals filled with the last entry)
    # and orders that defeat the "nearly sorted" guess (all of it reversed; two high keys in a
    # row early, which the scan keeps, so that every key after them is merged back) must all
    # come out in order
    from sim.contacts import merge_nearly_sorted

    rng = np.random.default_rng(7)
    keys = sorted(rng.choice(10**9, 900, replace=False).tolist())
    order = keys[:800]
    if pattern in ("appended", "both"):
        order += keys[800:]
        order[800:] = rng.permutation(order[800:]).tolist()
    if pattern in ("removed", "both"):
        for _ in range(40):  # _remove_awake: the last entry fills the hole
            k = int(rng.integers(0, len(order)))
            order[k] = order[-1]
            order.pop()
    if pattern == "reversed":
        order = order[::-1]
    if pattern == "two_high":
        order = [order[-2], order[-1]] + order[:-2]
    got = np.array(order, np.int64)
    spare = np.full(len(got), -1, np.int64)
    merge_nearly_sorted(got, spare, len(got))
    np.testing.assert_array_equal(got, np.sort(np.array(order, np.int64)))
