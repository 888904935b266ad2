"""Table 8 "table_failures": the failure catalogue — where freezing resting bodies goes wrong.

Question: in the scenarios where freezing can go wrong (the seed paper's admitted limits and the
big engines' known ones), which systems get the outcome wrong, is it freezing that made it wrong
(or the engine itself), how far off do the bodies end, and what did freezing buy in time?

Scenarios (``study.scenarios``, whose docstrings give each scene's geometry and the physics
of its outcome): support_removed, overhang (seed figure 3), tipping, unstable_equilibrium,
slow_sliding, slope_creep, unstable_ledge, slow_glide, slope_creep_plank (each a second case, with
other geometry, of the three before it), impact_on_stack, load_on_overhang, wake_cascade,
three_bodies. Each runs
for its own duration (3-7 s); a projectile that must arrive after everything froze arrives at
3.5 s (after Bullet's fixed 2 s of deactivation time).

Systems: all ten (sim-off, sim-sleep, sim-paper, sim-extended, pymunk, pymunk-sleep, pybullet,
pybullet-sleep, box2d, box2d-sleep) at dt 1/60 s, each engine at its own default solver settings
(study.peers.DEFAULT_ITERATIONS): sim's soft step with 4 substeps per step and 1 biased
+ 1 relax sweep per substep; pymunk 10 iterations per step; pybullet 50 per step. Sim slop and
pymunk collision_slop 0.005 m, every freezing/sleeping parameter at its default
(study.common.build). Each system's full settings (``runner.settings``) are in the
metadata's ``system_settings``.

Truth: sim-off at dt / ``truth_divisor`` (8: 1/480 s) at sim's default 4 substeps, with
``truth_iterations`` (4) biased sweeps per substep (and the default 1 relax sweep), classified by
the scenario's classifier. Since solver v2 ``iterations`` counts sweeps *per substep*: the old
truth's 20 velocity iterations per step at dt/8 was 160 sweeps per 1/60 s; 4 per substep at 4
substeps and dt/8 is 128 biased + 32 relax sweeps, the same effort per simulated second, against
the judged sim runs' 4 + 4 (8x finer step, 4x the sweeps per substep). Measured on every
scenario, sim-off at dt/4 and dt/8 with 1, 2 and 4 sweeps per substep and at dt/16 with 8 give
the same label each time (solver v2, quick and full truth alike); the measures of the
non-chaotic scenarios agree to a few mm (what follows an impact is chaotic: poses, not labels,
differ there). The truth's label is checked against what physics says (the scenario's
``expected``; column ``truth_is_expected``, and tests/unit/test_scenarios.py); a mismatch would be
the
scenario's fault and is reported, not hidden.

Per scenario x system (one row each):
- ``outcome``: the label of the final pose (the untimed run; the timed runs are checked to end in
  the same pose, column ``timed_pose_diff_m``); ``right``: outcome == truth; ``changed``: outcome
  differs from the same engine with sleeping off at the same dt (``reference``), i.e. freezing
  changed the outcome; ``engine_right``: the reference's own outcome == truth (when it is not,
  a wrong outcome is the engine's, not freezing's).
- ``measure``: the continuous quantity the label is judged on (``measure_name``, unit in the
  name), beside the truth's (``truth_measure``).
- pose error against the reference's final pose: ``pose_error_m`` (largest centre distance) and
  ``pose_error_rad`` (largest angle difference, modulo 2 pi) over the *key* bodies (all but
  projectiles: a projectile that slides on for ever says nothing about freezing), and
  ``pose_error_all_m`` over every body. Also the same against the truth (``truth_error_m``).
- what was frozen: ``frozen_fraction`` (body-steps frozen / body-steps, ``asleep`` of the runner,
  sampled after every step), ``key_ever_frozen`` (fraction of key bodies frozen at some step: did
  the danger meet a frozen body at all?) and, for scheduled events, ``asleep_at_event`` (fraction
  of key bodies frozen on the step before the projectile arrives, 0.1 s before ``event_s``).
- timing: ``wall_ms_median`` / ``wall_ms_min``: wall time of one whole run after its first step
  (median and min over ``repeats``, default 7), ``ms_per_step``, ``speedup`` = the reference's
  median / this system's median (1 for the references), and ``speedup_min``, the same ratio of
  minima (a check: when the two disagree, the machine was busy). Method (docs/ARCHITECTURE.md §5):
  Numba
  kernels compiled first (common.compile_kernels); one untimed trial run per system sizes K, the
  runs per repeat, so that a repeat lasts about ``repeat_s`` (50 ms; K = 1 for most Bullet runs,
  ~20-150 for sim and pymunk; column ``runs_per_repeat``); each repeat builds K runners
  (untimed), steps each once (untimed: the first step's contact creation is excluded), then times
  ``step(n - 1)`` of the K runners back to back with the garbage collector paused, and divides by
  K; repeats round-robin over the ten systems, order reversed every other repeat, serially in
  this process. The untimed runs (truth, and each system stepped one step at a time to sample
  ``asleep``) go through study.executor.run_tasks.

Without sim's presolve: sim solves the start pose's contact impulses to convergence before step 1
(``World(initial_iterations=...)``, on by default), so a body placed at rest starts in equilibrium;
no peer has that. Each sim system's untimed run is repeated without it (``initial_iterations=0``,
the variants "sim-off (no presolve)" etc., ``study.systems.NO_PRESOLVE``), judged the same way
against "sim-off (no presolve)": columns ``outcome_no_presolve``, ``changed_no_presolve`` and
``right_no_presolve`` of the sim rows (empty for the peers). The timed runs are the defaults'
only.

Choices: the whole scenario is the timed unit (its speed-up is what freezing buys on *that* run,
danger included; these scenes have 1-10 bodies, so per-step overheads weigh heavily and speed-ups
are small: the scaling study measures large scenes). ``right`` is judged on labels, whose
thresholds are each classifier's (stated in study.scenarios); pose errors give the size.

Columns: scenario, system, reference, bodies, seconds, steps, event_s, expected, truth,
truth_is_expected, outcome, right, changed, engine_right, measure_name, measure, truth_measure,
pose_error_m, pose_error_rad, pose_error_all_m, truth_error_m, frozen_fraction, key_ever_frozen,
asleep_at_event, wall_ms_median, wall_ms_min, ms_per_step, speedup, speedup_min, repeats,
runs_per_repeat, timed_pose_diff_m; for sim, outcome_no_presolve, changed_no_presolve,
right_no_presolve.

    python -m experiments.table_failures [--quick] [--repeats R] [--only NAME[,NAME...]]
writes results/data/table_failures.csv and table_failures.json (with --only, results/only/: part
of the catalogue never replaces the table).
"""

import argparse
import math
import statistics

import numpy as np
import pandas as pd
from tqdm import tqdm

from study import cli, common, scenarios, systems
from study.common import DT, REFERENCE, SYSTEMS, build, compile_kernels, pose_error, sweep_store
from study.executor import run_tasks
from study.timing import timed

NAME = "table_failures"
TRUTH_SYSTEM = "sim-off"
EVENT_LEAD_S = 0.1  # s before a scheduled arrival at which "asleep at event" is read

#: repeat_s: a sim or pymunk run of these scenes lasts 0.3-10 ms; timed alone, on the shared
#: 2-core machine (load 3-5) half the repeats of a 1 ms run came out 2-5 times slower (the process
#: preempted for a time slice) and medians were noise. A repeat therefore times K whole runs back
#: to back, K chosen so that it lasts about repeat_s; a busy machine then stretches every system's
#: repeat alike instead of hitting a few at random.
FULL = {
    "scenarios": tuple(scenarios.SCENARIOS),
    "repeats": 7,
    "repeat_s": 0.05,
    "truth_divisor": 8,
    "truth_iterations": 4,
}
#: quick: the same scenarios (each is small; the tests check every truth label), one repeat of
#: one run (timings are only smoke-tested) and a coarser truth (dt/4)
QUICK = {
    "scenarios": tuple(scenarios.SCENARIOS),
    "repeats": 1,
    "repeat_s": 0.0,
    "truth_divisor": 4,
    "truth_iterations": 4,
}


def _steps(seconds, dt):
    return int(round(seconds / dt))


def observe(task):
    """One untimed run: (scenario name, system, dt, iterations or None: the engine's default; for
    sim, sweeps per substep). Steps one step at a time
    to sample ``asleep``; returns the final pose, its label and measure, and what was frozen."""
    name, system, dt, iterations = task
    scenario = scenarios.get(name)
    scene = scenario.build()
    seconds = scenario.duration(scene)
    steps = _steps(seconds, dt)
    key = scenarios.key_bodies(scene)
    event_s = scenario.event_time(scene)
    event_step = None if event_s is None else _steps(event_s - EVENT_LEAD_S, dt)
    settings = {} if iterations is None else {"iterations": iterations}
    settings.update(systems.system_settings(system))  # a variant's (no presolve)
    runner = build(systems.runner_system(system), scene, dt=dt, **settings)
    try:
        frozen_steps = 0  # body-steps frozen
        ever = np.zeros(len(scene.bodies), dtype=bool)
        at_event = math.nan
        for k in range(1, steps + 1):
            runner.step(1)
            asleep = np.asarray(runner.asleep, dtype=bool)
            frozen_steps += int(asleep.sum())
            ever |= asleep
            if k == event_step:
                at_event = float(asleep[key].mean())
        positions, angles = runner.positions, runner.angles
        return {
            "positions": positions,
            "angles": angles,
            "outcome": scenario.classify(scene, positions, angles),
            "measure": scenario.measure(scene, positions, angles),
            "frozen_fraction": frozen_steps / (steps * len(scene.bodies)),
            "key_ever_frozen": float(ever[key].mean()),
            "asleep_at_event": at_event,
            "steps": steps,
            "settings": runner.settings,
        }
    finally:
        runner.close()


class Batch:
    """K runners of the same scenario stepped back to back, so that one timed repeat lasts long
    enough (see ``time_scenario``) and is still a whole run of each."""

    def __init__(self, runners):
        self.runners = runners

    @property
    def engine_seconds(self):
        """s: the runners' engine time summed, when every runner keeps one (``timing.timed``
        then times the engines alone, as for a single runner: Box2D's per-step motion-cap read
        and pybullet-sleep's pose read are the runner's work); else None (timed whole)."""
        kept = [getattr(r, "engine_seconds", None) for r in self.runners]
        return None if any(k is None for k in kept) else sum(kept)

    def step(self, n):
        for r in self.runners:
            r.step(n)
        return self


def runs_per_repeat(system, scene, steps, target_s):
    """K, the runs per timed repeat: one untimed trial run (built, first step, then the rest
    timed) gives the length of a run; K = ceil(target_s / that), at least 1 (target_s 0: K = 1,
    no trial run)."""
    if target_s <= 0:
        return 1
    runner = build(system, scene)
    try:
        runner.step(1)
        wall = timed(runner, steps - 1)
    finally:
        runner.close()
    return max(1, math.ceil(target_s / max(wall, 1e-9)))


def time_scenario(name, systems, repeats, target_s, progress):
    """Wall time (s) per run of every system's whole run of scenario ``name`` after its first
    step, per repeat; K runs per repeat (``runs_per_repeat``); and each system's final poses.
    Round-robin over systems, order reversed every other repeat."""
    scenario = scenarios.get(name)
    scene = scenario.build()
    steps = _steps(scenario.duration(scene), DT)
    k_runs = {s: runs_per_repeat(s, scene, steps, target_s) for s in systems}
    walls = {s: [] for s in systems}
    poses = {s: [] for s in systems}
    for r in range(repeats):
        for system in systems if r % 2 == 0 else systems[::-1]:
            progress.set_postfix_str(f"{name} {system} x{k_runs[system]}")
            batch = Batch([build(system, scene) for _ in range(k_runs[system])])
            try:
                batch.step(1)  # excluded: the first step creates the contacts
                walls[system].append(timed(batch, steps - 1) / k_runs[system])
                poses[system] += [(x.positions, x.angles) for x in batch.runners]
            finally:
                for x in batch.runners:
                    x.close()
            progress.update()
    return walls, poses, k_runs


def run(config, args):
    names = tuple(s for s in config["scenarios"] if args.only is None or s in args.only)
    repeats = cli.or_default(args.repeats, config["repeats"])
    truth_dt = DT / config["truth_divisor"]
    compile_kernels()

    # untimed: the truth and every system's observed run, in parallel
    tasks = [(n, TRUTH_SYSTEM, truth_dt, config["truth_iterations"]) for n in names]
    tasks += [(n, s, DT, None) for n in names for s in SYSTEMS]
    tasks += [(n, s, DT, None) for n in names for s in systems.NO_PRESOLVE_SYSTEMS]
    store, header = sweep_store(NAME, args, config)
    results = dict(
        zip(
            [(t[0], t[1] if t[2] == DT else "truth") for t in tasks],
            run_tasks(observe, tasks, desc=f"{NAME} untimed runs", store=store, header=header),
        )
    )

    # timed: serial, interleaved
    timings = {}
    with tqdm(
        total=len(names) * len(SYSTEMS) * repeats, desc=f"{NAME} timed runs", unit="run"
    ) as bar:
        for n in names:
            timings[n] = time_scenario(n, SYSTEMS, repeats, config["repeat_s"], bar)

    rows = []
    for n in names:
        scenario = scenarios.get(n)
        scene = scenario.build()
        key = scenarios.key_bodies(scene)
        truth = results[(n, "truth")]
        walls, poses, k_runs = timings[n]
        medians = {s: statistics.median(walls[s]) for s in SYSTEMS}
        for system in SYSTEMS:
            obs, ref = results[(n, system)], results[(n, REFERENCE[system])]
            err_m, err_rad = pose_error(
                obs["positions"][key], obs["angles"][key], ref["positions"][key], ref["angles"][key]
            )
            err_all, _ = pose_error(
                obs["positions"], obs["angles"], ref["positions"], ref["angles"]
            )
            truth_err, _ = pose_error(
                obs["positions"][key],
                obs["angles"][key],
                truth["positions"][key],
                truth["angles"][key],
            )
            timed_diff = max(
                pose_error(p, a, obs["positions"], obs["angles"])[0] for p, a in poses[system]
            )
            without = _without_presolve(results, n, system, truth)
            rows.append(
                {
                    "scenario": n,
                    "system": system,
                    "reference": REFERENCE[system],
                    "bodies": len(scene.bodies),
                    "seconds": scenario.duration(scene),
                    "steps": obs["steps"],
                    "event_s": scenario.event_time(scene),
                    "expected": scenario.expected,
                    "truth": truth["outcome"],
                    "truth_is_expected": truth["outcome"] == scenario.expected,
                    "outcome": obs["outcome"],
                    "right": obs["outcome"] == truth["outcome"],
                    "changed": obs["outcome"] != ref["outcome"],
                    "engine_right": ref["outcome"] == truth["outcome"],
                    "measure_name": scenario.measure_name,
                    "measure": obs["measure"],
                    "truth_measure": truth["measure"],
                    "pose_error_m": err_m,
                    "pose_error_rad": err_rad,
                    "pose_error_all_m": err_all,
                    "truth_error_m": truth_err,
                    "frozen_fraction": obs["frozen_fraction"],
                    "key_ever_frozen": obs["key_ever_frozen"],
                    "asleep_at_event": obs["asleep_at_event"],
                    "wall_ms_median": 1e3 * medians[system],
                    "wall_ms_min": 1e3 * min(walls[system]),
                    "ms_per_step": 1e3 * medians[system] / (obs["steps"] - 1),
                    "speedup": medians[REFERENCE[system]] / medians[system],
                    "speedup_min": min(walls[REFERENCE[system]]) / min(walls[system]),
                    "repeats": repeats,
                    "runs_per_repeat": k_runs[system],
                    "timed_pose_diff_m": timed_diff,
                    **without,
                }
            )
    table = pd.DataFrame(rows)
    scenes = [scenarios.get(n).build() for n in names]
    parameters = {
        # the scenarios that ran (with --only, not the whole catalogue the configuration lists)
        "config": {**config, "scenarios": list(names)},
        "dt": DT,
        "systems": list(SYSTEMS),
        "reference": dict(REFERENCE),
        "repeats": repeats,
        "scenarios": {
            n: {
                "question": scenarios.get(n).question,
                "expected": scenarios.get(n).expected,
                "labels": list(scenarios.get(n).labels),
                "seconds": scenarios.get(n).seconds,
                "event_s": scenarios.get(n).event_s,
                "params": scenarios.get(n).params,
                "measure": scenarios.get(n).measure_name,
            }
            for n in names
        },
        "truth": {
            "system": TRUTH_SYSTEM,
            "dt": truth_dt,
            "iterations": config["truth_iterations"],
            "iterations_are": "biased sweeps per substep (sim solver v2)",
            "substeps": results[(names[0], "truth")]["settings"].get("substeps"),
            "settings": results[(names[0], "truth")]["settings"],
        },
        "event_lead_s": EVENT_LEAD_S,
        "without_presolve": {
            "systems": list(systems.NO_PRESOLVE_SYSTEMS),
            "settings": systems.NO_PRESOLVE_SETTINGS,
            "columns": list(_without_presolve({}, None, "pymunk", None)),
        },
        "system_settings": {s: results[(names[0], s)]["settings"] for s in SYSTEMS},
        "frozen_means": "the runner's asleep: sim World.frozen (out of the awake list); "
        "pymunk body.is_sleeping; pybullet velocities exactly 0 and pose unchanged",
    }
    return table, scenes, parameters


def _without_presolve(results, scenario, system, truth):
    """The no-presolve columns of a row: for a sim system, its variant's outcome, whether it
    differs from the outcome of "sim-off (no presolve)" (freezing changed it) and whether it is
    the truth's; None for a peer's (no presolve to leave out)."""
    columns = ("outcome_no_presolve", "changed_no_presolve", "right_no_presolve")
    if systems.engine_of(system) != "sim":
        return dict.fromkeys(columns)
    obs = results[(scenario, systems.no_presolve(system))]
    ref = results[(scenario, systems.no_presolve(REFERENCE[system]))]
    return dict(
        zip(
            columns,
            (
                obs["outcome"],
                obs["outcome"] != ref["outcome"],
                obs["outcome"] == truth["outcome"],
            ),
        )
    )


def scenario_names(text):
    """The argparse type of --only: comma-separated scenario names, each one known."""
    names = [s.strip() for s in text.split(",") if s.strip()]
    if not names:
        raise argparse.ArgumentTypeError(f"names no scenario: {text!r}")
    for s in names:
        try:
            scenarios.get(s)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None
    return tuple(dict.fromkeys(names))


def is_subset(config, args):
    """Whether --only leaves some of the catalogue out: then the run is not the table."""
    return args.only is not None and not set(config["scenarios"]) <= set(args.only)


def _extra_args(parser):
    parser.add_argument(
        "--repeats",
        type=cli.positive_int,
        default=None,
        help="timed repeats per system (default 7, quick 1)",
    )
    parser.add_argument(
        "--only",
        type=scenario_names,
        default=None,
        metavar="NAME[,NAME...]",
        help="run only these scenarios (default: all of them). Part of the catalogue is not the "
        "table: it is written to results/only/table_failures.csv (+ .json; --quick: "
        "results/quick/only/), never over the table in results/data/, and the stored runs of "
        "the other scenarios are kept for the whole table's next run",
    )


main = common.entry(
    NAME, __doc__, FULL, QUICK, run, extra_args=_extra_args, subset=is_subset, sweep=True
)

if __name__ == "__main__":
    main()
