"""Table "table_extremes" (figure "fig_extremes"): numerical stability at the extremes.

Question: where does each system (sim under every freeze policy, pymunk and pybullet with sleeping
off and on) stop giving a usable answer when one thing at a time is pushed to an extreme, and is
freezing ever the thing that breaks it? Every run is marked stable / degraded / failed / rejected
/ not run by the rules below; the figure is a grid of those marks, rows = (axis, value), columns =
systems.

Axes (each row one value; values listed from benign to extreme; every scene starts at rest with
its bodies exactly touching unless said otherwise; unit boxes, density 1 kg/m^2, friction 0.6):
- ``mass_heavy_on_light`` / ``mass_light_on_heavy``: a column of 3 unit boxes whose top box is
  m_top/m_below = 1, 10, 100, 1000 (resp. 1, 1/10, 1/100, 1/1000) times as heavy as the two below
  (its density scaled). 3 s.
- ``mass_dropped``: the heavy-on-light column *dropped* (each box DROP_GAP = 0.1 m above the one
  below, as the ``dt`` axis's column), m_top/m_below = 1, 10, 100, 1000: the solver must build the
  column and then carry the load, with no presolved start to lean on (see ``dt``). Judged against
  the stacked pose. 3 s.
- ``size_small`` / ``size_large``: a column of 3 square boxes of side 1, 0.1, 0.01 m and, past the
  issue's 1 cm, 1 mm and 0.1 mm; resp. 1, 10, 100 m. Same gravity (9.81 m/s^2) and the same
  solver settings passed to every size (sim's slop 5 mm and speculative distance 2 cm as caps;
  pymunk's collision_slop matched to the scene's smallest body, ``study.common.comparable_slop``:
  0.5 mm at 0.1 m, 0.05 mm at 1 cm; each scene's in the metadata's ``scenes``); sim scales its
  tolerances down with the smaller body's size (``sim.tolerances``), and refuses a body too
  small for its step with a ValueError naming the substeps (or dt) that would resolve it: at dt
  1/60 s and 4 substeps, 1 mm boxes need substeps >= 11 and 0.1 mm boxes >= 34, so both are
  refused ("rejected" cells, not failures). 3 s.
- ``plank_flat``: a plank 2 m long and 2/a m thick (aspect a = 1, 3, 10, 30, 100; mass held at
  1 kg by its density, so only the shape changes) lying centred across a unit box. 3 s.
- ``plank_upright``: a plank 1 m tall and 1/a m wide (a = 1, 3, 10, 30, 100) standing on its end
  on the floor (stable: it tips only past atan(1/a)). 3 s.
- ``polygon_vertices``: a regular n-gon (n = 3, 4, 8, 16, 32, 64; circumradius 0.5 m) resting on
  its flat bottom edge on a unit box. 3 s.
- ``collinear``: a unit box whose bottom edge has a fifth vertex eps below its midpoint (eps = 1e-2,
  1e-4, 1e-6, 1e-9 m: nearly collinear edges, and the box starts balanced on that vertex, able to
  rock by 2 eps rad onto either half), with a unit box resting on it. 3 s.
- ``projectile_stack``: a 0.2 m box projectile (density 1) fired horizontally at 10, 30, 100,
  200 m/s into the middle of box 2 of a 5-box column. It starts v T m away (T = 2.5 s + half a
  step of 1/60 s: at dt 1/60 it is then half a step's travel short of touching at the end of a
  step, not exactly touching, a lucky phase that would hide tunnelling) on a ballistic arc that
  returns to the aim height at t = T (vertical speed g T / 2), so every system has had 2.5 s to
  freeze the column before it arrives (Bullet needs its fixed 2 s); the fraction of the column
  asleep just before arrival is recorded. sim sweeps fast bodies against static and frozen ones
  (continuous collision, ``sim.continuous``) and makes contacts ahead of fast approaching pairs;
  pymunk has no continuous collision and pybullet's (swept-sphere CCD) is not switched on by its
  runner. 3 s.
- ``projectile_wall``: the same projectile at a static wall 5 cm thick and 4 m tall. 3 s.
- ``dt``: a *dropped* column of 10 unit boxes, each starting 0.1 m above the one below (the lowest
  0.1 m above the floor): they fall together and land one on another, the lowest at ~1.4 m/s and
  the top one, having fallen 1 m in all, at ~4.4 m/s, so the solver builds the column rather than
  being handed it in equilibrium (sim solves a scene placed at rest to convergence before its
  first step, ``initial_iterations``: a placed column stands in sim at any dt, which would measure
  that presolve, not the step). Judged against the stacked pose. dt = 1/480 .. 1/15 s (every other
  axis runs at 1/60 s). 5 s.
- ``iterations``: the same dropped column with 50, 20, 10, 5, 2, 1 iterations of each engine's own
  solver setting (elsewhere each engine's default, study.peers.DEFAULT_ITERATIONS). The
  numbers are not the same work: pymunk and pybullet do that many sweeps per step; sim does that
  many biased sweeps *per substep*, at its default 4 substeps (plus 1 relaxing sweep per substep),
  so its value 1, the axis's extreme, is sim's default and does 4 biased sweeps per step. The
  ``iterations`` and ``substeps`` columns of each row say exactly what ran. 5 s.
- ``substeps`` (sim only: the knob soft step trades for accuracy, Box2D v3's; pymunk and pybullet
  have none, their nearest knob is the ``dt`` axis): the same dropped column at 16, 8, 4, 2, 1
  substeps per step of 1/60 s, 1 iteration per substep. No peer row (not applicable, rather than
  "not run"), and no "breaks first" is drawn from it (nothing to compare with). 5 s.
- ``stack_height``: a column of 10, 20, 50 unit boxes placed at rest (sim starts it in
  equilibrium, see ``dt``; the peers do not: see the no-presolve systems below). 5 s.
- ``pyramid_base``: sim.scenes.pyramid(base) for base 10, 20, 40, 60 (55 .. 1830 bodies). 5 s.
- ``bodies``: 10^4 bodies as 2000 five-box columns 1.5 m apart. 2 s.
- ``long_run``: a 3-box column for 10^5 steps (1667 s at 1/60): drift and energy over a long rest.
- ``impact_threshold``: a 0.5 m box (density 0.3: 0.075 kg) "hammer" HAMMER_GAP = 2 m above a
  unit-box "anvil" on the floor, thrown down at v0 = v* (1 + d), d = -1e-3, -1e-6, +1e-6, +1e-3.
  v* is found by bisection (45 halvings of [0, 20] m/s: ~1e-13 relative; through the executor) as
  the v0 at which the policy's impulse test flips: under sim-paper, whether the hammer is held on
  landing on the anvil's (rotation-stable, floor-like) top edge or bounces (impulse_threshold
  1 N s); under sim-extended, whether the impact wakes the frozen anvil (impact_speed
  0.5 m/s: the impulse over the anvil's mass). The other systems have no such test: they get
  sim-paper's v*. The question is whether a decision on a knife's edge makes states chatter. 2 s.
- ``knife_edge``: a unit box balanced on one corner with its centre of mass offset from exactly
  above the corner by a tilt of 1e-3, 1e-6, 1e-9 and 0 rad (0 = exact balance, an unstable
  equilibrium that only round-off breaks; with an offset the box must fall to that side: a tilt
  grows as cosh(3.2 t) here, from 1e-9 rad it falls in ~7 s). 10 s.

Systems: sim-off, sim-sleep, sim-paper, sim-extended (default policy parameters), pymunk,
pymunk-sleep, pybullet, pybullet-sleep, box2d, box2d-sleep (study.common.SYSTEMS; sim slop 5 mm
as a cap, pymunk's collision_slop matched to each scene; each engine's default iterations, sim's
default substeps), plus, on the
placed axes only (PLACED_AXES: the scenes that start with bodies resting on one another, where
sim's presolve puts them in equilibrium before step 1: mass_heavy_on_light, mass_light_on_heavy,
size_small, size_large, plank_flat, plank_upright, polygon_vertices, collinear, projectile_stack,
stack_height, pyramid_base, bodies, long_run), the four sim systems again with the presolve off
(``World(initial_iterations=0)``), named "sim-off (no presolve)" etc. (NO_PRESOLVE_SYSTEMS). The
peers have no presolve: an advantage only sim has is reported separately, so that sim without it
can be compared with them like for like (the analysis does both). Not placed, so not repeated: the
dropped columns (``dt``, ``iterations``, ``substeps``, ``mass_dropped``: nothing touches at the
start), the projectile into a wall (likewise), and the impact and knife-edge scenes (one body on
the floor by a face or a corner: the presolve only sets the first step's floor impulse).

pybullet is not run on scenes of more than ``pybullet_max_bodies`` = 2000 bodies (the 10^4 bodies of
the "bodies" axis): measured on this machine (2026-12-07), a pybullet step of pyramid(20) costs 13
ms, of pyramid(40) 62 ms, of pyramid(60) 0.15 s at the start (more as it collapses: its run reached
``budget_s`` at step 240 of 300 and is marked "not run", timeout), of the 10^4 boxes in columns 1.3
s, whose 120 steps would pass ``budget_s``; those cells are marked "not run" with the reason, never
dropped. (Until 2026-12-07 the cap was 250 bodies, from costs of 0.68 s and 5.3 s a step quoted for
pyramid(40) and (60) that were ten times too high: pybullet had no cells there.) Any run is stopped
after ``budget_s`` s of wall time and marked "not run" (timeout; see the rules for what its
reason says and when it is failed instead).

Reference (for the outcome): the same scene under sim-off at dt_ref = min(dt, 1/60) / ``fine``
(fine = 8; 32 for the projectiles, so that a 200 m/s projectile moves 0.1 m per step, less than
the 0.25 m it needs to cross the wall: the reference cannot tunnel even without the continuous
collision that the runs test) with sim's default REF_SUBSTEPS = 4 substeps and REF_ITERATIONS = 1
biased sweep per substep, presolve on, for the same simulated time; one run per distinct scene,
shared by all systems (and by the no-presolve runs: the reference is the best estimate of what the
scene does, and a scene placed at rest starts in equilibrium). Why: in soft step the substep is
the accuracy knob (a substep re-integrates positions and re-solves every contact from the new
separation; an extra iteration only re-sweeps the same linearisation), so a reference 8x finer in
dt is 8x the runs' substeps: 32 per 1/60 s. The old reference's 40 iterations were per *step* of a
solver without substeps; 40 per substep at dt/8 would be 1280 biased sweeps per 1/60 s, which is
not what was meant, and costs for nothing: checked when chosen, 4x the substeps (16), 4x finer dt
(fine 32) or 40 iterations per substep leave the outcome of every scene tried unchanged (dropped
10-box column, placed and dropped 1000:1 stacks, 100:1 dropped stack, knife edge 1e-6 rad, upright
plank 100:1; final poses within 3 cm, 8 cm for the dropped 1000:1 stack). A scene sim refuses at
that step (a body too small for it, e.g. 0.1 mm boxes at dt 1/480 s) gets its reference with the
substeps doubled until the World accepts it (the reference's ``substeps`` are in the metadata).
Shortcuts, both stated: the 10^4-body scene's reference is one five-box column (its columns never
touch: identical, independent systems), and the long run's reference lasts 60 s of simulated time
(a column placed at rest stands or falls within seconds; what the long run is about, drift and
energy over 10^5 steps, is measured in the run itself).

Measured in every run (from each system's own observables, by the same code for all; sampled
after every step for the projectile, impact and knife-edge scenes, else at ~``samples`` = 200
evenly spaced steps, fewer for big scenes: at most ``sample_budget`` = 20000 body-samples per run
and at least 10 samples, so a 10^4-body run is sampled 10 times and its penetration and wakes
are those seen at the samples):
- finite: every position, angle, velocity and angular velocity finite; a sim.SimulationError or
  any exception while stepping is recorded as the error;
- energy: E = kinetic + potential (m |g| (y - floor_y)); E_avail = E at the start = the most any
  motion can release. energy_growth = max(E(t) - E(0)) / E_avail; ke_max_rel = max KE(t) / E_avail;
- penetration: the deepest overlap at a sample (separating-axis test on the convex polygons, pairs
  from a sweep over bounding boxes, floor included), divided by the smaller of the two bodies'
  thinnest widths: penetration_rel; the metres too;
- drift: the largest displacement of a body that should rest (every body of the rest scenes, the
  anvil of the impact scene) from its start, divided by that body's thinnest width: drift_rel;
- tunnelling: a body's centre below the floor at the end of the run, or (projectile scenes,
  checked every step) the projectile's centre passing through a body: entering it through one
  face and leaving through the opposite face, within one step or over several (its path between
  samples clipped to the body's rectangle; pushed back out, or out of a side face, is not
  counted);
- outcome: rest, impact and projectile_stack scenes: "stands" if no (non-projectile) body moved
  more than half its thinnest width nor turned more than 0.2 rad, else "collapsed";
  projectile_wall: "stopped" / "passed" (projectile's final x before / beyond the wall);
  knife_edge: "stays" (turned less than 0.1 rad) / "falls left" / "falls right";
- wakes: the most times one body went from asleep to awake (the runners' ``asleep``) between
  samples; for sim also state_changes, the most state changes of one body in ``World.events``
  (equal-state events excluded);
- ms_per_step: wall time of the steps (the first step excluded, sampling excluded) over their
  count. Measured inside each run while other runs share the machine (a process pool): indicative
  only; the study's speed figures come from its serial benchmarks (bench_step, bench_freeze).

Rules (a run gets the worst mark any rule gives; reasons are listed in ``reason``):
- failed: an error raised while stepping; a non-finite state; explosion (KE > 2 E_avail at any
  sample: energy that no motion of the scene can release); tunnelling; chattering (a body woken
  more than 2 times in a rest or impact scene, or, in the impact scene, a sim body changing state
  more than 3 times: landing, being held, waking once and re-freezing take at most 3); or an outcome
  different from the reference's (skipped, with a note, when the reference itself is not valid:
  error, refused, non-finite or tunnelled);
- degraded: finite, same outcome, but penetration_rel > 0.10 (an overlap deeper than a tenth of
  the thinner body), drift_rel > 0.01 (a resting body moved more than 1 % of its thinnest width),
  or energy_growth > 0.05 (5 % of the available energy created);
- stable: otherwise;
- rejected: refused with a clear error: the scene or the settings were refused with a ValueError
  before the first step, recorded with its message (e.g. sim's "body 0 is 0.001 m thick ... Use
  substeps >= 11"). Not a result and not a failure of physics: the system said it cannot do this,
  rather than doing it wrong; the analysis lists these cells apart and never counts them as
  breaking;
- not run: cost cap or timeout. A run stopped by its ``budget_s`` part way says in its reason what
  it had shown by then (its outcome then is the pose at the timeout, not at the end, so it is not
  a verdict); but if a rule whose verdict no later step can take back had already failed it (a
  non-finite state, an explosion, a passage through a body, chattering: an event or a running
  maximum), it is failed, "before the timeout" (``study.extremes.rules.classify``).

Columns: axis, value, unit, system, scene, bodies, dt_s, iterations, substeps, steps, status,
reason, outcome, ref_outcome, ref_valid, error, finite, exploded, tunnelled, chattering,
energy_growth, ke_max_rel, penetration_max_m, penetration_rel, drift_max_m, drift_rel, wakes_max,
state_changes_max, asleep_before_event, decision, ms_per_step, steps_done, wall_s. ``iterations``
is the run's solver iterations as the runner reports them (sim: per substep); ``substeps`` sim's
substeps per step (empty for the peers). ``<name>.json`` holds the thresholds v* and the
reference runs.

Code (study/extremes/): ``axes`` (one Axis record per axis: adding an axis is one entry
there), ``scenes`` (the builders), ``geometry`` and ``judge`` (the measuring), ``rules`` (the
marks), ``threshold`` (the bisection of v*), ``runs`` (the tasks and one run), ``record`` (a
run's Measurement and a table Row, whose fields are the columns). This script sweeps them.

Every untimed run goes through study.executor.run_tasks with an incremental store
(results/partial/table_extremes.jsonl; --quick: results/quick/partial/table_extremes-quick.jsonl):
an interrupted sweep resumes where it stopped; the store is removed once the CSV is written.

    python -m experiments.table_extremes [--quick]
writes results/data/table_extremes.csv and table_extremes.json. --quick: one or two values per
axis (the extreme ones), short runs (1 s; the projectiles 3 s, the knife edge 4 s), small sizes,
coarser references (fine 4, projectiles 8).
"""

import json
import math
from dataclasses import asdict, replace

import pandas as pd

from study import common
from study.common import DT, SYSTEMS
from study.executor import run_tasks
from study.extremes import rules
from study.extremes.axes import AXES, ALL_SYSTEMS, PLACED_AXES, SIM_ONLY_AXES, applies
from study.systems import NO_PRESOLVE_SETTINGS, NO_PRESOLVE_SYSTEMS
from study.extremes.judge import KNIFE_TURN, STAND_MOVE, STAND_TURN
from study.extremes.record import Measurement, Row
from study.extremes.runs import (
    REF_ITERATIONS,
    REF_MAX_SUBSTEPS,
    REF_SUBSTEPS,
    reference_task,
    run_task,
    simulate_stored,
    task_key,
)
from study.extremes.scenes import (
    ARRIVAL_S,
    HAMMER,
    HAMMER_DENSITY,
    HAMMER_GAP,
    PROJECTILE_SIZE,
    WALL,
    scene_of,
)
from study.extremes.threshold import find_threshold
from study.peers import engine_of

NAME = "table_extremes"

FULL = {
    "axes": {name: list(axis.values) for name, axis in AXES.items()},
    "duration_s": {name: axis.duration_s for name, axis in AXES.items()},
    "fine": 8,
    "fine_projectile": 32,
    "long_run_reference_s": 60.0,
    "samples": 200,
    "sample_budget": 20000,
    "budget_s": 120.0,
    "pybullet_max_bodies": 2000,
    "bisection_steps": 45,
}
QUICK = {
    "axes": {name: list(axis.quick) for name, axis in AXES.items()},
    "duration_s": {name: axis.quick_duration_s for name, axis in AXES.items()},
    "fine": 4,
    "fine_projectile": 8,
    "long_run_reference_s": 5.0,
    "samples": 50,
    "sample_budget": 20000,
    "budget_s": 20.0,
    "pybullet_max_bodies": 2000,
    "bisection_steps": 45,
}


def thresholds_of(config, store, header):
    """policy -> find_threshold's result, for the axes with knob "threshold" (two bisections,
    through the executor); {} when no such axis is in ``config``."""
    axes = [a for a, values in config["axes"].items() if AXES[a].knob == "threshold" and values]
    if not axes:
        return {}
    steps = int(round(config["duration_s"][axes[0]] / DT))
    tasks = [
        {
            "role": "threshold",
            "policy": p,
            "steps": steps,
            "bisection_steps": config["bisection_steps"],
        }
        for p in ("paper", "extended")
    ]
    found = run_tasks(
        find_threshold,
        tasks,
        desc=f"{NAME} thresholds",
        store=store,
        header=header,
        key=lambda t: f"threshold|{t['policy']}",
    )
    return {t["policy"]: res for t, res in zip(tasks, found)}


def sweep_tasks(config, thresholds):
    """(run tasks, not run: [(axis, value, system, reason)]) for every applicable cell."""
    runs, not_run = [], []
    for axis, values in config["axes"].items():
        for value in values:
            for system in ALL_SYSTEMS:
                if not applies(axis, system):
                    continue
                v_star = None
                if AXES[axis].knob == "threshold":
                    policy = "extended" if system == "sim-extended" else "paper"
                    v_star = thresholds[policy]["v_star"]
                    if not math.isfinite(v_star):
                        not_run.append(
                            (
                                axis,
                                value,
                                system,
                                "no threshold crossing found: " + thresholds[policy]["note"],
                            )
                        )
                        continue
                task = run_task(axis, value, system, config, v_star)
                n = task["bodies"]
                if engine_of(task["runner"]) == "pybullet" and n > config["pybullet_max_bodies"]:
                    not_run.append(
                        (
                            axis,
                            value,
                            system,
                            f"cost: pybullet not run above {config['pybullet_max_bodies']}"
                            f" bodies ({n}; 10^4 boxes in columns cost it ~1.3 s per step)",
                        )
                    )
                    continue
                runs.append(task)
    return runs, not_run


def table_of(runs, not_run, results, config):
    """The table: one Row per run (marked by the rules against its reference) and per cell not
    run, sorted by axis, value (benign to extreme) and system."""
    rows = []
    for task in runs:
        ref = results[task_key(reference_task(task, config))]
        res = results[task_key(task)]
        res = replace(res, chattering=rules.chattering(task, res))
        status, reason = rules.classify(res, ref)
        if not rules.ref_valid(ref) and status not in ("rejected", "not run"):
            reason = (reason + "; " if reason else "") + "reference not valid: outcome not compared"
        rows.append(Row.of_run(task, res, status, reason, ref))
    for axis, value, system, reason in not_run:
        rows.append(
            Row(
                axis=axis,
                value=value,
                unit=AXES[axis].unit,
                system=system,
                status="not run",
                reason=reason,
            )
        )
    table = pd.DataFrame([asdict(row) for row in rows])
    # temporary sort keys (dropped): AXES's order, the config's order of values, ALL_SYSTEMS's
    order = {a: k for k, a in enumerate(AXES)}
    table["_a"] = table["axis"].map(order)
    table["_v"] = [config["axes"][a].index(v) for a, v in zip(table["axis"], table["value"])]
    table["_s"] = table["system"].map({s: k for k, s in enumerate(ALL_SYSTEMS)})
    table = table.sort_values(["_a", "_v", "_s"]).drop(columns=["_a", "_v", "_s"])
    return table.reset_index(drop=True)


def run(config, args):
    common.compile_kernels()
    store, header = common.sweep_store(NAME, args, config)  # entry removes it once written

    # 1. the impulse thresholds (two bisections, through the executor)
    thresholds = thresholds_of(config, store, header)

    # 2. every run and every distinct reference, all independent: one executor call
    runs, not_run = sweep_tasks(config, thresholds)
    refs = {}
    for task in runs:
        ref = reference_task(task, config)
        refs.setdefault(task_key(ref), ref)
    tasks = list(refs.values()) + runs
    stored = run_tasks(
        simulate_stored, tasks, desc=f"{NAME} runs", store=store, header=header, key=task_key
    )
    results = {task_key(t): Measurement(**res) for t, res in zip(tasks, stored)}

    # 3. the table
    table = table_of(runs, not_run, results, config)

    references = [
        {
            "key": k,
            "scene": t["scene"],
            "dt_s": t["dt"],
            "iterations": t["iterations"],
            "substeps": results[k].substeps,
            "steps": t["steps"],
            "outcome": results[k].outcome,
            "valid": rules.ref_valid(results[k]),
            "error": results[k].error,
            "tunnelled": results[k].tunnelled,
            "penetration_rel": results[k].penetration_rel,
            "wall_s": results[k].wall_s,
        }
        for k, t in refs.items()
    ]
    scenes = [
        scene_of(spec)
        for spec in {
            json.dumps(t["scene"], sort_keys=True): t["scene"]
            for t in runs
            if t["kind"] != "rejected"
        }.values()
    ]
    parameters = {
        "dt": DT,
        "systems": list(SYSTEMS),
        "no_presolve": {
            "systems": list(NO_PRESOLVE_SYSTEMS),
            "settings": NO_PRESOLVE_SETTINGS,
            "axes": [a for a in PLACED_AXES if a in config["axes"]],
        },
        "sim_only_axes": [a for a in SIM_ONLY_AXES if a in config["axes"]],
        "reference": {
            "system": "sim-off",
            "fine": config["fine"],
            "fine_projectile": config["fine_projectile"],
            "substeps": REF_SUBSTEPS,
            "iterations_per_substep": REF_ITERATIONS,
            "substeps_doubled_up_to": REF_MAX_SUBSTEPS,
        },
        "rules": {
            "explosion_factor": rules.EXPLOSION_FACTOR,
            "penetration_rel": rules.PENETRATION_REL,
            "drift_rel": rules.DRIFT_REL,
            "energy_growth": rules.ENERGY_GROWTH,
            "max_wakes": rules.MAX_WAKES,
            "max_state_changes": rules.MAX_STATE_CHANGES,
            "stand_move": STAND_MOVE,
            "stand_turn_rad": STAND_TURN,
            "knife_turn_rad": KNIFE_TURN,
        },
        "axes": {a: {"unit": AXES[a].unit, "values": config["axes"][a]} for a in AXES},
        "thresholds": thresholds,
        "references": references,
        "projectile": {"size_m": PROJECTILE_SIZE, "arrival_s": ARRIVAL_S, "wall_m": list(WALL)},
        "impact": {"hammer_m": HAMMER, "hammer_density": HAMMER_DENSITY, "gap_m": HAMMER_GAP},
        "store": str(store),
    }
    return table, scenes, parameters


main = common.entry(NAME, __doc__, FULL, QUICK, run, sweep=True)

if __name__ == "__main__":
    main()
