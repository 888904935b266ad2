"""Table "bench_step": milliseconds per step versus body count, sim (freeze off) vs pymunk (sleeping off).

Question: before any freezing, how fast is sim's solver compared with an established engine on the
same scenes, at the same dt, iterations, friction and slop? This fixes the baseline that every
later speed-up is measured from, and shows how each system's cost grows with the body count.

Scenes: rest_row(n) for n in 10, 100, 1000, 5000 (independent boxes on the floor: cost of contacts
with the floor only) and pyramid(base) for base in 10, 20, 40 (stacked boxes: coupled contacts).
Both systems run dt 1/60 s, 10 iterations, slop 0.005 m, the scene's friction, no sleeping.

Method (DESIGN.md section 6): one throwaway sim World compiles the Numba kernels first; each system
is built, then 10 untimed warm-up steps; then R repeats of K steps each, timed with
time.perf_counter and the garbage collector paused, alternating sim and pymunk repeat by repeat so
that machine noise hits both alike. Reported per step: median and min over repeats, in ms, and on
the sim rows the ratio pymunk/sim of medians (``speedup_vs_pymunk``, > 1 means sim is faster).
``max_displacement_m`` (largest distance any body moved from its start, sampled after each repeat)
guards against a scene that blew up, or collapsed, looking fast.

    python -m experiments.bench_step [--quick] [--repeats R] [--steps K]
writes results/data/bench_step.csv and bench_step.json.
"""
import argparse
import statistics
import time

import numpy as np
import pandas as pd
from tqdm import tqdm

import sim
from experiments.timing import timed
from experiments.metadata import collect, write_results
from experiments.peers import make_runner

NAME = "bench_step"
DT = 1 / 60            # s
ITERATIONS = 10
SLOP = 0.005           # m, sim's slop and pymunk's collision_slop
WARMUP_STEPS = 10

FULL = {"rest_row": (10, 100, 1000, 5000), "pyramid": (10, 20, 40)}
QUICK = {"rest_row": (10, 100), "pyramid": (5, 10)}
BUILDERS = {"rest_row": sim.scenes.rest_row, "pyramid": sim.scenes.pyramid}
PARAM = {"rest_row": "n", "pyramid": "base"}       # the size parameter reported per scene


#: Systems timed, by their experiments.peers name, with the settings that make them comparable.
SYSTEMS = ("sim-off", "pymunk")
SYSTEM_SETTINGS = {"sim-off": {"slop": SLOP}, "pymunk": {"collision_slop": SLOP}}


def _make(system, scene):
    return make_runner(system, scene, dt=DT, iterations=ITERATIONS, **SYSTEM_SETTINGS[system])


def bench_scene(scene, repeats, steps, progress=None):
    """Time every system on ``scene``; one result row per system."""
    systems, starts, build_s = [], [], []
    for name in SYSTEMS:
        t0 = time.perf_counter()
        system = _make(name, scene)
        build_s.append(time.perf_counter() - t0)
        starts.append(system.positions)
        system.step(WARMUP_STEPS)                   # first steps excluded (contacts, caches)
        systems.append(system)
    times = [[] for _ in systems]
    moved = [0.0 for _ in systems]
    for _ in range(repeats):
        for k, system in enumerate(systems):        # interleaved: sim, pymunk, sim, pymunk ...
            times[k].append(timed(system, steps))
            d = np.hypot(*(system.positions - starts[k]).T).max()
            moved[k] = max(moved[k], float(d))
            if progress is not None:
                progress.update()
    rows = []
    for k, system in enumerate(systems):
        per_step_ms = [1e3 * t / steps for t in times[k]]
        rows.append({"scene": scene.name, "param": scene.params[PARAM[scene.name]],
                     "bodies": len(scene.bodies), "system": system.name,
                     "ms_per_step_median": statistics.median(per_step_ms),
                     "ms_per_step_min": min(per_step_ms), "repeats": repeats,
                     "steps_per_repeat": steps, "max_displacement_m": moved[k],
                     "build_s": build_s[k]})
    return rows


def run(sizes, repeats, steps):
    """Benchmark every scene in ``sizes`` ({builder name: params}); returns (table, scenes)."""
    sim.World(sim.scenes.rest_row(2), dt=DT, iterations=ITERATIONS).step(2)  # compile Numba kernels
    scenes = [BUILDERS[name](p) for name, params in sizes.items() for p in params]
    rows = []
    with tqdm(total=len(scenes) * repeats * len(SYSTEMS), desc=NAME, unit="repeat") as bar:
        for scene in scenes:
            bar.set_postfix_str(f"{scene.name} {len(scene.bodies)} bodies")
            rows += bench_scene(scene, repeats, steps, bar)
    table = pd.DataFrame(rows)
    # ratio of medians, on the sim rows: how many times faster sim is than pymunk
    med = table.pivot_table(index=["scene", "param"], columns="system",
                            values="ms_per_step_median")
    ratio = (med["pymunk"] / med["sim-off"]).rename("speedup_vs_pymunk")
    table = table.join(ratio, on=["scene", "param"])
    table.loc[table["system"] != "sim-off", "speedup_vs_pymunk"] = np.nan
    return table, scenes


def main(argv=None, data_dir=None):
    """Command line entry; ``data_dir`` overrides results/data (tests)."""
    parser = argparse.ArgumentParser(prog=f"python -m experiments.{NAME}",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes, few repeats (CI)")
    parser.add_argument("--repeats", type=int, default=None, help="timed repeats (default 7, quick 3)")
    parser.add_argument("--steps", type=int, default=None, help="steps per repeat (default 50, quick 10)")
    args = parser.parse_args(argv)
    sizes = QUICK if args.quick else FULL
    repeats = args.repeats or (3 if args.quick else 7)
    steps = args.steps or (10 if args.quick else 50)
    if repeats < 1 or steps < 1:
        parser.error("--repeats and --steps must be >= 1")

    table, scenes = run(sizes, repeats, steps)
    parameters = {"dt": DT, "iterations": ITERATIONS, "slop": SLOP, "warmup_steps": WARMUP_STEPS,
                  "repeats": repeats, "steps_per_repeat": steps, "quick": args.quick,
                  "sizes": sizes, "systems": list(SYSTEMS),
                  "system_settings": {name: _make(name, scenes[0]).settings
                                      for name in SYSTEMS}}
    metadata = collect(scenes, parameters, script=NAME)
    csv_path, _ = write_results(NAME, table, metadata, folder=data_dir)
    with pd.option_context("display.width", 200, "display.max_columns", 20):
        print(table.to_string(index=False, float_format=lambda x: f"{x:.4g}"))
    print(f"wrote {csv_path}")
    return table


if __name__ == "__main__":
    main()
