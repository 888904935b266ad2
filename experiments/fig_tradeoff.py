"""Figure 7 "fig_tradeoff": the speed-accuracy trade of freezing, and its Pareto front per system,
beside the trade sim's own solver knobs make.

Question: how much faster does a whole run get under each freezing / sleeping system as its
threshold is made more eager, and what does that cost in accuracy, on top of the error the time
step already makes? And how does that compare with the trade a user makes with the solver itself
(sim's substeps and iterations, freezing off)? x = speed-up over the same engine with sleeping off
at its default settings and the same dt, y = error against a converged reference of that engine
with sleeping off (fine dt *and* many iterations, see "Reference").

Scenes (chosen so that freezing saves real time and the outcome is not chaotic: a pile of random
polygons diverges between any two dt, its pose error would measure chaos, not freezing):
- ``pyramid(10)``: 55 unit boxes placed at rest (sim.scenes.pyramid). Freezing can start at once;
  what it can cost is a structure held where it stands while the reference settles or creeps.
- ``landing``: a row of ``base`` unit boxes on the floor (gap 0.125 m as in the pyramid), above it
  ``layers`` rows of one box fewer each, every box centred over a gap of the row below, each row's
  bottom ``drop`` = 0.5 m above the top of the row below; beside them ``loners`` boxes that fall
  flat onto the floor from 0.5, 1.0, 1.5 m. Everything starts at rest and falls flat (no spin), so
  the contact sequence is the same at any dt: the rows land at 3.1 and 4.4 m/s, the loners at 3.1,
  4.4 and 5.4 m/s (impact impulses 3-5 N s on 1 kg boxes, across the paper's default threshold of
  1 N s). Full: base 8, 2 layers, 3 loners (24 bodies). The scene is mirror-symmetric and every
  landing flat, so the exact answer moves no box sideways; what an engine gets wrong here is how
  well it converges the impacts' contact impulses. Measured (solver v2, full size): without its
  impact sweeps (``impact_iterations=0``; sim.soft_step.IMPACT_SWEEP_SPEED) sim-off slid the
  pile's boxes up to 3.3 cm sideways during the landings (all leftwards-biased: the sweep order's
  asymmetry), and did *not* get better with a finer dt or more substeps (dt/8: 2.6 cm; 16
  substeps: 3.8 cm) but did with iterations (4 per substep: 6.5 mm; 8: 3.2 mm). With them (8 more
  sweeps with friction rows per substep, around each landing, in its steps) it ends 0.7 mm from
  the rest pose. Nothing slides once the pile is at rest.
Each run lasts ``duration_s`` = 5 s of simulated time (300 steps at dt 1/60): the landing is over
by ~1 s and Bullet needs its fixed 2 s of rest before a body sleeps.

Systems and sweeps (one table row per scene, system, parameter, value). Every grid is log-spaced
around the parameter's default (the default itself included), from "freezes almost nothing" to
"freezes too eagerly"; one parameter varies at a time, the others stay at their defaults:
- sim-paper ``impulse_threshold`` (N s, default 1.0; sim/freeze/paper.py): a floor-like contact
  whose collision impulse is below it "stays in contact" (the body is held, then frozen); above it
  the body bounces. Small = nothing is ever held, large = every landing is held at impact.
  Grid: default x 10^(k/2), k = -3..3 (0.032 .. 32 N s).
- sim-extended ``impact_speed`` (m/s, default 0.5; sim/freeze/extended.py): awake bodies' contact
  impulses on a frozen body that would set it moving faster than this wake it (impact). Large =
  impacts never wake. k = -3..3.
- sim-extended ``rest_speed`` (m/s, default 0.02): the rest test's speed |v| + |w| extent. Not in
  the issue's list, but it, not the impact speed, decides how eagerly extended freezes; without
  it the sweep would show extended's eager end only through waking. k = -7..3 (6.3 um/s .. 0.6
  m/s): its slow end must reach "freezes almost nothing", as the sleep timers' 5 s does. At k = -3
  (0.6 mm/s) extended still froze the landing at 4x: a box that landed is pushed out of its 0.15 mm
  overlap at under 0.2 mm/s, and only a slower rest speed waits for that (measured at 3cab659:
  k = -4, -5, -6, -7 gave 2.9x, 1.9x, 1.4x, 1.15x, moving bodies by 142, 37, 11, 3 um).
- sim-extended ``rest_acceleration`` (m/s^2, default 0.1): the rest test's steadiness gate, how
  much a slow body's velocity may still change over a step (|dv| + |dw| extent, per dt). On the
  landing it, not the speed, is what holds extended back once the boxes are slow: their impulses
  still change while the soft contacts settle, and the rest speed's sweep saturates at the
  default's 5.3x. k = -3..3 (3.2 mm/s^2 .. 3.2 m/s^2). Measured on the full landing (fde8011,
  awake fraction / freezing's own error): 0.0032 -> 0.23 / 0.19 mm, 0.1 -> 0.125 / 0.55 mm, 1.0
  -> 0.070 / 0.79 mm, 3.2 -> 0.064 / 1.09 mm; the certificate still refuses every body not held,
  so a looser gate freezes the landed boxes sooner, never one in the air.
- sim-sleep ``sleep_speed`` (m/s, default 0.05) and ``sleep_time`` (s, default 0.5;
  sim/freeze/sleep.py): a body is idle under the speed, an island sleeps when all its bodies were
  idle for the time. sleep_speed k = -3..3; sleep_time k = -3..2 (0.016 s = one step .. 5 s = the
  whole run, which freezes nothing).
- pymunk-sleep ``sleep_time`` (s, default 0.5, the runner's; Chipmunk's own default is infinity)
  and ``idle_speed`` (m/s; default |g| dt = 0.1635 m/s, Chipmunk's rule when left unset; the
  default row leaves it unset, the others set it). Same grids as sim-sleep.
- pybullet-sleep ``sleep_threshold`` ((m/s)^2 + (rad/s)^2, a sum of squared joint velocities;
  default 0.05; study/peers/pybullet_runner.py; the 2 s deactivation time is fixed in
  Bullet). A squared speed, so the grid steps by whole decades: default x 10^k, k = -3..2
  (speeds 7 mm/s .. 2.2 m/s).
- box2d-sleep at its default only (``time_to_sleep`` 0.5 s, a row that sets nothing): Box2D 2.3's
  sleep tolerances (b2_timeToSleep, b2_linearSleepTolerance 0.01 m/s, b2_angularSleepTolerance 2
  deg/s) are compiled into the binding, so there is nothing to sweep; its one point still sits on
  the same axes as every other system's front.
- sim-off, pymunk, pybullet, box2d at dt 1/60 and their default settings: the baseline (speed-up 1
  by definition; its error is the time step's and the default iterations' own).
- sim-off's solver knobs (role "solver"), freezing off, one at a time, the others at their
  defaults: ``substeps`` per step (default 4, sim.World's) x 2^k, k = -2..2 (1 .. 16 substeps),
  ``iterations`` (biased sweeps per substep; default 1, what the runners give sim) x 2^k,
  k = 0..3 (1 .. 8), and ``impact_iterations`` (more biased sweeps, with friction rows, per
  substep of a step with a landing, for the contacts around it; default 8) x 2^k, k = -3..1
  (1 .. 16); relax sweeps stay at 1 per substep. Cost grows about linearly with
  substeps x (iterations + 1), plus the impact sweeps in the steps that have them. Timed and
  measured exactly as the freezing settings (speed-up over sim-off at its defaults, error
  against sim's reference), so both trades share the axes.
Settings: each engine at its own defaults (study.peers.DEFAULT_ITERATIONS): sim's soft step
with 4 substeps and 1 biased + 1 relax sweep per substep; pymunk 10 iterations per step; pybullet
50 per step; Box2D 8 velocity and 3 position iterations per step. Sim slop and pymunk
collision_slop 0.005 m (study.common). Every run's full
settings (``runner.settings``) are in the metadata's ``system_settings``.

Reference per engine: the same engine with sleeping off at dt / ``fine`` (fine = 8: dt 1/480 s,
2400 steps) *and* ``reference_iterations`` (sim 16 biased and ``reference_relax_iterations`` 64
relax sweeps per substep at its default 4 substeps; pymunk 40, pybullet 200 and Box2D 32 velocity
iterations per step: 4x their defaults; Box2D's 3 position iterations stay). A fine dt alone is
not a reference for sim: its landing converges with sweeps, not with the step, and its friction is
solved only in the relax sweeps and a landing's impact sweeps (measured on the full landing at
238f82e, before the impact sweeps, at dt/8 with 16 biased
sweeps: 4 relax sweeps instead of 1 moved boxes by up to 9.6 mm, 32 biased sweeps instead of 16 by
1.4 mm, dt/16 by 1.7 mm; see ``reference_settings`` for the relax sweeps' convergence). The
peers' references were iteration-bound too, less so: pymunk at dt/8 with 10 iterations moved
boxes 5.8 mm sideways (0.02 mm with 40), pybullet at dt/8 with 50 by 0.6 mm (0.001 mm with 200).
Its own resolution is measured too: the same engine at dt / (fine / 2) with half the reference
iterations against it (row role "resolution"); an error below that is within the reference's
uncertainty. The reference is finer than every setting judged against it (sim: 8x finer step and
2x the largest swept iterations; checked at start-up).

Errors (every system measured by the same code, never by an engine's own contact report;
the code is study.tradeoff's, as are the scenes and the timed runs):
- pose error of the final state against the reference: largest and mean distance between centres
  of mass (m) and largest angle difference (rad, modulo 2 pi) over all bodies;
- the same largest distance and angle against the *exact* final pose (``rest_pose``: the pyramid
  stays where it was placed; on the landing no box moves sideways or turns and each rests on the
  row below), columns ``exact_error_max_m``, ``exact_angle_error_max_rad``. It needs no engine's
  reference, so it also holds where a reference has not converged (its resolution row says so),
  and it is the same yardstick for every engine. The reference rows have it too;
- freezing's own error, ``freeze_error_max_m`` and ``freeze_angle_error_max_rad``: the largest
  distance and angle between the final pose under a freezing setting and the final pose of the
  same engine with sleeping off at the same dt and default settings (the baseline run; 0 for the
  baseline itself; NaN for the solver rows, which freeze nothing). The pose error against the
  reference is that engine's solver error plus what freezing adds; this column is what freezing
  adds alone, so that "what freezing costs" is not confounded with "whose solver is more
  accurate";
- penetration: the deepest overlap between two bodies, or between a body and the floor (or a static
  body), from positions, angles and the scene's polygons (separating-axis test on the convex
  polygons: the overlap is the smallest push along any edge normal of either polygon that
  separates them; ``deepest_overlap``). Measured on the pose after every step at dt (the
  reference: every ``fine`` steps, at the same times) and reported as the largest over the run and
  at the end. A resting contact overlaps by up to the slop (0.005 m) in pymunk, ~1e-5 m in Bullet
  and in sim solver v2 (its contacts carry their load rigidly); the reference's value is in its
  row. The largest over the run is set by the impacts themselves, the same under every freezing
  setting: in pymunk and Bullet a box landing at v sinks up to v dt into what it hits before the
  engine sees the contact (1.8-3 cm at dt 1/60); sim's speculative contacts reach the distance a
  pair closes in one step (relative speed x dt) ahead, so it sees the contact before impact and
  sinks under a millimetre. What freezing changes is the overlap left at the end: a body frozen
  before the solver has pushed it back out keeps its overlap (the figure draws that one).
These accuracy runs are untimed and independent: they go through study.executor.run_tasks
(a process pool). Each also records the mean fraction of bodies awake over the run, the awake
count at the end and the first time every body was asleep.

Speed-up: wall time of the whole run (build excluded; the first step excluded, as every timing of
the study; steps 2..300 timed in one ``runner.step`` call with the garbage collector paused)
under the setting, divided into that of the same engine with sleeping off at its default
settings and the same dt (for sim: sim-off at 4 substeps, 1 sweep per substep).
Kernels are compiled first (common.compile_kernels). Each repeat builds a fresh runner per setting;
within an engine the settings run round-robin in one process (order reversed every other repeat),
repeats: sim 15, pymunk 15, pybullet 5, box2d 15 (a sim or pymunk run lasts 2-40 ms, so a single
preemption by another process on this shared 2-core machine can triple one repeat: seen in a
5-repeat trial, where settings doing identical work differed 3x in median; a pybullet run of
pyramid(10) lasts ~1.5 s and averages such bursts out). Reported: median and min over repeats and
every repeat's time (``wall_s_all``), speed-up of medians (and of minima). Timed runs are serial,
after every untimed run has finished (the pool must not compete with them). The final pose of the
last timed repeat is compared with the accuracy run's (``replay_difference_m``): the engines are
deterministic, so the errors describe exactly the runs that were timed.

Columns: scene, bodies, system, engine, role (baseline | sweep | solver | reference | resolution),
parameter, value, unit, is_default, dt_s, steps, repeats, wall_s_median, wall_s_min,
wall_s_all (every repeat, s, space-separated), off_wall_s_median, speedup, speedup_min,
n_awake_final, awake_fraction, all_asleep_at_s,
pose_error_max_m, pose_error_mean_m, angle_error_max_rad, exact_error_max_m,
exact_angle_error_max_rad, freeze_error_max_m, freeze_angle_error_max_rad, penetration_max_m,
penetration_final_m, replay_difference_m (reference
and resolution rows: parameter "iterations", value the iterations they ran).

    python -m experiments.fig_tradeoff [--quick]
writes results/data/fig_tradeoff.csv and fig_tradeoff.json. --quick: pyramid(4) and a landing of
4 + 3 boxes and 1 loner, 2.5 s, references at dt/4 (resolution dt/2; the same reference
iterations), every other grid point (substeps 1, 4, 16; iterations 1, 4).
"""

import inspect
import math
import statistics

import numpy as np
import pandas as pd
from tqdm import tqdm

import sim
from study import common
from study.common import DT, SLOP, compile_kernels, sweep_store
from study.executor import run_tasks
from study import systems
from study.peers import DEFAULT_ITERATIONS, engine_of
from study.peers.box2d_runner import BOX2D_SLEEP
from study.peers.pybullet_runner import DEFAULT_SLEEP_THRESHOLD
from study.peers.pymunk_runner import DEFAULT_SLEEP_TIME as PYMUNK_SLEEP_TIME
from study.tradeoff import (
    COLUMNS,
    accuracy_run,
    error_row,
    grid,
    make_scene,
    rest_pose,
    scene_tag,
    solver_grid,
    timed_runs,
)

NAME = "fig_tradeoff"
G = 9.81  # m/s^2, |gravity| of every scene here

#: the sleeping-off system of each engine (the speed-up's denominator and the reference)
OFF = dict(systems.OFF)
ENGINES = tuple(OFF)

#: sim-off's solver defaults, as the baseline runs them: substeps are sim.World's own, iterations
#: (biased sweeps per substep) what the runners give sim when none are asked for
SIM_SUBSTEPS = inspect.signature(sim.World).parameters["substeps"].default
SIM_IMPACT_ITERATIONS = inspect.signature(sim.World).parameters["impact_iterations"].default
SIM_ITERATIONS = DEFAULT_ITERATIONS["sim"]
#: (system, parameter, unit, default, log10 step of the grid, exponents k: value = default *
#: 10^(k * step)). Defaults are read from the code that defines them.
SWEEPS = (
    (
        "sim-paper",
        "impulse_threshold",
        "N s",
        sim.freeze.paper.PARAMETERS["impulse_threshold"],
        0.5,
        range(-3, 4),
    ),
    (
        "sim-extended",
        "impact_speed",
        "m/s",
        sim.freeze.extended.PARAMETERS["impact_speed"],
        0.5,
        range(-3, 4),
    ),
    (
        "sim-extended",
        "rest_speed",
        "m/s",
        sim.freeze.extended.PARAMETERS["rest_speed"],
        0.5,
        range(-7, 4),
    ),
    (
        "sim-extended",
        "rest_acceleration",
        "m/s^2",
        sim.freeze.extended.PARAMETERS["rest_acceleration"],
        0.5,
        range(-3, 4),
    ),
    (
        "sim-sleep",
        "sleep_speed",
        "m/s",
        sim.freeze.sleep.PARAMETERS["sleep_speed"],
        0.5,
        range(-3, 4),
    ),
    ("sim-sleep", "sleep_time", "s", sim.freeze.sleep.PARAMETERS["sleep_time"], 0.5, range(-3, 3)),
    ("pymunk-sleep", "sleep_time", "s", PYMUNK_SLEEP_TIME, 0.5, range(-3, 3)),
    # Chipmunk's rule when idle_speed is unset: |g| dt (cpSpaceProcessComponents)
    ("pymunk-sleep", "idle_speed", "m/s", G * DT, 0.5, range(-3, 4)),
    ("pybullet-sleep", "sleep_threshold", "(m/s)^2", DEFAULT_SLEEP_THRESHOLD, 1.0, range(-3, 3)),
    # Box2D 2.3's sleep tolerances are compile-time constants (b2Settings.h): its default alone
    ("box2d-sleep", "time_to_sleep", "s", BOX2D_SLEEP["b2_timeToSleep"], 0.5, range(0, 1)),
)
#: settings whose default row leaves the parameter unset (the engine's own rule applies)
UNSET_AT_DEFAULT = {("pymunk-sleep", "idle_speed"), ("box2d-sleep", "time_to_sleep")}
#: sim-off's solver knobs, freezing off (role "solver"): (system, parameter, unit, default,
#: exponents k: value = default * 2^k, whole numbers). One varies at a time.
SOLVER_SWEEPS = (
    ("sim-off", "substeps", "per step", SIM_SUBSTEPS, range(-2, 3)),
    ("sim-off", "iterations", "per substep", SIM_ITERATIONS, range(0, 4)),
    ("sim-off", "impact_iterations", "per substep", SIM_IMPACT_ITERATIONS, range(-3, 2)),
)

FULL = {
    "scenes": (("pyramid", {"base": 10}), ("landing", {"base": 8, "layers": 2, "loners": 3})),
    "duration_s": 5.0,
    "fine": 8,  # reference dt = DT / fine; resolution run at DT / (fine/2)
    # the references' iterations (sim: biased sweeps per substep; the peers: per step); the
    # resolution runs use half (see the docstring for the convergence measured)
    "reference_iterations": {"sim": 16, "pymunk": 40, "pybullet": 200, "box2d": 32},
    "reference_relax_iterations": 64,  # sim's relax sweeps per substep (see reference_settings)
    "every_other_grid_point": False,
    "repeats": {"sim": 15, "pymunk": 15, "pybullet": 5, "box2d": 15},
}
QUICK = {
    "scenes": (("pyramid", {"base": 4}), ("landing", {"base": 4, "layers": 1, "loners": 1})),
    "duration_s": 2.5,
    "fine": 4,
    "reference_iterations": {"sim": 16, "pymunk": 40, "pybullet": 200, "box2d": 32},
    "reference_relax_iterations": 64,  # sim's relax sweeps per substep (see reference_settings)
    "every_other_grid_point": True,  # k = -2, 0, 2 only
    "repeats": {"sim": 3, "pymunk": 3, "pybullet": 3, "box2d": 3},
}
ERROR_FLOOR = 1e-9  # m or rad; analysis draws smaller errors (round-off) at this value


# ---- the settings swept -------------------------------------------------------------------------


def _grid_points(exponents, config):
    return (
        [k for k in exponents if k % 2 == 0]
        if config["every_other_grid_point"]
        else list(exponents)
    )


def settings_of(config):
    """Every (system, parameter, unit, value, is_default, role) to time and measure, per engine,
    the sleeping-off baseline first, then the freezing sweeps ("sweep"), then sim-off's solver
    knobs ("solver")."""
    out = {e: [(OFF[e], "none", "", math.nan, True, "baseline")] for e in ENGINES}
    for system, parameter, unit, default, step, exponents in SWEEPS:
        ks = _grid_points(exponents, config)
        for k, value in zip(ks, grid(default, step, ks)):
            out[engine_of(system)].append((system, parameter, unit, value, k == 0, "sweep"))
    for system, parameter, unit, default, exponents in SOLVER_SWEEPS:
        ks = _grid_points(exponents, config)
        for k, value in zip(ks, solver_grid(default, ks)):
            out[engine_of(system)].append((system, parameter, unit, value, k == 0, "solver"))
    return out


def reference_settings(engine, config, role):
    """The runner settings of ``engine``'s reference ("reference") or of the run that measures its
    resolution ("resolution": half the iterations).

    sim's reference converges its relax sweeps (``reference_relax_iterations``) as well as its
    biased ones: friction is solved only in the relax sweeps (and a landing's impact sweeps), and
    with one relax sweep per substep the reference was not converged. Measured on the full landing
    at dt/8 (238f82e, before the impact sweeps; with them the reference is 0.20 mm from the exact
    pose, 0.31 mm before): with 16 biased
    sweeps, 4 relax sweeps instead of 1 moved boxes by up to 9.6 mm; against 64 biased and 64
    relax sweeps, 16 and 64 is 0.35 mm off, 64 and 16 4.4 mm, 16 and 16 4.5 mm, 32 and 32
    0.75 mm: the relax sweeps are what converges it."""
    iterations = int(config["reference_iterations"][engine])
    half = role != "reference"
    n = max(1, iterations // 2) if half else iterations
    if engine == "sim":
        relax = int(config["reference_relax_iterations"])
        return {"iterations": n, "relax_iterations": max(1, relax // 2) if half else relax}
    return {"iterations": n}


def check_reference(config):
    """ValueError unless sim's reference is finer than every solver setting swept: a finer step
    (fine >= 2) and more sweeps per substep than the most swept."""
    swept = max(
        solver_grid(d, _grid_points(ex, config))
        for _, p, _, d, ex in SOLVER_SWEEPS
        if p == "iterations"
    )
    ref = reference_settings("sim", config, "reference")["iterations"]
    if ref <= max(swept) or config["fine"] < 2:
        raise ValueError(
            f"sim's reference ({ref} sweeps per substep at dt/{config['fine']}) must "
            f"be finer than every swept setting (up to {max(swept)} sweeps)"
        )


def runner_settings(system, parameter, value, is_default):
    if parameter == "none" or (is_default and (system, parameter) in UNSET_AT_DEFAULT):
        return {}
    if parameter in ("substeps", "iterations", "impact_iterations"):
        return {parameter: int(value)}
    return {parameter: value}


def run(config, args):
    compile_kernels()
    steps = int(round(config["duration_s"] / DT))
    fine = int(config["fine"])
    if fine < 2 or fine % 2:
        raise ValueError(f"fine must be an even integer >= 2, got {fine}")
    check_reference(config)
    per_engine = settings_of(config)
    scenes = [make_scene(name, params) for name, params in config["scenes"]]

    # 1. untimed accuracy runs (the pool), before any timing
    tasks, keys = [], []
    for (name, params), scene in zip(config["scenes"], scenes):
        base = {"scene": name, "scene_params": params}
        for engine in ENGINES:
            for role, div in (("reference", fine), ("resolution", fine // 2)):
                tasks.append(
                    {
                        **base,
                        "system": OFF[engine],
                        "dt": DT / div,
                        "settings": reference_settings(engine, config, role),
                        "sample_every": div,
                        "samples": steps,
                    }
                )
                keys.append((scene_tag(scene), engine, role, None))
            for k, (system, parameter, _, value, is_default, _) in enumerate(per_engine[engine]):
                tasks.append(
                    {
                        **base,
                        "system": system,
                        "dt": DT,
                        "settings": runner_settings(system, parameter, value, is_default),
                        "sample_every": 1,
                        "samples": steps,
                    }
                )
                keys.append((scene_tag(scene), engine, "setting", k))
    store, header = sweep_store(NAME, args, config)
    key_of = {id(t): repr(k) for t, k in zip(tasks, keys)}
    results = dict(
        zip(
            keys,
            run_tasks(
                accuracy_run,
                tasks,
                desc=f"{NAME} accuracy runs",
                store=store,
                header=header,
                key=lambda t: key_of[id(t)],
            ),
        )
    )

    # 2. timed runs, serial, one engine at a time, settings interleaved
    total = sum(len(per_engine[e]) * config["repeats"][e] for e in ENGINES) * len(scenes)
    timings = {}
    with tqdm(total=total, desc=f"{NAME} timed runs", unit="run") as bar:
        for scene in scenes:
            for engine in ENGINES:
                runs = [
                    (system, runner_settings(system, parameter, value, is_default), parameter)
                    for system, parameter, _, value, is_default, _ in per_engine[engine]
                ]
                timings[scene_tag(scene), engine] = timed_runs(
                    scene, runs, steps, config["repeats"][engine], bar
                )

    # 3. the table
    rows = []
    for scene in scenes:
        tag = scene_tag(scene)
        exact = rest_pose(scene)
        for engine in ENGINES:
            ref = results[tag, engine, "reference", None]
            times, final = timings[tag, engine]
            off_median = statistics.median(times[0])
            off_min = min(times[0])
            for role, div in (("reference", fine), ("resolution", fine // 2)):
                res = results[tag, engine, role, None]
                rows.append(
                    error_row(
                        tag,
                        scene,
                        system=OFF[engine],
                        engine=engine,
                        role=role,
                        parameter="iterations",
                        unit=ITERATIONS_UNIT[engine],
                        value=reference_settings(engine, config, role)["iterations"],
                        is_default=False,
                        dt=DT / div,
                        steps=steps * div,
                        res=res,
                        ref=ref,
                        exact=exact,
                    )
                )
            for k, (system, parameter, unit, value, is_default, role) in enumerate(
                per_engine[engine]
            ):
                res = results[tag, engine, "setting", k]
                row = error_row(
                    tag,
                    scene,
                    system=system,
                    engine=engine,
                    role=role,
                    parameter=parameter,
                    unit=unit,
                    value=value,
                    is_default=is_default,
                    dt=DT,
                    steps=steps,
                    res=res,
                    ref=ref,
                    exact=exact,
                    off=results[tag, engine, "setting", 0] if role != "solver" else None,
                )
                med, low = statistics.median(times[k]), min(times[k])
                end_pose, end_awake = final[k]
                row.update(
                    repeats=len(times[k]),
                    wall_s_median=med,
                    wall_s_min=low,
                    wall_s_all=" ".join(f"{t:.6g}" for t in times[k]),
                    off_wall_s_median=off_median,
                    speedup=off_median / med,
                    speedup_min=off_min / low,
                    replay_difference_m=float(np.abs(end_pose - res["positions"]).max()),
                )
                if end_awake != res["n_awake_final"]:
                    raise RuntimeError(
                        f"{tag} {system} {parameter}={value}: the timed run ended "
                        f"with {end_awake} awake, the accuracy run with "
                        f"{res['n_awake_final']}: runs are not reproducible"
                    )
                rows.append(row)
    table = pd.DataFrame(rows, columns=COLUMNS)

    system_settings = {}
    for engine in ENGINES:
        for role in ("reference", "resolution"):
            res = results[scene_tag(scenes[0]), engine, role, None]
            system_settings[f"{OFF[engine]} {role}"] = res["settings"]
        for k, (system, parameter, _, value, is_default, role) in enumerate(per_engine[engine]):
            if is_default:
                system_settings.setdefault(
                    system, results[scene_tag(scenes[0]), engine, "setting", k]["settings"]
                )
            elif role == "solver":
                system_settings[f"{system} {parameter}={int(value)}"] = results[
                    scene_tag(scenes[0]), engine, "setting", k
                ]["settings"]
    parameters = {
        "dt": DT,
        "slop": SLOP,
        "duration_s": config["duration_s"],
        "steps": steps,
        "reference_dt": DT / fine,
        "resolution_dt": DT / (fine // 2),
        "reference_iterations": {
            e: reference_settings(e, config, "reference")["iterations"] for e in ENGINES
        },
        "resolution_iterations": {
            e: reference_settings(e, config, "resolution")["iterations"] for e in ENGINES
        },
        "reference_settings": {e: reference_settings(e, config, "reference") for e in ENGINES},
        "iterations_unit": dict(ITERATIONS_UNIT),
        "iterations": dict(DEFAULT_ITERATIONS),
        "error_floor": ERROR_FLOOR,
        "sim_defaults": {
            "substeps": SIM_SUBSTEPS,
            "iterations": SIM_ITERATIONS,
            "relax_iterations": inspect.signature(sim.World).parameters["relax_iterations"].default,
        },
        "sweeps": [
            {
                "system": s,
                "parameter": p,
                "unit": u,
                "default": d,
                "grid_log10_step": st,
                "exponents": list(ex),
            }
            for s, p, u, d, st, ex in SWEEPS
        ],
        "solver_sweeps": [
            {
                "system": s,
                "parameter": p,
                "unit": u,
                "default": d,
                "grid": "default * 2^k",
                "exponents": list(ex),
                "values": solver_grid(d, _grid_points(ex, config)),
            }
            for s, p, u, d, ex in SOLVER_SWEEPS
        ],
        "unset_at_default": sorted(f"{s}:{p}" for s, p in UNSET_AT_DEFAULT),
        "timing": "build excluded, first step excluded, steps 2..N in one call with GC paused; "
        "settings of one engine round-robin, order reversed every other repeat; "
        "speedup = median(off) / median(setting)",
        "penetration": "deepest_overlap: SAT on the scene's polygons at every sampled pose",
        "system_settings": system_settings,
    }
    return table, scenes, parameters


#: what an engine's iteration count counts
ITERATIONS_UNIT = {
    "sim": "per substep",
    "pymunk": "per step",
    "pybullet": "per step",
    "box2d": "velocity, per step",
}


main = common.entry(NAME, __doc__, FULL, QUICK, run, sweep=True)

if __name__ == "__main__":
    main()
