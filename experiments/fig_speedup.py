"""Figure "fig_speedup" (figure 4): step time against body count on resting scenes, every system.

Question: once a scene rests, how much cheaper is a step under each freeze policy of sim, and under
the sleeping of Chipmunk (pymunk) and Bullet (pybullet), than with freezing/sleeping off, and how
does that grow with the number of bodies?

Scenes (sim/scenes.py): ``rest_row(n)`` for n in {100, 300, 1000, 3000, 10000} (unit boxes on the
floor, 0.5 m apart: nothing touches but the floor) and ``pyramid(base)`` for base in {5, 10, 20,
40} (15 to 820 boxes, each carried by the two below). Systems: sim-off, sim-sleep, sim-paper,
sim-extended, pymunk, pymunk-sleep, pybullet, pybullet-sleep, box2d, box2d-sleep (study/peers;
dt 1/60 s; each engine at its own default solver settings, study.peers.DEFAULT_ITERATIONS: sim
its soft step with 4 substeps per step and 1 biased + 1 relax sweep per substep, pymunk 10
iterations per step, pybullet 50, Box2D 8 and 3; slop (sim) and collision_slop (pymunk) 0.005 m,
unit boxes' slop; every system's full settings, ``runner.settings``, are in the metadata's
``system_settings``).

pybullet is run only up to PYBULLET_MAX_BODIES = 1000 bodies: Bullet costs ~30 ms per step per
1000 awake boxes here (31 ms on rest_row(1000), 65 ms on pyramid(40) in the run of 2026-12-07),
so rest_row(3000) and rest_row(10000) would cost minutes each. Those rows are in the table with
NaN times and the flag "not run: pybullet capped at 1000 bodies".

Method, per scene: every system is built, then
  1. settled: a freezing system (sim-sleep/paper/extended, pymunk-sleep, pybullet-sleep) is stepped
     one step at a time until no body is solved (``steps_to_all_frozen``) or the cap of
     ``settle_s`` = 4 s of simulated time (Bullet's deactivation time is a fixed 2 s, Chipmunk's and
     sim-sleep's sleep_time 0.5 s); then every system, freezing or not, is stepped on to the cap, so
     all are timed at the same simulated age: the steady state of the resting scene, whatever it is
     (a system that never freezes the whole scene is timed as it is: sim-paper freezes only the
     two lowest rows of a pyramid, and that is a result, not a failure of the run);
  2. 10 untimed warm-up steps; a repeat length calibrated to last ~0.1 s (a frozen sim step costs
     nanoseconds: a short repeat would time the call; ``study.common.calibrate``: a frozen sim
     repeat lasts a few ms, the call under 1% of it);
  3. timed: 7 repeats, interleaved round-robin over all systems of the scene (order reversed on
     every other repeat), the garbage collector paused (study/timing.py); the Numba kernels
     are compiled before anything is timed.
Reported per (scene, system): median and min ms/step over repeats, the awake (solved) count
before and after the timing (a freeze that does not hold during timing shows up here), the step at
which all froze, the largest distance a body moved (m), and the speed-ups:
``speedup`` = median ms/step of the same engine with sleeping off (sim-off for sim's policies,
pymunk for pymunk-sleep, pybullet for pybullet-sleep) / this system's median ms/step (1 for the
references); ``speedup_paired`` = median over repeats of that ratio within a repeat (the two ran
back to back, so slow load drifts cancel); ``speedup_vs_sim_off`` = sim-off median / this median.
Then the same systems again, one step per call (``study.timing.single_calls``: repeats of calls
of ``step(1)``, calibrated alike, interleaved): ``ms_per_call_median`` and ``speedup_single``
(the reference's median / this one's). sim runs many steps in one compiled call, which the
engines' Python APIs cannot: its ms/step above leaves out the call's own cost, which a program
stepping once per call pays every step (a frozen sim step in a long call costs nanoseconds; its
call tens of microseconds), so the single-call speed-up is the comparison such a program sees.

Columns: family, size (n or base), scene, bodies, system, engine, reference, ms_per_step_median,
ms_per_step_min, speedup, speedup_paired, speedup_vs_sim_off, ms_per_call_median,
speedup_single, calls_per_repeat, n_awake_before, n_awake_after,
steps_to_all_frozen, settle_steps, steps_per_repeat, repeats, max_displacement_m, flag
("reference: sleeping off", "all frozen", "NOT all frozen", or "not run: ...").

    python -m experiments.fig_speedup [--quick]
writes results/data/fig_speedup.csv and fig_speedup.json. --quick: rest_row {30, 100}, pyramid
{4, 8}, 2.5 s settle cap, 3 repeats of ~0.01 s.
"""

import math
import statistics

import pandas as pd
from tqdm import tqdm

import sim
from study.common import (
    DT,
    FROZEN_MEANS,
    REFERENCE,
    SLOP,
    SYSTEMS,
    build,
    compile_kernels,
    entry,
    label,
)
from study.peers import engine_of
from study.protocols import FREEZING, WARMUP_STEPS, settle_and_time

NAME = "fig_speedup"
PYBULLET_MAX_BODIES = 1000  # larger scenes are not run under pybullet (cost, see docstring)
FAMILIES = ("rest_row", "pyramid")

FULL = {
    "rest_row": (100, 300, 1000, 3000, 10000),
    "pyramid": (5, 10, 20, 40),
    "settle_s": 4.0,
    "repeat_s": 0.1,
    "repeats": 7,
}
#: --quick: small enough for the test suite. Its largest row has 300 boxes: at 100, before the
#: "quiet" fast path, a frozen step's fixed cost (the stages' calls: ~10 us) was a third of a
#: solved one, so the frozen row's speed-up (3.2-3.5 unloaded) fell under 3 on a loaded machine
#: (2.65, CI beside another run); at 300 it was 8.6 (unloaded).
QUICK = {"rest_row": (30, 300), "pyramid": (4, 8), "settle_s": 2.5, "repeat_s": 0.01, "repeats": 3}


def scenes_of(config):
    """Every scene of the run, family by family, smallest first."""
    return [sim.scenes.BUILDERS[family](size) for family in FAMILIES for size in config[family]]


def systems_for(scene):
    """The systems run on ``scene``: all, except pybullet above PYBULLET_MAX_BODIES."""
    return tuple(
        s for s in SYSTEMS if engine_of(s) != "pybullet" or len(scene.bodies) <= PYBULLET_MAX_BODIES
    )


def _size(scene):
    return scene.params["n"] if scene.name == "rest_row" else scene.params["base"]


def scene_rows(scene, runs, systems, repeats):
    """One row per system of SYSTEMS for a timed scene (``runs``: settle_and_time's dicts for
    ``systems``); systems not run get NaN and a flag saying why."""
    by_system = dict(zip(systems, runs))
    median = {s: statistics.median(r["times"]) for s, r in by_system.items()}
    per_call = {s: statistics.median(r["call_times"]) for s, r in by_system.items()}
    n = len(scene.bodies)
    rows = []
    for system in SYSTEMS:
        ref = REFERENCE[system]
        row = {
            "family": scene.name,
            "size": _size(scene),
            "scene": label(scene),
            "bodies": n,
            "system": system,
            "engine": engine_of(system),
            "reference": ref,
        }
        run = by_system.get(system)
        if run is None:
            rows.append(
                {
                    **row,
                    "ms_per_step_median": math.nan,
                    "ms_per_step_min": math.nan,
                    "speedup": math.nan,
                    "speedup_paired": math.nan,
                    "speedup_vs_sim_off": math.nan,
                    "ms_per_call_median": math.nan,
                    "speedup_single": math.nan,
                    "calls_per_repeat": math.nan,
                    "n_awake_before": math.nan,
                    "n_awake_after": math.nan,
                    "steps_to_all_frozen": math.nan,
                    "settle_steps": math.nan,
                    "steps_per_repeat": math.nan,
                    "repeats": 0,
                    "max_displacement_m": math.nan,
                    "flag": f"not run: pybullet capped at {PYBULLET_MAX_BODIES} bodies",
                }
            )
            continue
        if system not in FREEZING:
            flag = "reference: sleeping off"
        elif run["before"] == 0 and run["after"] == 0:
            flag = "all frozen"
        else:
            flag = "NOT all frozen"
        ref_times = by_system[ref]["times"]
        rows.append(
            {
                **row,
                "ms_per_step_median": median[system],
                "ms_per_step_min": min(run["times"]),
                "speedup": median[ref] / median[system],
                # the reference and this system ran back to back within each repeat
                "speedup_paired": statistics.median(r / t for r, t in zip(ref_times, run["times"])),
                "speedup_vs_sim_off": median["sim-off"] / median[system],
                "ms_per_call_median": per_call[system],
                "speedup_single": per_call[ref] / per_call[system],
                "calls_per_repeat": run["calls"],
                "n_awake_before": run["before"],
                "n_awake_after": run["after"],
                "steps_to_all_frozen": math.nan if run["froze_at"] is None else run["froze_at"],
                "settle_steps": run["age"],
                "steps_per_repeat": run["steps"],
                "repeats": repeats,
                "max_displacement_m": run["moved"],
                "flag": flag,
            }
        )
    return rows


def run(config, args):
    compile_kernels()
    scenes = scenes_of(config)
    cap = int(round(config["settle_s"] / DT))
    repeats = config["repeats"]
    rows, settings = [], {}
    total = sum(len(systems_for(s)) for s in scenes) * repeats
    with tqdm(total=total, desc=f"{NAME} timing", unit="repeat") as bar:
        for scene in scenes:
            systems = systems_for(scene)
            runs = settle_and_time(
                scene, systems, cap, config["repeat_s"], repeats, bar, age_steps=cap
            )
            rows += scene_rows(scene, runs, systems, repeats)
    probe = sim.scenes.single_box()
    for system in SYSTEMS:
        with build(system, probe) as r:
            settings[system] = r.settings
    parameters = {
        "dt": DT,
        "slop": SLOP,
        "settle_cap_steps": cap,
        "warmup_steps": WARMUP_STEPS,
        "pybullet_max_bodies": PYBULLET_MAX_BODIES,
        "reference": REFERENCE,
        "frozen_means": FROZEN_MEANS,
        "system_settings": settings,
    }
    return pd.DataFrame(rows), scenes, parameters


main = entry(NAME, __doc__, FULL, QUICK, run)

if __name__ == "__main__":
    main()
