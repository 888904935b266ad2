"""The measurement protocols the freeze study shares (bench_freeze, fig_speedup, fig_scaling,
fig_time_to_rest): settle a scene and time its steps (``settle_and_time``), the cost of an awake
and of a frozen body-step from a grid of mixes (``per_body_cost``), and the steps until a scene is
fully frozen (``freeze_run``). The method is described in experiments/bench_freeze.py's
docstring; the scripts that use a protocol describe it again where they differ.

A library module: it is imported by scripts and imports none (tests/pipeline/test_makedeps.py)."""

import math
import statistics
from typing import NamedTuple

import numpy as np

import sim
from study.common import DT, awake_mask, build, calibrate, label, n_awake, step_until_frozen
from study.cost_fit import FIT_UNITS, fit_cost, relative_to_off
from study import systems
from study.peers import engine_of
from study.timing import interleaved, interleaved_calls, single_calls

WARMUP_STEPS = 10  # untimed steps after build (and after freezing) before any timing
FALL_HEIGHT = 3000.0  # m, bottom of the falling block (mixes, fall scene)
FLY_PITCH = 2.0  # m between falling/drifting boxes (unit boxes: never touching at rest)
FREEZE_HOLD_S = 1.0  # s stepped after all froze, to see whether the freeze holds
GRAVITY = 9.81  # m/s^2, every scene's (sim.Scene's default)

#: the systems that freeze or sleep (the others are the references: nothing frozen)
FREEZING = systems.FREEZING  # the systems that freeze: time-to-rest runs each
#: per_body_cost's default systems (bench_freeze part 2)
MIX_SYSTEMS = ("sim-extended", "sim-off")


# ---- scenes ------------------------------------------------------------------------------------


def block(n, y0, velocity=None, angular_velocity=None, x0=0.0):
    """``n`` unit boxes in a block ~sqrt(n) columns wide, FLY_PITCH apart, bottom row at y0."""
    cols = max(1, math.ceil(math.sqrt(n)))
    bodies = []
    for i in range(n):
        row, col = divmod(i, cols)
        v = (0.0, 0.0) if velocity is None else tuple(float(x) for x in velocity[i])
        w = 0.0 if angular_velocity is None else float(angular_velocity[i])
        bodies.append(
            sim.Body.box(
                1.0,
                1.0,
                position=(x0 + col * FLY_PITCH, y0 + row * FLY_PITCH),
                velocity=v,
                angular_velocity=w,
                friction=0.6,
            )
        )
    return bodies


def mix_scene(n_frozen, n_awake, height=FALL_HEIGHT, launch=0.0):
    """rest_row(n_frozen) (bodies 0..n_frozen-1) plus n_awake boxes in flight ``height`` m up,
    launched upwards at ``launch`` m/s (``mix_launch``)."""
    bodies = list(sim.scenes.rest_row(n_frozen).bodies) if n_frozen else []
    bodies += block(n_awake, height, velocity=[(0.0, launch)] * n_awake)
    return sim.Scene(
        bodies=bodies,
        name="mix",
        params={
            "n_frozen": n_frozen,
            "n_awake": n_awake,
            "height": height,
            "launch": launch,
            "pitch": FLY_PITCH,
            "row": "rest_row(n_frozen)",
        },
    )


def mix_launch(config, repeats):
    """m/s: the upward speed that brings the mixes' flyers to the top of their flight half way
    through the timing of a world that needs no settling (WARMUP_STEPS, then ``repeats`` of
    ``config["mix_steps"]`` steps).

    Why: the flyers stand for the cheapest awake body, one with no contacts; a body's cost in sim
    also grows with its speed (a fat box that runs ahead of it, and, past half its size a step,
    the continuous stage's sweep). Dropped from rest they reached 57 m/s by the end of a 7 x 50
    step timing, 0.95 m a step, and each cost sim ~1.1-1.8 us a step instead of ~0.17 us. Thrown
    up so that they peak mid-timing, they move at most g (repeats x steps / 2) dt: 28.6 m/s,
    0.48 m a step, at 7 x 50 steps of 1/60 s."""
    return GRAVITY * DT * (WARMUP_STEPS + repeats * config["mix_steps"] / 2.0)


def fall_scene(n, height=FALL_HEIGHT):
    """n boxes falling from ``height`` m, never touching each other before the floor."""
    return sim.Scene(
        bodies=block(n, height), name="fall", params={"n": n, "height": height, "pitch": FLY_PITCH}
    )


def flight_budget(height=FALL_HEIGHT, clearance=10.0):
    """Steps a box starting at rest ``height`` m up stays more than ``clearance`` m above the
    floor under semi-implicit Euler at DT (it has fallen g dt^2 n (n+1) / 2 after n steps)."""
    g = 9.81
    n = int(math.sqrt(2.0 * (height - clearance) / (g * DT * DT)))
    while g * DT * DT * n * (n + 1) / 2 > height - clearance:
        n -= 1
    return n


# ---- running -----------------------------------------------------------------------------------
def long_row(part, scene, system, bodies, n_aw, n_fr, metric, value, unit, flag=""):
    """One row of the study's long-form tables (columns: part, scene, system, bodies, n_awake,
    n_frozen, metric, value, unit, flag)."""
    return {
        "part": part,
        "scene": scene,
        "system": system,
        "bodies": bodies,
        "n_awake": n_aw,
        "n_frozen": n_fr,
        "metric": metric,
        "value": value,
        "unit": unit,
        "flag": flag,
    }


def timing_rows(common, times, before, after, steps, repeats):
    """The rows every timed run reports: median and min ms/step, awake counts around the timing,
    and how it was timed."""
    return [
        long_row(**common, metric="ms_per_step_median", value=statistics.median(times), unit="ms"),
        long_row(**common, metric="ms_per_step_min", value=min(times), unit="ms"),
        long_row(**common, metric="n_awake_before", value=before, unit="bodies"),
        long_row(**common, metric="n_awake_after", value=after, unit="bodies"),
        long_row(**common, metric="steps_per_repeat", value=steps, unit="steps"),
        long_row(**common, metric="repeats", value=repeats, unit="count"),
    ]


def largest_move(runner, start):
    """m: the largest distance any body of ``runner`` has moved from ``start`` ((N,2) m)."""
    return float(np.hypot(*(runner.positions - start).T).max())


# ---- settle and time: a scene at rest ----------------------------------------------------------
def _calls_per_repeat(runner, repeat_s, probe=5, lo=5, hi=2000):
    """One-step calls per repeat so that one repeat lasts about ``repeat_s``."""
    t = single_calls(runner, probe) / 1e3
    return int(min(hi, max(lo, round(repeat_s / max(t, 1e-9)))))


def settle_and_time(scene, systems, cap_steps, repeat_s, repeats, progress, age_steps=None):
    """Build every system on ``scene``, bring it to rest, and time its steps, interleaved.

    Each freezing system (FREEZING) is stepped one step at a time until no body is solved, or
    ``cap_steps``. With ``age_steps``, every system is then stepped on to that many steps, so that
    all are timed at the same simulated age (without it, systems that do not freeze are timed
    right after build: bench_freeze's part 1). Then WARMUP_STEPS untimed steps, a repeat length
    calibrated to ``repeat_s`` s, and ``repeats`` repeats interleaved over all systems; then the
    same again with one step per call (``study.timing.single_calls``; ``calls`` calls per repeat,
    calibrated alike).
    Returns one dict per system: ``froze_at`` (step count when none was solved, or None),
    ``before``/``after`` (awake counts around the timing), ``times`` (ms/step of each repeat),
    ``steps`` (steps per repeat), ``call_times`` (ms per one-step call of each repeat),
    ``calls`` (calls per repeat), ``age`` (steps taken before the warm-up), ``moved`` (m, largest
    distance a body moved from its start, measured after the timing). Runners are closed."""
    tag = label(scene)
    runners, froze_at, steps, starts, ages = [], [], [], [], []
    try:
        for system in systems:
            progress.set_postfix_str(f"{tag} {system}: build, freeze")
            runner = build(system, scene)
            runners.append(runner)
            starts.append(runner.positions)
            froze_at.append(step_until_frozen(runner, cap_steps) if system in FREEZING else None)
            if age_steps is not None and runner.step_count < age_steps:
                runner.step(age_steps - runner.step_count)
            ages.append(runner.step_count)
            runner.step(WARMUP_STEPS)
            steps.append(calibrate(runner, repeat_s))
        before = [n_awake(r) for r in runners]
        progress.set_postfix_str(f"{tag}: timing")
        times = interleaved(runners, steps, repeats, progress)
        calls = [_calls_per_repeat(r, repeat_s) for r in runners]
        progress.set_postfix_str(f"{tag}: timing, one step per call")
        call_times = interleaved_calls(runners, calls, repeats)
        after = [n_awake(r) for r in runners]
        return [
            {
                "froze_at": froze_at[k],
                "before": before[k],
                "after": after[k],
                "times": times[k],
                "steps": steps[k],
                "call_times": call_times[k],
                "calls": calls[k],
                "age": ages[k],
                "moved": largest_move(runners[k], starts[k]),
            }
            for k in range(len(systems))
        ]
    finally:
        for r in runners:
            r.close()


# ---- per-body cost: a frozen body-step vs an awake body-step ----------------------------------
def expected_awake(system, n_frozen, n_awake):
    """Bodies a mix should have solved once settled: the flyers only, if the system freezes the
    resting row; every body otherwise."""
    return n_awake if system in FREEZING else n_awake + n_frozen


class Mix(NamedTuple):
    """One timed world of per_body_cost: its mix and system."""

    tag: str  # the mix scene's label
    system: str
    n_frozen: int  # bodies in the resting row
    n_awake: int  # flyers


def per_body_cost(
    config, repeats, progress, systems=MIX_SYSTEMS, extra_units=None, scenes_out=None
):
    """bench_freeze part 2 on ``config``'s mixes for ``systems``: (rows, fits). A system that
    sleeps the row only after a timer (sim-sleep, pymunk-sleep: 0.5 s) is stepped, after the
    warm-up, until only the flyers are solved, for at most ``config["mix_settle_s"]`` s (default
    0). Fit rows are written for the keys of FIT_UNITS (+ ``extra_units``, key -> unit). The mix
    scenes are appended to the list ``scenes_out`` if one is given (for the metadata: building
    thousands of bodies again takes seconds)."""
    mixes = [(nf, na) for nf in config["mix_frozen"] for na in config["mix_awake"]]
    launch = mix_launch(config, repeats)
    settle_cap = WARMUP_STEPS + int(round(config.get("mix_settle_s", 0.0) / DT))
    runners, keys = [], []
    try:
        for nf, na in mixes:
            scene = mix_scene(nf, na, launch=launch)
            if scenes_out is not None:
                scenes_out.append(scene)
            for system in systems:
                progress.set_postfix_str(f"{label(scene)} {system}: build")
                runner = build(system, scene)
                runners.append(runner)
                runner.step(WARMUP_STEPS)
                while runner.step_count < settle_cap and n_awake(runner) != expected_awake(
                    system, nf, na
                ):
                    runner.step(1)
                keys.append(Mix(label(scene), system, nf, na))
        # the flyers must still be in flight at the end of the timing
        aged = max(r.step_count for r in runners)
        steps = max(1, min(config["mix_steps"], (flight_budget() - aged) // repeats))
        before = [n_awake(r) for r in runners]
        progress.set_postfix_str(f"{len(runners)} worlds: timing")
        times = interleaved(runners, [steps] * len(runners), repeats, progress)
        after = [n_awake(r) for r in runners]
        lowest = [
            float(r.positions[key.n_frozen :, 1].min()) if key.n_awake else math.nan
            for r, key in zip(runners, keys)
        ]  # m
        fastest = [
            float(np.hypot(*r.velocities[key.n_frozen :].T).max()) if key.n_awake else math.nan
            for r, key in zip(runners, keys)
        ]  # m/s, at the end of the timing (mix_launch)
    finally:
        for r in runners:
            r.close()
    rows, fits = [], {}
    for k, key in enumerate(keys):
        nf, na = key.n_frozen, key.n_awake
        expected = expected_awake(key.system, nf, na)
        ok = before[k] == expected and after[k] == expected and (not na or lowest[k] > 5.0)
        common = dict(
            part="per_body_cost",
            scene=key.tag,
            system=key.system,
            bodies=nf + na,
            n_aw=na,
            n_fr=nf,
            flag="" if ok else "awake count or flight check failed",
        )
        rows += timing_rows(common, times[k], before[k], after[k], steps, repeats)
        rows.append(long_row(**common, metric="lowest_flying_y", value=lowest[k], unit="m"))
        rows.append(long_row(**common, metric="fastest_flyer_speed", value=fastest[k], unit="m/s"))
    for system in systems:
        ks = [k for k, key in enumerate(keys) if key.system == system]
        fit = fit_cost(
            [keys[k].n_awake for k in ks],
            [keys[k].n_frozen for k in ks],
            [statistics.median(times[k]) for k in ks],
        )
        fits[system] = fit
    relative_to_off(fits)
    units = {**FIT_UNITS, "b_over_b_off": "ratio", "a_over_a_off": "ratio", **(extra_units or {})}
    for system, fit in fits.items():
        for key, value in fit.items():
            if key in units:
                rows.append(
                    long_row(
                        "per_body_cost",
                        "fit",
                        system,
                        math.nan,
                        math.nan,
                        math.nan,
                        f"fit_{key}",
                        value,
                        units[key],
                    )
                )
    return rows, fits


# ---- freeze runs: steps until everything is frozen -------------------------------------------
class FreezeTask(NamedTuple):
    """One freeze run: the scene (a sim.scenes builder and its keyword arguments), the system (or
    a sim system's variant, study.systems: "sim-extended (no presolve)"), and the most simulated
    time to wait for the freeze."""

    builder: str
    params: dict
    system: str
    cap_s: float  # s


def freeze_run(task):
    """One freeze run (bench_freeze part 3), a FreezeTask: steps the scene one step at a time until
    every body is frozen/asleep or the cap, then (if it froze) FREEZE_HOLD_S more to see whether
    the freeze holds; returns the run's rows. Module-level and self-contained, so sweeps can hand
    it to ``study.executor.run_tasks``."""
    system = task.system  # the rows' name: a variant keeps its own
    scene = sim.scenes.BUILDERS[task.builder](**task.params)
    tag = label(scene)
    n = len(scene.bodies)
    cap = int(round(task.cap_s / DT))
    hold = int(round(FREEZE_HOLD_S / DT))
    runs_as = systems.runner_system(system)
    with build(runs_as, scene, **systems.system_settings(system)) as runner:
        start = runner.positions
        is_sim = engine_of(runs_as) == "sim"
        frozen_at = observable_at = None
        while runner.step_count < cap:
            runner.step(1)
            if is_sim and observable_at is None and (runner.world.states != sim.State.FREE).all():
                observable_at = runner.step_count
            if not awake_mask(runner).any():
                frozen_at = runner.step_count
                break
        end_awake = n_awake(runner)
        end_not_free = int((runner.world.states != sim.State.FREE).sum()) if is_sim else math.nan
        moved = largest_move(runner, start)
        held = math.nan
        if frozen_at is not None:
            runner.step(hold)
            held = n_awake(runner)
    never = frozen_at is None
    flag = "never" if never else ""
    common = dict(
        part="time_to_freeze",
        scene=tag,
        system=system,
        bodies=n,
        n_aw=end_awake,
        n_fr=n - end_awake,
        flag=flag,
    )
    rows = [
        long_row(
            **common,
            metric="steps_to_all_frozen",
            value=math.nan if never else frozen_at,
            unit="steps",
        ),
        long_row(
            **common,
            metric="time_to_all_frozen",
            value=math.nan if never else frozen_at * DT,
            unit="s",
        ),
        long_row(**common, metric="n_awake_at_end", value=end_awake, unit="bodies"),
        long_row(**common, metric="n_awake_1s_after", value=held, unit="bodies"),
        long_row(**common, metric="max_displacement", value=moved, unit="m"),
        long_row(**common, metric="cap_steps", value=cap, unit="steps"),
    ]
    if is_sim:
        rows += [
            long_row(
                **common,
                metric="steps_to_all_not_free",
                value=math.nan if observable_at is None else observable_at,
                unit="steps",
            ),
            long_row(**common, metric="n_not_free_at_end", value=end_not_free, unit="bodies"),
        ]
    return rows


def freeze_tasks(scenes, cap_s, systems=FREEZING):
    """The tasks of part 3 for ``scenes`` ((builder name, params) pairs), scene-major."""
    return [
        FreezeTask(name, dict(params), system, cap_s)
        for name, params in scenes
        for system in systems
    ]
