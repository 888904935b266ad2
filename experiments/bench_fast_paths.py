"""Table "bench_fast_paths": does the solver pay only for what a scene uses?

Question (issue "extremes", model only what a scene requires): which work can the solver skip
when a scene does not need it, and does skipping pay? Each candidate is measured, in this one
process run, and kept only when it saves at least PAYS (5 %) of a step on a scene where it applies:

1. ``friction`` (built, ``World(fast_paths=...)``): no friction rows for contacts whose friction
   coefficient is zero. Scenes: ``columns`` (100 columns of 10 unit boxes, 1000 bodies, so the
   contacts are box-box and box-floor) frictionless and with mu 0.6 (where nothing may change),
   sim-off with fast paths on and off, interleaved repeats.
2. ``box_sat`` (built, measured, removed): a separating-axis test specialised to box pairs. It
   saved 2.5-4.9 % of a pyramid(40) step on a quiet machine (two runs at commit c38ae49), under
   the rule, so it is no longer in sim. Measured here: the upper bound of any SAT saving, the
   general SAT on every box pair of the step (timed in a loop over the step's own pairs) as a
   share of the step: a specialised test can save at most all of it.
3. ``statics`` (structural): static polygons live in the resting grid with frozen bodies, so a
   scene pays for them only where awake bodies come near. Measured: rest_row(1000) under off with
   no static polygons and with 100 static ledges placed 50 m above the row (never touched).
4. ``rotation`` (not built unless it pays): skipping cos/sin and vertex rotation for bodies that
   do not rotate. Upper bound: the time of the per-body rotation work (the geometry update of all
   awake bodies, which recomputes cos/sin and rotates every vertex and normal) as a share of a
   rest_row(1000) step.

    python -m experiments.bench_fast_paths [--quick] [--repeats R]
"""
import math
import statistics

import numpy as np
import pandas as pd
from numba import njit
from tqdm import tqdm

import sim
from experiments.common import DT, SLOP, compile_kernels, entry
from experiments.timing import interleaved, timed
from sim.broadphase import update_geometry
from sim.contacts import BODY_A, BODY_B
from sim.geometry import _max_separation

NAME = "bench_fast_paths"
PAYS = 0.05             # a fast path is kept when it saves at least this share of a step
FULL = {"columns": (100, 10), "pyramid": 40, "row": 1000, "statics": 100, "steps": 30,
        "repeats": 9}
QUICK = {"columns": (10, 5), "pyramid": 10, "row": 100, "statics": 10, "steps": 5, "repeats": 3}


def columns(n_columns, height, mu):
    """``n_columns`` columns of ``height`` unit boxes, 0.5 m apart, friction ``mu`` (floor too)."""
    bodies = [sim.Body.box(1.0, 1.0, position=(1.5 * c, 0.5 + i), friction=mu)
              for c in range(n_columns) for i in range(height)]
    return sim.Scene(bodies=bodies, floor_friction=mu, name="columns",
                     params={"columns": n_columns, "height": height, "friction": mu})


def with_ledges(scene, n, height=50.0):
    """``scene`` plus ``n`` static 1 x 0.2 m ledges ``height`` m up (never touched)."""
    ledges = [sim.Body.box(1.0, 0.2, position=(2.0 * k, height)) for k in range(n)]
    return sim.Scene(bodies=scene.bodies, static_bodies=ledges, name=scene.name + "+ledges",
                     params={**scene.params, "ledges": n, "ledge_height": height})


class _WorldRunner:
    """The smallest runner ``timing.interleaved`` needs: step(n)."""

    def __init__(self, world):
        self.world = world

    def step(self, n):
        self.world.step(n)


@njit
def _sat_all(pairs, vert_start, verts, normals, reps):
    """The general SAT both ways on every pair, ``reps`` times (the accumulated result keeps the
    compiler from dropping the work)."""
    acc = 0.0
    for _ in range(reps):
        for k in range(pairs.shape[0]):
            a, b = pairs[k, 0], pairs[k, 1]
            e1, s1 = _max_separation(verts, normals, vert_start[a], vert_start[a + 1],
                                     vert_start[b], vert_start[b + 1])
            e2, s2 = _max_separation(verts, normals, vert_start[b], vert_start[b + 1],
                                     vert_start[a], vert_start[a + 1])
            acc += s1 + s2 + e1 + e2
    return acc


def _median_ms(fn, reps, repeats):
    out = []
    for _ in range(repeats):
        out.append(1e3 * timed(_Call(fn), reps) / reps)
    return statistics.median(out)


class _Call:
    def __init__(self, fn):
        self.fn = fn

    def step(self, n):
        self.fn(n)


def _row(part, scene, variant, ms, share=math.nan, note=""):
    return {"part": part, "scene": scene, "variant": variant, "ms_per_step_median": ms,
            "saving_share_of_step": share, "note": note}


def friction(config, repeats, bar):
    rows = []
    for mu in (0.0, 0.6):
        scene = columns(*config["columns"], mu)
        runners = [_WorldRunner(sim.World(scene, dt=DT, slop=SLOP, fast_paths=fast))
                   for fast in (False, True)]
        for r in runners:
            r.step(10)                              # warm-up, first steps excluded
        times = interleaved(runners, [config["steps"]] * 2, repeats, bar)
        off, on = (statistics.median(t) for t in times)
        label = f"columns({config['columns'][0]}x{config['columns'][1]}, mu={mu})"
        rows.append(_row("friction", label, "fast_paths=False", off))
        rows.append(_row("friction", label, "fast_paths=True", on, 1.0 - on / off))
    return rows


def box_sat(config, repeats, bar):
    world = sim.World(sim.scenes.pyramid(config["pyramid"]), dt=DT, slop=SLOP)
    world.step(10)
    count = int(world._counters[sim.layout.N_MANIFOLDS])
    manifolds = world._contacts[1][:count]
    pairs = np.ascontiguousarray(manifolds[manifolds[:, BODY_A] >= 0][:, [BODY_A, BODY_B]])
    args = (pairs, world._vert_start, world._world_verts, world._world_normals)
    _sat_all(*args, 1)                                   # compile
    step_ms, sat_ms = [], []
    for _ in range(repeats):
        step_ms.append(1e3 * timed(_WorldRunner(world), config["steps"]) / config["steps"])
        sat_ms.append(_median_ms(lambda n: _sat_all(*args, n), config["steps"], 1))
        bar.update()
    step, sat = statistics.median(step_ms), statistics.median(sat_ms)
    label = f"pyramid({config['pyramid']})"
    return [_row("box_sat", label, "step", step),
            _row("box_sat", label, f"general SAT alone, {len(pairs)} box pairs", sat, sat / step,
                 "upper bound of any SAT saving")]


def statics(config, repeats, bar):
    base = sim.scenes.rest_row(config["row"])
    runners = [_WorldRunner(sim.World(s, dt=DT, slop=SLOP))
               for s in (base, with_ledges(base, config["statics"]))]
    for r in runners:
        r.step(10)
    times = interleaved(runners, [config["steps"]] * 2, repeats, bar)
    without, with_ = (statistics.median(t) for t in times)
    label = f"rest_row({config['row']})"
    return [_row("statics", label, "no static polygons", without),
            _row("statics", label, f"{config['statics']} static ledges, untouched", with_,
                 1.0 - with_ / without, "negative = the ledges' cost")]


def rotation(config, repeats, bar):
    world = sim.World(sim.scenes.rest_row(config["row"]), dt=DT, slop=SLOP)
    world.step(10)
    awake = world._activity[1]
    n = int(world._counters[sim.layout.N_AWAKE])

    def geometry(reps):
        for _ in range(reps):
            update_geometry(awake, n, world._position, world._angle, world._vert_start,
                            world._local_verts, world._local_normals, world._rotation,
                            world._world_verts, world._world_normals, world._aabb,
                            world.speculative_distance)
    geometry(1)
    step_ms, geo_ms = [], []
    for _ in range(repeats):
        step_ms.append(1e3 * timed(_WorldRunner(world), config["steps"]) / config["steps"])
        geo_ms.append(_median_ms(geometry, config["steps"], 1))
        bar.update()
    step, geo = statistics.median(step_ms), statistics.median(geo_ms)
    label = f"rest_row({config['row']})"
    return [_row("rotation", label, "step", step),
            _row("rotation", label, "geometry update of every awake body", geo, geo / step,
                 "upper bound of skipping rotation work")]


def verdicts(table):
    """One line per candidate: kept or not, and why (the PAYS rule)."""
    out = []
    f = table[(table["part"] == "friction") & (table["variant"] == "fast_paths=True")]
    frictionless = float(f["saving_share_of_step"].iloc[0])
    frictional = float(f["saving_share_of_step"].iloc[1])
    out.append({"candidate": "friction", "saving": frictionless,
                "verdict": "kept" if frictionless >= PAYS else "does not pay",
                "detail": f"saves {frictionless:.0%} of a frictionless step; {frictional:+.0%} "
                          f"on the frictional scene (noise)"})
    bound = float(table[table["part"] == "box_sat"]["saving_share_of_step"].dropna().iloc[0])
    out.append({"candidate": "box_sat", "saving": bound,
                "verdict": ("not built: cannot pay" if bound < PAYS else
                            "built, saved less than the rule, removed (see docstring)"),
                "detail": f"upper bound {bound:.1%} of a pyramid step"})
    share = float(table[table["part"] == "rotation"]["saving_share_of_step"].dropna().iloc[0])
    out.append({"candidate": "rotation", "saving": share,
                "verdict": ("not built: may pay, the bound is above the rule" if share >= PAYS
                            else "not built: cannot pay"),
                "detail": f"upper bound {share:.1%} of a step"})
    s = float(table[table["part"] == "statics"]["saving_share_of_step"].dropna().iloc[0])
    out.append({"candidate": "statics", "saving": s, "verdict": "structural (resting grid)",
                "detail": f"untouched static polygons change a step by {-s:+.1%}"})
    return out


def run(config, args):
    compile_kernels()
    repeats = config["repeats"]
    rows = []
    with tqdm(total=2 * 2 * repeats + repeats + 2 * repeats + repeats, desc=NAME,
              unit="repeat") as bar:
        rows += friction(config, repeats, bar)
        rows += box_sat(config, repeats, bar)
        rows += statics(config, repeats, bar)
        rows += rotation(config, repeats, bar)
    table = pd.DataFrame(rows)
    scenes = [columns(*config["columns"], 0.0), sim.scenes.pyramid(config["pyramid"]),
              sim.scenes.rest_row(config["row"])]
    return table, scenes, {"dt": DT, "slop": SLOP, "iterations": 10, "pays": PAYS,
                           "verdicts": verdicts(table)}


main = entry(NAME, __doc__, FULL, QUICK, run)

if __name__ == "__main__":
    main()
