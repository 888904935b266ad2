"""Figure "fig_time_to_rest" (figure 6): steps until a scene is fully frozen/asleep, per system.

Question: how soon does each freezing system stop solving a scene that comes to rest, and which
scenes does it never freeze whole? Freezing pays only from that step on (figure 4 times the
steady state after it).

Systems: sim-sleep (island sleep, 0.5 s timer), sim-paper (the seed's state machine), sim-extended
(ours), pymunk-sleep (Chipmunk, 0.5 s timer) and pybullet-sleep (Bullet, fixed 2 s deactivation
time). Scenes (sim/scenes.py): rest_row(50), stack(5), stack(10), pyramid(10), pyramid(20),
drop(30, seed 0..4) (30 random convex polygons dropped on the floor), seed_fig1 (a box on the
floor, one tilted on its corner, one in the air), seed_fig2 (a box falling on a box), seed_fig3
(a box sliding off a box).

Method (study.protocols.freeze_run, bench_freeze's part 3): each (scene, system) run is
stepped one step at a time, dt 1/60 s, until every body is frozen/asleep (no work is done for it:
sim's ``World.frozen``, out of the awake list; the peers' ``asleep``) or the cap of 30 s (1800
steps). A run that does not get there is kept, not dropped: NaN steps, flag "never", with the
number still awake at the cap (``n_awake_at_end``). A run that froze is stepped 1 s more and the
awake count then is recorded (a freeze that does not hold). Also recorded: the largest distance a
body moved (m), and for sim the step at which no body was FREE any more (``steps_to_all_not_free``:
under paper a pivoting or sliding body leaves FREE but stays awake). The runs are independent and
untimed, so they go to the local process pool (study/executor.py). Each engine at its own
default solver settings (study.peers.DEFAULT_ITERATIONS): sim its soft step with 4 substeps
per step and 1 biased + 1 relax sweep per substep, pymunk 10 iterations per step, pybullet 50; slop
(sim) 0.005 m, a cap that scales down with small bodies, and pymunk's collision_slop matched to each
scene's smallest body (``study.common.comparable_slop``; each scene's in the metadata's
``scenes``); every system's full settings (``runner.settings``, on a probe scene) are in the
metadata's ``system_settings``.

Also, for sim-extended on every scene (``certificate_cost``, timed here after compilation): how
often the rest certificate runs and what it costs, part "certificate": metrics certificates (tried
in all), steps_certifying (steps that tried any), steps_run, freeze_after_per_certificate (us: the
rest-test stage's time in the steps that certified, per certificate: an upper bound; the median
over CERTIFICATE_REPEATS whole runs of the scene, the same run each time). In the first
run, what the scene waits for once it is still: from the first step in which no awake body is
"moving" (``World.why_awake``: none as fast as rest_speed; metric still_from_step, NaN if never)
until every body is frozen, the awake body-steps by the reason the rest test gave
(waiting_<reason>, body-steps, one per reason of ``sim.World.AWAKE_REASONS``).

And how long the reference itself moves (``reference_motion``, part "reference"): each scene
run with freezing off to the cap, under each freezing system's reference (``REFERENCE_SYSTEMS``:
sim-off, and each peer with its sleeping off, since a peer's sleep freezes what *its* solver
moves, not sim's), and for each speed in ``REFERENCE_SPEEDS`` the last step at which its fastest
body moved at least that fast (|v| + |w| r, r the body's largest vertex distance from its centre
of mass, the measure of extended's rest test; metric ``moving_until_<speed>``, 0 if never, flag
"at cap" when still moving at the cap). A system that freezes a whole pile before its reference
stops moving has frozen motion (or a pile that took another path, since piles are chaotic): so
this is how soon a pile *can* be frozen whole without freezing what the engine's solver still
moves. The runs are untimed and go to the process pool.

And the same piles over more seeds (``SAMPLE``, part "seed_sample", sim-sleep and sim-extended
only, the two rest rules of one solver): piles are chaotic, and the median of five seeds moves by
tens of steps with any change to the solver (a step's rounding sends a body another way), so the
figure's five piles are checked against drop(30) seeds 0-99, run exactly as above (the first five
are the figure's piles again). --quick: drop(10) seeds 0-3.

And without sim's presolve (part "without_presolve"; ``WITHOUT_PRESOLVE``): sim's presolve
(``World(initial_iterations=...)``, on by default) solves the start pose's contact impulses before
step 1, so a scene placed at rest starts in equilibrium; no peer has one, and a rest test then
finds the scene at rest from its first step. So the scenes with bodies placed in contact (every
scene but the piles, which start in the air) run again under sim-sleep, sim-paper and
sim-extended with ``initial_iterations=0``, named "sim-sleep (no presolve)" etc.
(``study.systems.NO_PRESOLVE``), exactly as above: the advantage only sim has, reported apart.

Columns (long form, bench_freeze's): part ("time_to_freeze", "seed_sample", "certificate",
"reference" or "without_presolve"),
scene, system,
bodies, n_awake,
n_frozen (at the freeze, or at the cap), metric (steps_to_all_frozen, time_to_all_frozen,
n_awake_at_end, n_awake_1s_after, max_displacement, cap_steps; sim also steps_to_all_not_free,
n_not_free_at_end), value, unit, flag.

    python -m experiments.fig_time_to_rest [--quick]
writes results/data/fig_time_to_rest.csv and fig_time_to_rest.json. --quick: rest_row(50),
stack(5), pyramid(5), drop(15, seed 75), seed_fig1..3, cap 5 s.
"""

import math

import numpy as np
import pandas as pd

import sim
from study.common import DT, FROZEN_MEANS, SLOP, build, compile_kernels, entry, label
from study.executor import run_tasks
from study.protocols import FREEZE_HOLD_S, FREEZING, freeze_run, freeze_tasks, long_row
from study.peers import engine_of
from study.systems import NO_PRESOLVE_SETTINGS, REFERENCE, get, no_presolve

NAME = "fig_time_to_rest"
SYSTEMS = FREEZING
#: the seed sample's systems (see the module's docstring)
SAMPLE_SYSTEMS = ("sim-sleep", "sim-extended")
SEED_FIGS = (("seed_fig1", {}), ("seed_fig2", {}), ("seed_fig3", {}))
#: the sim systems again without their presolve, on the scenes placed at rest (module docstring)
WITHOUT_PRESOLVE = tuple(no_presolve(s) for s in SYSTEMS if engine_of(s) == "sim")
#: builders whose scenes start in the air (no contact for a presolve to solve)
DROPPED = ("drop",)
#: whole runs per scene timing the certificate (``certificate_cost``: the median is reported)
CERTIFICATE_REPEATS = 5
#: m/s: sleep's sleep_speed, extended's rest_speed, and a creep (``reference_motion``)
REFERENCE_SPEEDS = (0.05, 0.02, 0.001)
#: the references of the freezing systems, each engine with nothing frozen: sim-off and the
#: peers with their sleeping off (``reference_motion``)
REFERENCE_SYSTEMS = tuple(dict.fromkeys(REFERENCE[s] for s in SYSTEMS))

FULL = {
    "scenes": (
        ("rest_row", {"n": 50}),
        ("stack", {"height": 5}),
        ("stack", {"height": 10}),
        ("pyramid", {"base": 10}),
        ("pyramid", {"base": 20}),
        *(("drop", {"n": 30, "seed": seed}) for seed in range(5)),
    )
    + SEED_FIGS,
    "cap_s": 30.0,
    "sample": {"n": 30, "seeds": 100},
}
QUICK = {
    "scenes": (
        ("rest_row", {"n": 50}),
        ("stack", {"height": 5}),
        ("pyramid", {"base": 5}),
        # a pile that keeps a body awake (uncertified) for 30 s: what the quick run's "waiting"
        # numbers need. drop(15, seed 75) keeps body 12 (253 g), on one corner on the floor and
        # leaning on the bin's wall with that contact's friction at 91% of its limit (since a body
        # against an immovable one keeps its own contact anchor, 2026-12-07, after which seed 37
        # froze whole). Before: drop(15, seed 37) kept body 13 (206 g), on two points of body 9 with
        # 99% of its load on one: its centre of pressure at the edge of its support, which the tip
        # margin refuses (since extended's fixes of 2026-12, after which drop(15, seed 11) froze
        # whole). Before that: drop(15, seed 11) kept body 12: on one corner on the floor, leaning
        # on the bin's wall with that contact's friction at its limit (since a lane's two points are
        # one complementarity problem, soft_step.batches.two_row_impulses, every drop(10) pile of
        # seeds 0-59 freezes whole within 5 s). Before that drop(10, seed 21) kept body 4 (since a
        # two-point manifold on an immovable body carries its load's split at once); from the
        # corner contacts (geometry._closest_points) to that, seed 10 kept body 9; from the deep
        # sweeps to them every drop(10) pile of seeds 0-59 froze whole within 5 s and drop(15, seed
        # 11) kept body 12; before the deep sweeps drop(10, seed 10) kept body 4
        ("drop", {"n": 15, "seed": 75}),
    )
    + SEED_FIGS,
    "cap_s": 5.0,
    "sample": {"n": 10, "seeds": 4},
}


def run(config, args):
    # compiled here once, so the pool's workers load the kernels from Numba's cache
    compile_kernels()
    tasks = freeze_tasks(config["scenes"], config["cap_s"], SYSTEMS)
    rows = [row for rows in run_tasks(freeze_run, tasks, desc=f"{NAME} runs") for row in rows]
    sample = config["sample"]
    piles = [("drop", {"n": sample["n"], "seed": seed}) for seed in range(sample["seeds"])]
    tasks = freeze_tasks(piles, config["cap_s"], SAMPLE_SYSTEMS)
    rows += [
        {**row, "part": "seed_sample"}
        for rows in run_tasks(freeze_run, tasks, desc=f"{NAME} seed sample")
        for row in rows
    ]
    placed = [(name, params) for name, params in config["scenes"] if name not in DROPPED]
    tasks = freeze_tasks(placed, config["cap_s"], WITHOUT_PRESOLVE)
    rows += [
        {**row, "part": "without_presolve"}
        for rows in run_tasks(freeze_run, tasks, desc=f"{NAME} without presolve")
        for row in rows
    ]
    scenes = [sim.scenes.BUILDERS[name](**params) for name, params in config["scenes"]]
    rows += [row for scene in scenes for row in certificate_cost(scene, config["cap_s"])]
    tasks = [
        (name, params, config["cap_s"], system)
        for name, params in config["scenes"]
        for system in REFERENCE_SYSTEMS
    ]
    rows += [
        row for rows in run_tasks(_reference_task, tasks, desc=f"{NAME} references") for row in rows
    ]
    settings = {}
    probe = sim.scenes.single_box()
    for system in SYSTEMS:
        with build(system, probe) as r:
            settings[system] = r.settings
    parameters = {
        "dt": DT,
        "slop": SLOP,
        "cap_steps": int(round(config["cap_s"] / DT)),
        "freeze_hold_s": FREEZE_HOLD_S,
        "systems": SYSTEMS,
        "frozen_means": FROZEN_MEANS,
        "reference_speeds_m_per_s": REFERENCE_SPEEDS,
        "reference_systems": REFERENCE_SYSTEMS,
        "certificate_repeats": CERTIFICATE_REPEATS,
        # the sample's piles are run but not returned as scenes: their seeds are named here so
        # the record's seed holds them (study.metadata.collect adds the scenes' own)
        "seed": list(range(sample["seeds"])),
        "seed_sample": {
            "scene": "drop",
            **sample,
            "seed_list": list(range(sample["seeds"])),  # the seeds, named (not implied by a count)
            "systems": SAMPLE_SYSTEMS,
        },
        "system_settings": settings,
        "without_presolve": {
            "systems": WITHOUT_PRESOLVE,
            "settings": NO_PRESOLVE_SETTINGS,
            "scenes": [label(sim.scenes.BUILDERS[n](**p)) for n, p in placed],
        },
    }
    return pd.DataFrame(rows), scenes, parameters


def certificate_cost(scene, cap_s, repeats=None):
    """What extended's rest certificate (sim/freeze/certificate.py) costs on ``scene``: stepped
    with every stage timed until every body is frozen (or the cap), the certificates tried
    (one per candidate body per step), the steps that tried any, and the time of the rest test
    and freezing stage (``freeze_after``) in those steps per certificate: an upper bound on one
    certificate's cost, since the stage also runs the cheap gates and freezes the bodies. The run
    is deterministic, so it is repeated ``repeats`` times whole (default CERTIFICATE_REPEATS; the
    same steps and certificates each time) and the stage's time is the median over the repeats.
    In this process, after compilation (the kernels are compiled before)."""
    repeats = CERTIFICATE_REPEATS if repeats is None else repeats
    cap = int(round(cap_s / DT))
    still_from = math.nan  # the first step with no awake body moving
    waiting = dict.fromkeys(sim.World.AWAKE_REASONS, 0)  # body-steps from then on, by reason
    times = []
    for repeat in range(repeats):
        world = sim.World(scene, freeze="extended")
        stage_ms = 0.0
        busy = 0
        tried = 0
        while world.step_count < cap and world.n_awake > 0:
            ms = world.profile(1)["freeze_after"]
            now = world.inspect().certificates
            if now > tried:  # a step that certified: its rest-test stage counts
                busy += 1
                stage_ms += ms
            tried = now
            if repeat > 0:
                continue  # the reasons are the first run's (the runs are the same)
            reasons = world.why_awake()
            if math.isnan(still_from) and not (reasons == "moving").any():
                still_from = world.step_count
            if not math.isnan(still_from):
                for reason in reasons[reasons != ""]:
                    waiting[reason] += 1
        times.append(stage_ms)
    stage_ms = float(np.median(times))
    common = {
        "part": "certificate",
        "scene": label(scene),
        "system": "sim-extended",
        "bodies": len(scene.bodies),
        "n_aw": world.n_awake,
        "n_fr": len(scene.bodies) - world.n_awake,
    }
    per = 1e3 * stage_ms / tried if tried else float("nan")
    return [
        long_row(**common, metric="certificates", value=tried, unit="count"),
        long_row(**common, metric="steps_certifying", value=busy, unit="steps"),
        long_row(**common, metric="steps_run", value=world.step_count, unit="steps"),
        long_row(**common, metric="freeze_after_per_certificate", value=per, unit="us"),
        long_row(**common, metric="still_from_step", value=still_from, unit="steps"),
    ] + [
        long_row(**common, metric=f"waiting_{reason}", value=n, unit="body-steps")
        for reason, n in waiting.items()
    ]


def _reference_task(task):
    """``reference_motion`` of one (builder name, params, cap_s, system) task."""
    name, params, cap_s, system = task
    return reference_motion(sim.scenes.BUILDERS[name](**params), cap_s, system=system)


def reach(scene):
    """(N,) m: each body's largest vertex distance from its centre of mass (from sim's World,
    which places each body's centre of mass: the same geometry every engine is given)."""
    world = sim.World(scene, initial_iterations=0)
    return np.array(
        [
            np.linalg.norm(world.vertices(i) - world.positions[i], axis=1).max()
            for i in range(world.n_bodies)
        ]
    )


def reference_motion(scene, cap_s, speeds=REFERENCE_SPEEDS, system="sim-off"):
    """How long ``scene`` moves with freezing off under ``system`` (a system with nothing frozen:
    sim-off, or a peer with its sleeping off; the study's runner at its comparable settings):
    stepped to the cap, for each speed in ``speeds`` (m/s) the last step at which its fastest
    body's speed |v| + |w| r (r: the body's largest vertex distance from its centre of mass, m;
    ``reach``) was at least that (0 if never; flag "at cap" if that was the cap's step). Rows of
    part "reference"."""
    if get(system).freezes:  # (get: a clear error for a name that is no system)
        raise ValueError(
            f"reference_motion: {system!r} freezes bodies; the reference runs are the systems "
            f"with nothing frozen: {', '.join(REFERENCE_SYSTEMS)}"
        )
    cap = int(round(cap_s / DT))
    last = dict.fromkeys(speeds, 0)
    r = reach(scene)
    with build(system, scene) as runner:
        for step in range(1, cap + 1):
            runner.step(1)
            v = np.linalg.norm(runner.velocities, axis=1)
            fastest = float((v + np.abs(runner.angular_velocities) * r).max())
            for speed in speeds:
                if fastest >= speed:
                    last[speed] = step
    common = {
        "part": "reference",
        "scene": label(scene),
        "system": system,
        "bodies": len(scene.bodies),
        "n_aw": len(scene.bodies),
        "n_fr": 0,
    }
    return [
        long_row(
            **common,
            metric=f"moving_until_{speed:g}",
            value=step,
            unit="steps",
            flag="at cap" if step == cap else "",
        )
        for speed, step in last.items()
    ]


main = entry(NAME, __doc__, FULL, QUICK, run, sweep=True)

if __name__ == "__main__":
    main()
