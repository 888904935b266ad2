"""Benchmark "bench_setup": how long does it take to set up a scene of many bodies?

Question (issue item "Scale of set-up"): building a World of 10^6 boxes must take seconds; 10^5
boxes took ~48 s (32 s building the Scene body by body, 16 s packing it in a per-body loop). This
times, for each of two ways to describe the scene:

- arrays: ``Scene.from_arrays`` (one box polygon shared by every body), for 10^4, 10^5, 10^6
  boxes;
- Body list: N ``sim.Body.box`` objects and ``sim.Scene(bodies=...)``, for 10^3, 10^4, 10^5 boxes;

the scene, ``sim.packing.pack`` alone (the World's own arrays), and ``sim.World(scene)`` whole:
validation, packing, the start poses' contacts, the overlap check and the initial solve of the
contact impulses (``sim.presolve``). The boxes stand in rows of 1000 stacked on one another, so
the scene is 1000 columns up to 1000 boxes high: the hardest start for the initial solve, whose
default is held to ``sim.presolve.WORK`` contact-sweeps (before that budget, 2026-12-06, the
World of 10^6 such boxes took 275 s, 265 of them in 5000 sweeps of the initial solve, which
still had not converged). Reported with it: the sweeps the solve spent and whether it converged
(a World whose budget cut it short warns; the warning is expected here and silenced).

Each time is the median of ``--repeats`` runs (default 3), garbage collector paused as in
``study.timing``. Prints a table; writes no results file (not part of ``make``).

    python -m experiments.bench_setup [--quick] [--repeats R]
"""

import argparse
import gc
import statistics
import time
import warnings

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
    """Times (scene, pack, World, s) and the initial solve's (sweeps, converged) of n boxes
    through Scene.from_arrays."""
    position = grid(n)
    scene_s, scene = timed(lambda: sim.Scene.from_arrays(BOX, position, friction=0.6))
    return (scene_s, *world_run(scene, n))


def body_list_run(n):
    """The same for n boxes as sim.Body objects (creating them is part of the scene)."""
    position = grid(n).tolist()
    scene_s, scene = timed(
        lambda: sim.Scene(
            bodies=[sim.Body.box(1.0, 1.0, position=tuple(p), friction=0.6) for p in position]
        )
    )
    return (scene_s, *world_run(scene, n))


def world_run(scene, n):
    """(pack s, World s, initial-solve sweeps, converged) of a scene of n bodies."""
    pack_s, packed = timed(lambda: pack(scene))
    assert packed.n_dynamic == n
    with warnings.catch_warnings():
        # the budget's warning on tall stacks: expected here, and reported below
        warnings.simplefilter("ignore", RuntimeWarning)
        world_s, world = timed(lambda: sim.World(scene))
    report = world.inspect()
    return pack_s, world_s, report.presolve_sweeps, report.presolve_converged


COLUMNS_OUT = ("scene s", "pack s", "World s", "total s", "us/body", "sweeps", "converged")


def measure(path, run, sizes, repeats):
    """Print one row per size: medians of ``repeats`` runs; the total is scene + World (the World
    packs the scene itself: pack alone is shown for what it costs)."""
    rows = []
    for n in sizes:
        times = [run(n) for _ in range(repeats)]
        scene_s, pack_s, world_s = (statistics.median(t[k] for t in times) for k in range(3))
        total = statistics.median(t[0] + t[2] for t in times)
        sweeps, converged = times[-1][3], times[-1][4]
        rows.append((path, n, scene_s, pack_s, world_s, total, sweeps, converged))
        print(
            f"{path:<10} {n:>9,d} {scene_s:>9.3f} {pack_s:>9.3f} {world_s:>9.3f} {total:>9.3f} "
            f"{1e6 * total / n:>9.2f} {sweeps:>9d} {str(converged):>9}",
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
    print(f"median of {args.repeats}; the initial solve's sweeps and convergence of the last run")
    print(f"{'path':<10} {'bodies':>9} " + " ".join(f"{c:>9}" for c in COLUMNS_OUT))
    measure("arrays", arrays_run, arrays, args.repeats)
    measure("Body list", body_list_run, lists, args.repeats)


if __name__ == "__main__":
    main()
