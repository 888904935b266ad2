"""Table "bench_freeze": what freezing resting bodies buys in step time, and what it costs.

Question: once bodies rest, how cheap does a step become under each freeze policy (and under the
big engines' sleeping), what does a frozen body still cost next to an awake one, how soon does each
system stop solving a resting scene, and does freezing slow down scenes where nothing can rest?
Four parts, one long-form table (column ``part``), each answering one of the issue's targets:

1. ``frozen_cost`` — rest_row(5000) once fully frozen: ms/step under sim-off (the reference,
   nothing frozen), sim-sleep, sim-paper, sim-extended, pymunk-sleep and box2d-sleep; and
   rest_row(500) with
   the same systems plus pybullet-sleep (Bullet steps ~25 ms per awake 500-box row, and needs its
   fixed 2 s of deactivation time before any body sleeps, so it is timed on the smaller row). Each
   freezing system is stepped one step at a time until no body is solved (counted, see "frozen"
   below), then 10 more untimed steps; the awake count is recorded before and after the timing.
   Target: sim under 0.02 ms/step fully frozen (pymunk asleep: ~0.013). Also timed one step per
   call (``ms_per_call_median``, ``speedup_vs_off_single``; study.timing.single_calls): what a
   program stepping once per call pays, call overhead included.
2. ``per_body_cost`` — ms/step = a * N_awake + b * N_frozen + c, fitted by least squares. Each mix
   is rest_row(N_frozen) plus N_awake unit boxes in a block (pitch 2 m, so they never touch) that
   start 3000 m up, thrown upwards so that they peak half way through the timing
   (``study.protocols.mix_launch``: at most 28.6 m/s, 0.48 m a step, at 7 x 50 steps): they are
   awake and in flight through the whole
   timing (checked: their lowest point stays far above the floor, and under sim-extended the awake
   count equals N_awake before and after). N_frozen x N_awake = {0, 1000, 2000, 4000} x
   {100, 400, 1600}, under sim-extended (the row frozen) and under sim-off (every body solved; there
   the fit's b is the cost of a resting body that is solved). The flyer counts span 16x because an
   awake body without contacts was cheap when this was chosen (a ~ 0.13-0.22 us a step then): with
   {100, 200, 400} the flyers changed a sim-off step (1-2 ms with the 4000-box row solved) by
   0.05 ms, within its timing noise, and sim-off's a came out 0.04 +- 0.23 us (even negative under
   load); with {100, 400, 1600} it is 0.13 +- 0.01 us (2026-12-07). Every world of the sweep is
   built first and the repeats run round-robin over all of them, so slow drifts in machine load
   spread over every mix instead of biasing some. Reported: a, b, c with standard errors, b/a
   (target <= 0.02), the RMS and largest residual and R^2, and b(extended)/b(off). The awake bodies
   are the cheapest kind: no contacts, and slow (dropped from rest they reached 57 m/s, and sim's
   continuous stage swept each every step, 1.1-1.8 us of its a; see experiments/fig_scaling.py).
3. ``time_to_freeze`` — steps until every body is frozen/asleep, for every system that freezes
   (study.systems.FREEZING: sim-sleep, sim-paper, sim-extended, pymunk-sleep, pybullet-sleep and
   box2d-sleep) on rest_row(50), drop(30, seed 0..2), pyramid(10),
   pyramid(20) and stack(5), capped at 30 s of simulated time: a system that does not get there is
   reported as NaN with flag "never", with the number still awake at the cap. Also recorded: how
   many bodies are awake 1 s after all froze (a freeze that does not hold), and the largest
   distance any body moved. Target: rest_row frozen within 3 steps under paper and extended
   (pymunk needs 31 steps, pybullet ~125).
4. ``in_flight_overhead`` — scenes where nothing can rest: "fall" (1000 boxes falling from 3000 m,
   never touching) and "drift" (1000 boxes in zero gravity without a floor, all moving at about
   3 m/s with random spread and spin, so some collide but none is ever slow): ms/step under
   sim-off and sim-extended in three phases of each scene (the fall from its start, half way
   down and near the end of its flight; the drift from steps 0, 500 and 1000), each phase timed
   on fresh builds from the same state, 3x the usual repeats, and per phase the ratio
   extended/off (the median of the repeats' paired ratios; also the ratio of medians). The
   scenes are not stationary (the fall's step costs ~25x more late than early), so a phase is
   never compared with another (``study/in_flight.py`` says how). Target: extended no more than
   5 % slower than off in every phase (scene rows ``ratio_to_off_worst``,
   ``worst_phase_step``).

"Frozen" means *no work is done for the body*: every runner's ``asleep`` (for sim,
``World.frozen``: out of the awake list). Under ``paper`` a VERTICAL_STABLE body that pivots, or a
ROTATION_STABLE body that still slides, is awake; part 3 also reports, for sim, the step at which
every body had left FREE (``steps_to_all_not_free``), beside the frozen one.

Method (docs/ARCHITECTURE.md §5; the protocols are study/protocols.py's, shared with the
figures): one throwaway tiny World per freeze policy compiles the Numba kernels first; every
runner is built, then stepped (untimed) through warm-up; timed repeats call ``runner.step(K)``
with the garbage collector paused, interleaved round-robin over all systems compared (order
reversed on every other repeat); reported per step are the median and min over repeats (default
7), in ms. All systems use dt 1/60 s and each engine's own default solver
settings (study.peers.DEFAULT_ITERATIONS): sim its soft step with 4 substeps per step and
1 biased + 1 relax sweep per substep, pymunk 10 iterations per step, pybullet 50; slop (sim)
0.005 m, a cap that scales down with small bodies, and pymunk's collision_slop matched to each
scene's smallest body (``study.common.comparable_slop``; each scene's in the metadata's
``scenes``). Every system's full settings (``runner.settings``, on a probe scene) are in the
metadata's ``system_settings``. In part 1, K is chosen per system so that a repeat lasts about
0.1 s (``study.common.calibrate``; a frozen sim step costs nanoseconds, and its repeats last a few
ms, the call under 1% of them).

Columns: part, scene, system, bodies, n_awake, n_frozen, metric, value, unit, flag. n_awake and
n_frozen are measured counts (part 1: before timing; part 3: when all froze, or at the cap), except
in part 2, where they are the mix's design (N_awake in flight, N_frozen the row; under sim-off the
row is solved, not frozen). The fit rows of part 2 have scene "fit". ``<name>.json`` holds the
metadata, the fits and every target's verdict.

    python -m experiments.bench_freeze [--quick] [--repeats R]
writes results/data/bench_freeze.csv and bench_freeze.json.
"""

import argparse
import math
import statistics

import numpy as np
import pandas as pd
from tqdm import tqdm

import sim
from study.common import (
    interrupted,
    DT,
    SLOP,
    build,
    compile_kernels,
    data_folder,
    label,
)
from study.cli import first_paragraph, or_default, positive_int
from study.metadata import code_state, collect, write_results
from study.protocols import (
    FALL_HEIGHT,
    FLY_PITCH,
    FREEZE_HOLD_S,
    FREEZING,
    MIX_SYSTEMS,
    WARMUP_STEPS,
    fall_scene,
    flight_budget,
    freeze_run,
    freeze_tasks,
    long_row,
    mix_launch,
    mix_scene,
    per_body_cost,
    settle_and_time,
)
from study.in_flight import (
    DRIFT_SEED,
    DRIFT_SPEED,
    DRIFT_SPREAD,
    PART,
    drift_scene,
    in_flight_overhead,
    n_timings,
    phase_starts,
    spans,
)

NAME = "bench_freeze"

FROZEN_SYSTEMS = (
    "sim-off",
    "sim-sleep",
    "sim-paper",
    "sim-extended",
    "pymunk-sleep",
    "box2d-sleep",
)
FROZEN_SYSTEMS_PB = FROZEN_SYSTEMS + ("pybullet-sleep",)

#: the issue's targets
TARGET_FROZEN_MS = 0.02  # ms/step, sim fully frozen on rest_row(5000)
TARGET_B_OVER_A = 0.02  # frozen body-step vs awake body-step
TARGET_FREEZE_STEPS = 3  # rest_row frozen within this many steps under paper/extended
TARGET_OVERHEAD = 1.05  # extended / off on a scene where nothing rests

FULL = {
    "frozen_cost": (("rest_row", 5000, FROZEN_SYSTEMS), ("rest_row", 500, FROZEN_SYSTEMS_PB)),
    "frozen_repeat_s": 0.1,  # aim of one timed repeat in part 1, s
    "freeze_cap_s": 10.0,  # part 1: most simulated time spent waiting for the freeze
    "mix_frozen": (0, 1000, 2000, 4000),
    "mix_awake": (100, 400, 1600),
    "mix_steps": 50,
    "ttf_scenes": (
        ("rest_row", {"n": 50}),
        ("drop", {"n": 30, "seed": 0}),
        ("drop", {"n": 30, "seed": 1}),
        ("drop", {"n": 30, "seed": 2}),
        ("pyramid", {"base": 10}),
        ("pyramid", {"base": 20}),
        ("stack", {"height": 5}),
    ),
    "ttf_cap_s": 30.0,
    "flight_n": 1000,
    "flight_steps": 50,
    "drift_span": 1000,  # steps over which the drift's phases start (study.in_flight)
    "flight_repeat_factor": 3,
    "repeats": 7,
}
QUICK = {
    "frozen_cost": (("rest_row", 200, FROZEN_SYSTEMS_PB),),
    "frozen_repeat_s": 0.01,
    "freeze_cap_s": 5.0,
    # flyers 10x apart and 50 steps a repeat, so that the awake cost (a ~ 0.13 us per step) is
    # resolved under sim-off too: with (20, 50) flyers and 10 steps, the flyers changed a sim-off
    # step by 0.004 ms, below its noise, and the fit's a was 0.04-0.18 +- 0.05 us, once negative
    "mix_frozen": (0, 200, 400),
    "mix_awake": (20, 200),
    "mix_steps": 50,
    "ttf_scenes": (
        ("rest_row", {"n": 50}),
        ("drop", {"n": 10, "seed": 0}),
        ("pyramid", {"base": 5}),
        ("stack", {"height": 5}),
    ),
    "ttf_cap_s": 5.0,
    "flight_n": 200,
    "flight_steps": 10,
    "drift_span": 60,
    "flight_repeat_factor": 2,
    "repeats": 3,
}


# ---- part 1: a fully frozen scene --------------------------------------------------------------
def frozen_cost(config, repeats, progress):
    rows = []
    for name, n, systems in config["frozen_cost"]:
        scene = sim.scenes.BUILDERS[name](n)
        tag = label(scene)
        cap = int(round(config["freeze_cap_s"] / DT))
        runs = settle_and_time(scene, systems, cap, config["frozen_repeat_s"], repeats, progress)
        off_median, off_call = (
            (
                statistics.median(runs[systems.index("sim-off")]["times"]),
                statistics.median(runs[systems.index("sim-off")]["call_times"]),
            )
            if "sim-off" in systems
            else (math.nan, math.nan)
        )
        for system, run in zip(systems, runs):
            times, before, after = run["times"], run["before"], run["after"]
            med, low = statistics.median(times), min(times)
            call = statistics.median(run["call_times"])
            if system not in FREEZING:
                flag = "reference: nothing frozen"
            elif before == 0 and after == 0:
                flag = "all frozen"
            else:
                flag = "NOT all frozen"
            common = dict(
                part="frozen_cost",
                scene=tag,
                system=system,
                bodies=n,
                n_aw=before,
                n_fr=n - before,
                flag=flag,
            )
            rows += [
                long_row(**common, metric="ms_per_step_median", value=med, unit="ms"),
                long_row(**common, metric="ms_per_step_min", value=low, unit="ms"),
                long_row(**common, metric="speedup_vs_off", value=off_median / med, unit="ratio"),
                long_row(**common, metric="ms_per_call_median", value=call, unit="ms"),
                long_row(
                    **common, metric="speedup_vs_off_single", value=off_call / call, unit="ratio"
                ),
                long_row(**common, metric="calls_per_repeat", value=run["calls"], unit="calls"),
                long_row(**common, metric="n_awake_before", value=before, unit="bodies"),
                long_row(**common, metric="n_awake_after", value=after, unit="bodies"),
                long_row(
                    **common,
                    metric="steps_to_all_frozen",
                    value=math.nan if run["froze_at"] is None else run["froze_at"],
                    unit="steps",
                ),
                long_row(**common, metric="steps_per_repeat", value=run["steps"], unit="steps"),
                long_row(**common, metric="repeats", value=repeats, unit="count"),
                long_row(**common, metric="max_displacement", value=run["moved"], unit="m"),
            ]
    return rows


def time_to_freeze(config, progress):
    rows = []
    for task in freeze_tasks(config["ttf_scenes"], config["ttf_cap_s"]):
        progress.set_postfix_str(f"{task.builder}{task.params} {task.system}")
        rows += freeze_run(task)
        progress.update()
    return rows


# ---- verdicts ----------------------------------------------------------------------------------
def _value(table, part, metric, scene=None, system=None):
    sel = (table["part"] == part) & (table["metric"] == metric)
    if scene is not None:
        sel &= table["scene"] == scene
    if system is not None:
        sel &= table["system"] == system
    values = table.loc[sel, "value"]
    return float(values.iloc[0]) if len(values) else math.nan


def body_cost_verdict(fit):
    """Target 2 from the cost fit of sim-extended: (met, note). Met when b/a <= TARGET_B_OVER_A
    and the fit measured something: an awake body whose fitted cost a is not positive (timing
    noise swamping a small quick fit) makes b/a meaningless, and a negative b/a would otherwise
    pass."""
    note = f"fit RMS residual {fit['rms_residual']:.3g} ms/step, R^2 {fit['r2']:.4f}"
    if not fit["a"] > 0:
        return False, note + f"; the fit's awake-body cost a = {fit['a']:.3g} ms is not positive"
    return bool(fit["b_over_a"] <= TARGET_B_OVER_A), note


def verdicts(table, config, fits):
    """Every target of the issue: (name, measured, target text, PASS/MISS) as dicts."""
    out = []

    def add(target, measured, goal, ok, note=""):
        out.append(
            {
                "target": target,
                "measured": measured,
                "goal": goal,
                "verdict": "PASS" if ok else "MISS",
                "note": note,
            }
        )

    name, n, systems = config["frozen_cost"][0]
    tag = f"{name}({n})"
    for system in ("sim-sleep", "sim-paper", "sim-extended"):
        ms = _value(table, "frozen_cost", "ms_per_step_median", tag, system)
        before = _value(table, "frozen_cost", "n_awake_before", tag, system)
        after = _value(table, "frozen_cost", "n_awake_after", tag, system)
        add(
            f"1. {tag} fully frozen, {system}",
            f"{ms:.4f} ms/step (awake {before:.0f} -> {after:.0f})",
            f"< {TARGET_FROZEN_MS} ms/step, all frozen",
            ms < TARGET_FROZEN_MS and before == 0 and after == 0,
        )
    ext = fits["sim-extended"]
    add(
        "2. frozen vs awake body-step, sim-extended",
        f"b/a = {ext['b_over_a']:.4g} "
        f"(a {ext['a']:.3g}, b {ext['b']:.3g} +- {ext['b_stderr']:.2g} ms)",
        f"b/a <= {TARGET_B_OVER_A}",
        *body_cost_verdict(ext),
    )
    for system in ("sim-paper", "sim-extended"):
        steps = _value(table, "time_to_freeze", "steps_to_all_frozen", "rest_row(50)", system)
        add(
            f"3. rest_row(50) frozen, {system}",
            f"{steps:.0f} steps",
            f"<= {TARGET_FREEZE_STEPS} steps",
            steps <= TARGET_FREEZE_STEPS,
        )
    for scene in (f"fall({config['flight_n']})", f"drift({config['flight_n']})"):
        worst = _value(table, PART, "ratio_to_off_worst", scene, "sim-extended")
        at = _value(table, PART, "worst_phase_step", scene, "sim-extended")
        add(
            f"4. {scene} extended / off, worst phase",
            f"{worst:.3f} (from step {at:.0f})",
            f"<= {TARGET_OVERHEAD}",
            worst <= TARGET_OVERHEAD,
        )
    return out


def summary(table, config, fits, targets, quick):
    """A readable account of every part and every target."""
    lines = []
    fmt = lambda x: "nan" if not np.isfinite(x) else f"{x:.4g}"
    t = table[table["part"] == "frozen_cost"]
    lines.append(
        "== 1. frozen_cost: ms/step once fully frozen (median [min]; awake before -> after)"
    )
    for scene in dict.fromkeys(t["scene"]):
        for system in dict.fromkeys(t.loc[t["scene"] == scene, "system"]):
            g = lambda m: _value(table, "frozen_cost", m, scene, system)
            lines.append(
                f"  {scene:14s} {system:15s} {fmt(g('ms_per_step_median')):>9s} "
                f"[{fmt(g('ms_per_step_min'))}] ms  x{fmt(g('speedup_vs_off'))} vs off  "
                f"one step per call {fmt(g('ms_per_call_median'))} ms "
                f"x{fmt(g('speedup_vs_off_single'))}  "
                f"awake {g('n_awake_before'):.0f} -> {g('n_awake_after'):.0f}  "
                f"froze at step {fmt(g('steps_to_all_frozen'))}"
            )
    lines.append("== 2. per_body_cost: ms/step = a N_awake + b N_frozen + c")
    t = table[(table["part"] == "per_body_cost") & (table["metric"] == "ms_per_step_median")]
    piv = t.pivot_table(index=["n_frozen", "n_awake"], columns="system", values="value")
    lines += ["  " + s for s in piv.to_string(float_format=lambda x: f"{x:.4f}").splitlines()]
    for system, f in fits.items():
        lines.append(
            f"  fit {system:13s} a={f['a']:.4g}+-{f['a_stderr']:.2g}  "
            f"b={f['b']:.4g}+-{f['b_stderr']:.2g}  c={f['c']:.4g}+-{f['c_stderr']:.2g} "
            f"ms  b/a={f['b_over_a']:.4g}  RMS resid {f['rms_residual']:.3g} ms  "
            f"R^2 {f['r2']:.4f}"
        )
    f = fits["sim-extended"]
    lines.append(
        f"  a frozen body costs {f['b_over_b_off']:.3g} of a resting body solved under "
        f"off (b_ext / b_off)"
    )
    lines.append(
        "== 3. time_to_freeze: steps until every body is frozen/asleep "
        f"(cap {config['ttf_cap_s']:g} s; 'never' = not within the cap, awake left)"
    )
    t = table[table["part"] == "time_to_freeze"]
    for scene in dict.fromkeys(t["scene"]):
        cells = []
        for system in FREEZING:
            steps = _value(table, "time_to_freeze", "steps_to_all_frozen", scene, system)
            left = _value(table, "time_to_freeze", "n_awake_at_end", scene, system)
            held = _value(table, "time_to_freeze", "n_awake_1s_after", scene, system)
            cell = (
                f"never({left:.0f} awake)"
                if not np.isfinite(steps)
                else f"{steps:.0f}" + (f"(+{held:.0f} woke)" if held > 0 else "")
            )
            cells.append(f"{system}={cell}")
        lines.append(f"  {scene:17s} " + "  ".join(cells))
    lines.append(
        "== 4. in_flight_overhead: nothing can rest (ms/step, median of fresh builds per phase)"
    )
    t = table[(table["part"] == PART) & (table["metric"] == "phase_start_step")]
    for scene in dict.fromkeys(t["scene"]):
        g = lambda m, s: _value(table, PART, m, scene, s)
        lines.append(
            f"  {scene:26s} off {g('ms_per_step_median', 'sim-off'):.4f}  extended "
            f"{g('ms_per_step_median', 'sim-extended'):.4f}  ratio paired "
            f"{g('ratio_to_off_paired', 'sim-extended'):.3f} (of medians "
            f"{g('ratio_to_off_median', 'sim-extended'):.3f})  awake "
            f"{g('n_awake_after', 'sim-extended'):.0f}/"
            f"{g('n_awake_before', 'sim-extended'):.0f}"
        )
    lines.append("== targets" + (" (QUICK sizes: indicative only)" if quick else ""))
    for v in targets:
        lines.append(
            f"  {v['verdict']:4s}  {v['target']}: {v['measured']}  (goal {v['goal']})"
            + (f"  [{v['note']}]" if v["note"] else "")
        )
    return "\n".join(lines)


# ---- entry -------------------------------------------------------------------------------------
def run(config, repeats):
    """Every part; returns (table, fits)."""
    compile_kernels()
    n_mix = len(config["mix_frozen"]) * len(config["mix_awake"]) * len(MIX_SYSTEMS)
    flight_repeats = config["flight_repeat_factor"] * repeats
    rows = []
    with tqdm(
        total=sum(len(s) for _, _, s in config["frozen_cost"]) * repeats,
        desc=f"{NAME} 1/4 frozen_cost",
        unit="repeat",
    ) as bar:
        rows += frozen_cost(config, repeats, bar)
    with tqdm(total=n_mix * repeats, desc=f"{NAME} 2/4 per_body_cost", unit="repeat") as bar:
        part, fits = per_body_cost(config, repeats, bar)
        rows += part
    with tqdm(
        total=len(config["ttf_scenes"]) * len(FREEZING),
        desc=f"{NAME} 3/4 time_to_freeze",
        unit="run",
    ) as bar:
        rows += time_to_freeze(config, bar)
    with tqdm(
        total=n_timings(config, flight_repeats),
        desc=f"{NAME} 4/4 in_flight_overhead",
        unit="repeat",
    ) as bar:
        rows += in_flight_overhead(config, flight_repeats, bar)
    return pd.DataFrame(rows), fits


def scenes_of(config, repeats):
    """Every scene the run uses (for the metadata)."""
    scenes = [sim.scenes.BUILDERS[name](n) for name, n, _ in config["frozen_cost"]]
    launch = mix_launch(config, repeats)
    scenes += [
        mix_scene(nf, na, launch=launch)
        for nf in config["mix_frozen"]
        for na in config["mix_awake"]
    ]
    scenes += [sim.scenes.BUILDERS[name](**p) for name, p in config["ttf_scenes"]]
    scenes += [fall_scene(config["flight_n"]), drift_scene(config["flight_n"])]
    return scenes


def main(argv=None, data_dir=None):
    """Command line entry; ``data_dir`` overrides results/data (tests)."""
    parser = argparse.ArgumentParser(
        prog=f"python -m experiments.{NAME}", description=first_paragraph(__doc__)
    )
    parser.add_argument("--quick", action="store_true", help="small sizes, few repeats (CI)")
    parser.add_argument(
        "--repeats",
        type=positive_int,
        default=None,
        help="timed repeats (default 7, quick 3; part 4 uses 3x, quick 2x)",
    )
    args = parser.parse_args(argv)
    started = code_state()  # the code that runs (collect says if it changes before the end)
    config = QUICK if args.quick else FULL
    repeats = or_default(args.repeats, config["repeats"])

    try:
        table, fits = run(config, repeats)
    except KeyboardInterrupt:
        raise SystemExit(interrupted(NAME, data_folder(args.quick, data_dir))) from None
    targets = verdicts(table, config, fits)
    settings = {}
    probe = sim.scenes.single_box()
    for system in dict.fromkeys(FROZEN_SYSTEMS_PB + MIX_SYSTEMS + FREEZING):
        with build(system, probe) as r:
            settings[system] = r.settings
    parameters = {
        "dt": DT,
        "slop": SLOP,
        "warmup_steps": WARMUP_STEPS,
        "repeats": repeats,
        "flight_repeats": config["flight_repeat_factor"] * repeats,
        "quick": args.quick,
        "sizes": config,
        "fall_height_m": FALL_HEIGHT,
        "mix_launch_m_per_s": mix_launch(config, repeats),
        "fly_pitch_m": FLY_PITCH,
        "flight_budget_steps": flight_budget(),
        "drift": {"speed": DRIFT_SPEED, "spread": DRIFT_SPREAD, "seed": DRIFT_SEED},
        "flight_phases": {label(s): phase_starts(n) for s, n in spans(config)},
        "freeze_hold_s": FREEZE_HOLD_S,
        "frozen_means": (
            "sim: World awake_slot < 0 (out of the awake list); pymunk/pybullet/box2d: asleep"
        ),
        "system_settings": settings,
    }
    folder = data_folder(args.quick, data_dir)
    metadata = collect(
        scenes_of(config, repeats), parameters, script=NAME, seed=DRIFT_SEED, started=started
    )
    metadata["fits"] = fits
    metadata["targets"] = targets
    csv_path, _ = write_results(NAME, table, metadata, folder=folder)
    print(summary(table, config, fits, targets, args.quick))
    print(f"wrote {csv_path}")
    return table


if __name__ == "__main__":
    main()
