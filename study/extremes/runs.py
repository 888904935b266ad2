"""The runs of the extremes table (experiments/table_extremes.py): the executor task of one
(axis, value, system) cell (``run_task``) and of its reference (``reference_task``), both plain
dicts keyed in the incremental store by ``task_key``, and ``simulate``, which builds, steps,
samples and judges one of them into a Measurement.

Nothing here names an axis: what an axis varies is read from its Axis record
(study.extremes.axes)."""

import json
import math
import time

import numpy as np

from study.common import DT, build
from study.extremes.axes import AXES
from study.systems import runner_system, system_settings
from study.extremes.geometry import Shapes
from study.extremes.judge import Judge
from study.extremes.record import Measurement
from study.extremes.rules import EXPLOSION_FACTOR
from study.extremes.scenes import scene_of
from study.extremes.threshold import Decision
from study.peers import sim_world

#: the reference's solver (table_extremes' docstring, "Reference"): sim.World's defaults, written
#: out so that the reference is fixed here and never moves with a runner's or the World's defaults
REF_SUBSTEPS = 4  # substeps per reference step (doubled for a scene refused at it)
REF_ITERATIONS = 1  # biased solve sweeps per substep
REF_MAX_SUBSTEPS = 4096  # give up doubling here (the reference is then "rejected")
#: the systems whose impulse test the impact axis watches (the others get sim-paper's v*)
DECIDING_SYSTEMS = ("sim-paper", "sim-extended")
#: scene kinds sampled after every step: their event (an arrival, an impact, a fall) is brief
EVERY_STEP_KINDS = ("projectile", "impact", "knife")


def state_changes(runner, n):
    """Most state changes of one sim body (equal-state events excluded); nan for peers."""
    world = sim_world(runner)
    if world is None:
        return math.nan
    counts = np.zeros(n, dtype=int)
    for _, body, a, b, _ in world.events:
        if a != b:
            counts[body] += 1
    return int(counts.max()) if n else 0


def build_runner(task, scene):
    """The task's runner. A task with ``refine_substeps`` (the references) that sim refuses as
    too fine for its step (a ValueError naming the substeps needed) is built again with its
    substeps doubled, up to that many; any other ValueError propagates (refused)."""
    settings = dict(task.get("settings", {}))
    system = task.get("runner") or runner_system(task["system"])
    while True:
        try:
            return build(system, scene, dt=task["dt"], iterations=task["iterations"], **settings)
        except ValueError as exc:
            substeps = settings.get("substeps")
            cap = task.get("refine_substeps")
            if not cap or substeps is None or "substeps" not in str(exc) or 2 * substeps > cap:
                raise
            settings["substeps"] = 2 * substeps


def simulate(task):
    """One run (executor task, a plain dict) -> Measurement: build, step with samples, judge.
    Never raises for what the simulated system does (a ValueError while building is recorded as
    'rejected', an exception while stepping as the run's error); the measuring code's own errors
    propagate."""
    out = Measurement(role=task["role"], iterations=task["iterations"])
    t_start = time.perf_counter()
    try:
        scene = scene_of(task["scene"])
        out.bodies = len(scene.bodies)
        shapes = Shapes(scene)
        runner = build_runner(task, scene)
    except ValueError as exc:
        out.status_hint, out.error = "rejected", f"{type(exc).__name__}: {exc}"
        return out
    # what ran, as the runner reports it (sim: iterations per substep, and its substeps)
    out.iterations = runner.settings.get("iterations", task["iterations"])
    world = sim_world(runner)
    out.substeps = int(world.substeps) if world is not None else None
    judge = Judge(scene, shapes)
    decision = Decision(task["system"][len("sim-") :]) if task.get("watch_decision") else None
    steps, every, budget = task["steps"], task["sample_every"], task["budget_s"]
    stepping = 0.0

    def advance(n):
        """Step n steps; an exception from the system (sim.SimulationError, or anything a peer
        raises) is the run's result, recorded; an exception in the measuring code is a bug and
        propagates."""
        try:
            runner.step(n)
        except Exception as exc:
            out.error = f"{type(exc).__name__}: {exc}"
            return False
        return True

    try:
        judge.sample(runner, 0.0)
        done = 0
        while done < steps and judge.finite:
            k = min(every, steps - done)
            if done == 0:  # the first step is not timed (the study's rule)
                if not advance(1):
                    break
                k -= 1
                done = 1
            t0 = time.perf_counter()
            if not advance(k):
                break
            stepping += time.perf_counter() - t0
            done += k
            out.steps_done = done
            judge.sample(
                runner,
                done * task["dt"],
                overlap=(done // every) % task.get("overlap_every", 1) == 0 or done == steps,
            )
            if decision is not None:
                decision.watch(runner.world)
            if judge.ke_max > EXPLOSION_FACTOR:
                out.exploded = True
                break
            if time.perf_counter() - t_start > budget and done < steps:
                out.status_hint = "not run"
                out.error = f"timeout: {budget:g} s of wall time reached at step {done} of {steps}"
                break
    finally:
        out.state_changes_max = state_changes(runner, shapes.n)
        runner.close()
    timed_steps = out.steps_done - 1
    # through_floor is judged on the last pose, "at the end of the run": a run stopped by its time
    # budget has no end, and a body's centre can dip under the floor and come back (penetration).
    # A passage through a body (judge.tunnelled) happened, whatever follows.
    ended = out.status_hint != "not run"
    tunnelled = "; ".join(t for t in (judge.tunnelled, ended and judge.through_floor()) if t)
    out.finite, out.tunnelled, out.outcome = judge.finite, tunnelled, judge.outcome()
    out.energy_growth, out.ke_max_rel = judge.energy_growth, judge.ke_max
    out.penetration_max_m, out.penetration_rel = judge.pen_m, judge.pen_rel
    out.drift_max_m = judge.drift_m if len(judge.resting) else math.nan
    out.drift_rel = judge.drift_rel if len(judge.resting) else math.nan
    out.wakes_max = int(judge.wakes.max()) if judge.start is not None else math.nan
    out.asleep_before_event = judge.asleep_before_event
    out.decision = decision.label() if decision is not None else ""
    out.ms_per_step = 1e3 * stepping / timed_steps if timed_steps > 0 else math.nan
    out.wall_s = time.perf_counter() - t_start
    if not judge.finite and not out.error:
        out.error = judge.error or "non-finite state (no error raised)"
    return out


def simulate_stored(task):
    """simulate(task) as a plain dict: the executor's task function (its incremental store keeps
    JSON, readable); Measurement(**result) restores it."""
    return simulate(task).stored()


def kind_and_size(spec):
    """(scene kind, body count); ("rejected", 0) when the scene itself is refused (the run then
    records the ValueError)."""
    try:
        scene = scene_of(spec)
    except ValueError:
        return "rejected", 0
    return scene.params["kind"], len(scene.bodies)


def sample_every(steps, bodies, every_step, config):
    """Steps between samples: 1 where an event must be caught (projectiles, impacts, knife
    edges); else ~``samples`` samples per run, fewer for big scenes (at most ``sample_budget``
    body-samples, at least 10 samples: measuring a 10^4-body pose costs more than stepping it)."""
    if every_step:
        return 1
    samples = max(10, min(config["samples"], config["sample_budget"] // max(1, bodies)))
    return max(1, steps // samples)


def run_task(axis, value, system, config, v_star=None):
    """The executor task of one (axis, value, system) run; ``axis`` is a name of AXES, ``system``
    one of ALL_SYSTEMS, ``v_star`` the impulse threshold (m/s) for a knob "threshold" axis."""
    record = AXES[axis]
    dt = float(value) if record.knob == "dt" else DT
    iterations = int(value) if record.knob == "iterations" else None
    settings = system_settings(system)
    if record.knob == "substeps":
        settings["substeps"] = int(value)
    spec = record.scene_spec(value, v_star)
    steps = int(value) if record.knob == "steps" else int(round(config["duration_s"][axis] / dt))
    kind, bodies = kind_and_size(spec)
    every_step = kind in EVERY_STEP_KINDS
    return {
        "role": "run",
        "axis": axis,
        "value": value,
        "system": system,
        "runner": runner_system(system),
        "settings": settings,
        "scene": spec,
        "kind": kind,
        "bodies": bodies,
        "dt": dt,
        "iterations": iterations,
        "steps": steps,
        "sample_every": sample_every(steps, bodies, every_step, config),
        "budget_s": config["budget_s"],
        "watch_decision": record.knob == "threshold" and system in DECIDING_SYSTEMS,
    }


def reference_task(run, config):
    """sim-off at a fine dt with REF_SUBSTEPS x REF_ITERATIONS, presolve on, same simulated time,
    whatever the run's own settings (table_extremes' docstring); ``run`` is a run_task."""
    record = AXES[run["axis"]]
    dt = min(run["dt"], DT) / config[record.fine]
    spec = run["scene"]
    duration = run["steps"] * run["dt"]
    if record.reference_scene is not None:  # one small scene stands for the row's
        builder, arg = record.reference_scene
        spec = {"builder": builder, "args": [arg]}
    if record.reference_cap:
        duration = min(duration, config[record.reference_cap])
    steps = int(round(duration / dt))
    kind, bodies = kind_and_size(spec)
    every_step = kind in EVERY_STEP_KINDS
    return {
        "role": "ref",
        "axis": "reference",
        "value": 0,
        "system": "sim-off",
        "runner": "sim-off",
        "settings": {"substeps": REF_SUBSTEPS},
        "refine_substeps": REF_MAX_SUBSTEPS,
        "scene": spec,
        "kind": kind,
        "bodies": bodies,
        "dt": dt,
        "iterations": REF_ITERATIONS,
        "steps": steps,
        "sample_every": sample_every(steps, bodies, every_step, config),
        "budget_s": 20 * config["budget_s"],
        # a reference's penetration is only reported: ~``samples`` overlap tests suffice
        # even where its poses are checked every step (tunnelling)
        "overlap_every": max(1, steps // config["samples"]) if every_step else 1,
    }


def task_key(task):
    """The store's key of a task: a run by its cell, a reference by everything that makes it."""
    if task["role"] == "run":
        return f"run|{task['axis']}|{task['value']!r}|{task['system']}"
    return "ref|" + json.dumps(
        [task["scene"], task["dt"], task["iterations"], task["steps"], task["settings"]],
        sort_keys=True,
    )
