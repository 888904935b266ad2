"""Benchmark "bench_setup": how long does it take to set up a scene of many bodies?

Question (issue item "Scale of set-up"): building a World of 10^6 boxes must take seconds; 10^5
boxes took ~48 s (32 s building the Scene body by body, 16 s packing it in a per-body loop). This
times the two set-up paths up to the World's own arrays (``sim.packing.pack``), not the World:

- arrays: ``Scene.from_arrays`` (one box polygon shared by every body) then ``pack``, for
  10^4, 10^5, 10^6 boxes;
- Body list: N ``sim.Body.box`` objects, ``sim.Scene(bodies=...)`` then ``pack``, for 10^3, 10^4,
  10^5 boxes.

Each time is the median of ``--repeats`` runs (default 3), garbage collector paused as in
``study.timing``. Prints a table; writes no results file (not part of ``make``).

    python -m experiments.bench_setup [--quick] [--repeats R]
"""

import argparse
import gc
import statistics
import time

import numpy as np

import sim
from sim.packing import pack
from study.cli import first_paragraph, positive_int

ARRAY_SIZES = (10**4, 10**5, 10**6)
LIST_SIZES = (10**3, 10**4, 10**5)
QUICK_ARRAY_SIZES = (10**3, 10**4)
QUICK_LIST_SIZES = (10**2, 10**3)
COLUMNS = 1000  # boxes per row of the grid; unit boxes 0.5 m apart, rows stacked
BOX = np.array([(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)])  # m, 1 x 1


def grid(n):
    """(n,2) m: positions of n unit boxes in rows of COLUMNS, rows resting on one another."""
    i = np.arange(n)
    return np.stack([1.5 * (i % COLUMNS), 0.5 + (i // COLUMNS).astype(float)], axis=1)


def timed(fn):
    """(seconds, result) of fn(), garbage collector paused."""
    gc_was_on = gc.isenabled()
    gc.disable()
    try:
        t0 = time.perf_counter()
        result = fn()
        return time.perf_counter() - t0, result
    finally:
        if gc_was_on:
            gc.enable()


def arrays_run(n):
    """(scene s, pack s) of n boxes through Scene.from_arrays."""
    position = grid(n)
    scene_s, scene = timed(lambda: sim.Scene.from_arrays(BOX, position, friction=0.6))
    pack_s, packed = timed(lambda: pack(scene))
    assert packed.n_dynamic == n
    return scene_s, pack_s


def body_list_run(n):
    """(scene s, pack s) of n boxes as sim.Body objects (creating them is part of the scene)."""
    position = grid(n).tolist()
    scene_s, scene = timed(
        lambda: sim.Scene(
            bodies=[sim.Body.box(1.0, 1.0, position=tuple(p), friction=0.6) for p in position]
        )
    )
    pack_s, packed = timed(lambda: pack(scene))
    assert packed.n_dynamic == n
    return scene_s, pack_s


def measure(path, run, sizes, repeats):
    rows = []
    for n in sizes:
        times = [run(n) for _ in range(repeats)]
        scene_s = statistics.median(t[0] for t in times)
        pack_s = statistics.median(t[1] for t in times)
        total = statistics.median(t[0] + t[1] for t in times)
        rows.append((path, n, scene_s, pack_s, total))
        print(
            f"{path:<10} {n:>9,d} {scene_s:>9.3f} {pack_s:>9.3f} {total:>9.3f} "
            f"{1e6 * total / n:>9.2f}",
            flush=True,
        )
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=first_paragraph(__doc__))
    parser.add_argument("--quick", action="store_true", help="small sizes only")
    parser.add_argument("--repeats", type=positive_int, default=3, help="timed repeats (default 3)")
    args = parser.parse_args(argv)
    arrays, lists = (
        (QUICK_ARRAY_SIZES, QUICK_LIST_SIZES) if args.quick else (ARRAY_SIZES, LIST_SIZES)
    )
    arrays_run(100)  # first calls (imports, caches) outside the timings
    body_list_run(100)
    print(f"median of {args.repeats}; seconds, except the last column")
    print(f"{'path':<10} {'bodies':>9} {'scene s':>9} {'pack s':>9} {'total s':>9} {'us/body':>9}")
    measure("arrays", arrays_run, arrays, args.repeats)
    measure("Body list", body_list_run, lists, args.repeats)


if __name__ == "__main__":
    main()
