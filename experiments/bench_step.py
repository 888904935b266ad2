"""Table "bench_step": milliseconds per step, sim (freeze off) vs pymunk, Box2D 2.3 and Box2D v3
(sleeping off), nothing frozen, and where sim's step spends its time.

Question (issue "Solver v2", done when): before any freezing, how fast is sim's solver against an
established engine on the same scenes? Target: sim-off at least 3x pymunk's step rate on
pyramid(40), rest_row(5000) and drop(200) while it settles, in one run; with the phase profile of
sim's step and the number of substeps and iterations used; beyond it, Box2D v3's speed (the
solver sim's soft step follows, the state of the art the issue names). This fixes the baseline
that every later speed-up is measured from, and shows how each system's cost grows with the body
count.

Scenes
- resting: rest_row(n) for n in 10, 100, 1000, 5000 (independent boxes on the floor: contacts with
  the floor only) and pyramid(base) for base in 10, 20, 40 (stacked boxes: coupled contacts).
- settling: drop(200), random convex polygons falling into a walled bin, timed over the first
  WINDOW steps (240 = 4 s: they fall, collide and pile up), the part of a run where every body
  moves and contacts come and go. Each repeat drops its own seed, from 0 on (every system of a
  repeat the same pile; a seed that any system refuses to build is skipped for all, listed in
  ``seeds_skipped``: Box2D's 0.01 m polygon skin refuses a sliver in drop(200) seeds 5, 11 and
  15): a pile is chaotic, and one seed's cost is one path of it (the corner contacts
  cost seed 0 8% a step, seeds 0-4 3.5% on average: seed 0's pile took a path with 249 full
  collisions a step instead of 204), so the median over repeats is a median over piles.
  Labelled "drop(200)", its seeds in ``seeds``.

Systems: each at its own defaults (study.peers.DEFAULT_ITERATIONS), so the comparison is
fair by construction: same scene, same start state, dt 1/60 s, sim's slop 0.005 m (a cap: it
scales down with small bodies) and pymunk's collision_slop matched to the scene's smallest body
(``study.common.comparable_slop``: 0.08-0.23 mm on drop(200); the metadata's ``scenes`` give each
scene's), no sleeping, each system's settings recorded (``system_settings``: from a probe scene).
sim: the soft step with 4 substeps per step, 1 biased solve sweep and
1 relax sweep per substep (8 sweeps over the contacts per step); pymunk: 10 iterations per step;
box2d: 8 velocity and 3 position iterations per step (Box2D 2.3's testbed defaults); box2d3:
Box2D v3 with 4 substeps, 1 biased and 1 relax sweep per substep, as sim (its testbed's
defaults; ``study.peers.box2d3_runner``). Box2D v3 is a benchmark-only system
(``study.systems.BENCH_ONLY``): timed here, compared on outcomes nowhere. Its build (the pyb2d3
wheel) is SSE2 (128-bit: 4 float32 contacts per instruction), one thread, where sim's kernels
are compiled for the machine they run on (256-bit packed instructions here, 4 float64 contacts
per instruction; ``bench_kernels``): wider registers that Box2D v3 compiled for AVX2 would take
too; ``system_settings`` records its build (``simd``).
One variant is timed on the settling scene beside them (``SETTLING_VARIANTS``), reported apart on
its own rows, never instead: "sim-off (no landing sweeps)", sim-off with ``impact_iterations=0``.
The landing sweeps (8 more biased sweeps with friction per substep around a contact approaching
faster than 1 m/s) are accuracy work no peer does: without them sim's step sweeps its contacts as
often as Box2D v3's does (4 substeps, one biased and one relax sweep each; only sim's mass-ratio and
deep contacts still get their few more; the sweeps themselves differ, docs/ARCHITECTURE.md section
2.3), at a landing error of centimetres instead of under a millimetre (fig_tradeoff's
impact_iterations sweep). So the row says how much of sim's time on the pile is that work, and how
sim's step compares with Box2D v3's at the same number of sweeps. The column ``impact_iterations``
says which row ran with them.
The columns ``substeps``, ``iterations`` and ``contact_sweeps_per_step``
(``study.peers.solver_summary``) say so on every row; the metadata holds every setting of
both (``system_settings``).

Method (docs/ARCHITECTURE.md §5): one throwaway sim World compiles the Numba kernels first (and runs
one profiled step, so profiling compiles nothing either).
- resting scenes: each system is built, then WARMUP_STEPS untimed steps; then R repeats of K steps
  each, timed with time.perf_counter and the garbage collector paused, round-robin over the
  systems (order reversed every other repeat) so that machine noise hits both alike.
- settling scene: every repeat builds every system afresh on that repeat's seed (building is not
  timed: sim's includes its initial-impulse solve) and times the same window, steps 1..WINDOW, in
  one call per system, interleaved as above.
Reported per step: median and min over repeats, ms; on the sim rows (sim-off and its variant, each
its own) the ratio peer/sim of medians (``speedup_vs_pymunk``, ``speedup_vs_box2d``,
``speedup_vs_box2d3``: > 1 means sim is faster).
``max_displacement_m`` (largest distance any body moved from its start) guards resting scenes
against a blow-up or collapse looking fast;
``bodies_in_bin`` (settling scene: bodies between the walls, below their top, at the end of the
window; the fewest over the repeats' piles) guards the drop. ``clamped_piles`` and ``clamps``
(settling scene) say in how many piles, and where first, a body reached its engine's silent
motion clamp (Box2D 2.3: 2 m and pi/2 rad per step; Box2D v3: 400 m/s and pi/4 rad per substep):
Box2D slows such a body without a word, so its pile is no longer the scene's. The Box2D runners
check this only at the end of a ``step`` call, so each timed window is replayed untimed one step
per call (``first_clamp``; the replay must end bit for bit where the timed run did).

Second output, ``bench_step_profile``: sim-off's step by stage (sim.data.STAGES, ``World.profile``),
ms per step, each stage's median over R profiled repeats: on resting scenes R repeats of K steps
after the timed ones (same World), on the drop a fresh World per repeat and seed over the same
window. The
"total" row is the sum of the stages' medians, so the stages add up to it;
``profile_total_ms`` is the median of the repeats' totals. Profiling reads the cycle counter at
every stage boundary, which costs time itself: ``profile_total_ms`` beside the unprofiled median
on the same row shows by how much. Also recorded: what ``World.inspect()``
reports at the end (active contacts, colours, batches, batch fill). This is the "after" profile of
the issue; the "before" one (the previous solver) is quoted from the issue, not recomputed.

    python -m experiments.bench_step [--quick] [--repeats R] [--steps K]
writes results/data/bench_step.csv + .json and results/data/bench_step_profile.csv + .json.
"""

import argparse
import statistics
import time

import numpy as np
import pandas as pd
from tqdm import tqdm

import sim
from study.common import (
    interrupted,
    DT,
    SLOP,
    build,
    data_folder,
    label,
)
from study.cli import first_paragraph, or_default, positive_int
from study.metadata import code_state, collect, write_results
from study.peers import solver_summary
from study.timing import timed
from sim.data import STAGES

NAME = "bench_step"
PROFILE_NAME = "bench_step_profile"
WARMUP_STEPS = 10
TARGET_RATIO = 3.0  # the issue's target: sim-off at least this times pymunk's step rate
#: the settling scene's first seed (see the docstring)
DROP_SEED = 0

FULL = {
    "rest_row": (10, 100, 1000, 5000),
    "pyramid": (10, 20, 40),
    "drop": (200,),
    "window": 240,
    "repeats": 7,
    "steps": 50,
}
QUICK = {
    "rest_row": (10, 100),
    "pyramid": (5, 10),
    "drop": (20,),
    "window": 30,
    "repeats": 3,
    "steps": 10,
}
BUILDERS = {
    "rest_row": sim.scenes.rest_row,
    "pyramid": sim.scenes.pyramid,
    "drop": lambda n, seed=DROP_SEED: sim.scenes.drop(n, seed=seed),
}
PARAM = {"rest_row": "n", "pyramid": "base", "drop": "n"}  # the size parameter reported
SETTLING = ("drop",)  # timed from the start, fresh builds
#: the scenes of the issue's target (label: scene name, size)
TARGETS = (("pyramid", 40), ("rest_row", 5000), ("drop", 200))

#: Systems timed, by their study.peers name, each at its own default settings.
SYSTEMS = ("sim-off", "pymunk", "box2d", "box2d3")
#: Variants timed on the settling scene only, beside the systems: name -> (the runner's system, the
#: settings that make the variant). sim's landing sweeps (``impact_iterations``, 8 more biased
#: sweeps with friction per substep around a contact that approaches faster than 1 m/s) are accuracy
#: work that no peer does, Box2D v3 included: without them sim sweeps its contacts as often as Box2D
#: v3 does, and its landing ends centimetres from its rest pose instead of under a millimetre
#: (fig_tradeoff's impact_iterations sweep). Reported apart, never instead: the study's sim-off
#: keeps them. On a resting scene they cost one comparison per lane, so they are timed where they
#: work only.
SETTLING_VARIANTS = {"sim-off (no landing sweeps)": ("sim-off", {"impact_iterations": 0})}
#: the rows that carry the speed-up columns: sim-off and its variants
SIM_ROWS = ("sim-off", *SETTLING_VARIANTS)
SETTLING_SYSTEMS = SYSTEMS + tuple(SETTLING_VARIANTS)


def build_system(system, scene):
    """The runner of ``system`` (a system or a settling variant) on ``scene``."""
    base, settings = SETTLING_VARIANTS.get(system, (system, {}))
    return build(base, scene, **settings)


def max_displacement(runner, start):
    return float(np.hypot(*(runner.positions - start).T).max())


def bodies_in_bin(scene, runner):
    """drop: bodies whose centre is between the two walls and below their top, m."""
    left, right = scene.static_bodies[0], scene.static_bodies[1]
    top = float(left.vertices[:, 1].max() + left.position[1])
    x, y = runner.positions.T
    inside = (x > left.position[0]) & (x < right.position[0]) & (y < top) & (y > 0.0)
    return int(np.count_nonzero(inside))


def _inspection(world):
    i = world.inspect()
    return {
        "contacts": i.n_active,
        "colours": i.n_colours,
        "batches": i.n_batches,
        "batch_fill": i.batch_fill,
    }


def _profile_rows(scene, profiles, unprofiled_ms, steps, inspection, settings):
    """Long-format rows of the profile table: one per stage, plus "total"."""
    base = {
        "scene": scene.name,
        "param": scene.params[PARAM[scene.name]],
        "label": label(scene),
        "bodies": len(scene.bodies),
        "system": "sim-off",
        **solver_summary(settings),
        "repeats": len(profiles),
        "steps_per_repeat": steps,
        "ms_per_step_unprofiled": unprofiled_ms,
        **inspection,
    }
    # Each stage is its own median over the repeats, and the "total" row is their sum, so the
    # table adds up by construction. The median of the repeats' totals is a different statistic
    # (a median of sums is not the sum of medians: on a quick run they differed by 21 %), kept
    # beside it as profile_total_ms, the profiled step as measured.
    medians = {
        stage: statistics.median(p[stage] for p in profiles)
        for stage in profiles[0]
        if stage != "total"
    }
    medians["total"] = sum(medians.values())
    measured = statistics.median(p["total"] for p in profiles)
    return [
        {
            **base,
            "stage": stage,
            "ms_per_step": ms,
            "share_of_total": ms / medians["total"] if medians["total"] > 0 else float("nan"),
            "profile_total_ms": measured,
        }
        for stage, ms in medians.items()
    ]


def _row(scene, runner, per_step_ms, steps, build_s, mode, extra, system=None):
    return {
        "scene": scene.name,
        "param": scene.params[PARAM[scene.name]],
        "label": label(scene),
        "bodies": len(scene.bodies),
        "system": system or runner.name,
        # sim's landing sweeps per substep (the settling variant runs without them; NaN: a peer)
        "impact_iterations": runner.settings.get("impact_iterations", np.nan),
        "mode": mode,
        **solver_summary(runner.settings),
        "ms_per_step_median": statistics.median(per_step_ms),
        "ms_per_step_min": min(per_step_ms),
        "repeats": len(per_step_ms),
        "steps_per_repeat": steps,
        "build_s": build_s,
        **extra,
    }


def bench_resting(scene, repeats, steps, progress=None):
    """Time every system on a resting ``scene`` (warm-up, then interleaved repeats); then profile
    sim's World. Returns (rows, profile rows)."""
    runners, starts, build_s = [], [], []
    for name in SYSTEMS:
        t0 = time.perf_counter()
        runner = build(name, scene)
        build_s.append(time.perf_counter() - t0)
        starts.append(runner.positions)
        runner.step(WARMUP_STEPS)  # first steps excluded (contacts, caches)
        runners.append(runner)
    times = [[] for _ in runners]
    moved = [0.0 for _ in runners]
    order = list(range(len(runners)))
    for r in range(repeats):
        for k in order if r % 2 == 0 else order[::-1]:
            times[k].append(1e3 * timed(runners[k], steps) / steps)
            moved[k] = max(moved[k], max_displacement(runners[k], starts[k]))
            if progress is not None:
                progress.update()
    world = runners[SYSTEMS.index("sim-off")].world
    inspection = _inspection(world)
    profiles = [world.profile(steps) for _ in range(repeats)]
    rows = [
        _row(
            scene,
            runner,
            times[k],
            steps,
            build_s[k],
            "resting",
            {
                "max_displacement_m": moved[k],
                "bodies_in_bin": np.nan,
                "clamped_piles": np.nan,  # checked on the settling scene only
                "clamps": "",
                **(inspection if runner.name == "sim-off" else {}),
            },
        )
        for k, runner in enumerate(runners)
    ]
    sim_k = SYSTEMS.index("sim-off")
    return rows, _profile_rows(
        scene, profiles, statistics.median(times[sim_k]), steps, inspection, runners[sim_k].settings
    )


def build_all(scene):
    """Every system and settling variant built on ``scene`` ({system: runner, build seconds}), or
    None when one of them refuses it (ValueError: Box2D's polygon skin refuses a sliver in some
    piles); then none is left open."""
    runners, build_s = {}, {}
    try:
        for system in SETTLING_SYSTEMS:
            t0 = time.perf_counter()
            runners[system] = build_system(system, scene)
            build_s[system] = time.perf_counter() - t0
    except ValueError:
        for runner in runners.values():
            runner.close()
        return None
    return runners, build_s


def first_clamp(system, scene, window, timed_runner):
    """Where a run of ``system`` on ``scene`` first reached its engine's silent motion clamp in
    steps 1..``window``: "seed s, <the runner's message>", or "" when it never did. A runner that
    checks its clamps only at the end of a ``step`` call (``checks_clamps_per_call``: the Box2D
    runners, whose per-body reads through Python cost as much as their steps) cannot see a
    clamp inside the timed window's one call: Box2D 2.3 spun a body of drop(200) seed 4 at its
    limit at step 84, unseen by the 240-step call. So the window is replayed, untimed, one step
    per call in a fresh build. The engines are deterministic: the replay must end where
    ``timed_runner`` ended, or the bench stops (it would not be the run that was timed)."""
    clamp = ""
    with build_system(system, scene) as runner:
        for _ in range(window):
            try:
                runner.step(1)
            except RuntimeError as exc:  # the step was taken; only the check raised
                clamp = clamp or f"seed {scene.params['seed']}, {exc}"
        if not (
            np.array_equal(runner.positions, timed_runner.positions)
            and np.array_equal(runner.angles, timed_runner.angles)
        ):
            raise RuntimeError(
                f"bench_step: {system}'s replay of {label(scene)} one step per call did not end "
                f"where its timed run did: the clamp check would not describe the timed run"
            )
    return clamp


def bench_settling(name, size, repeats, window, progress=None):
    """Time steps 1..``window`` of fresh systems on the settling scene ``name``(``size``), one
    seed per repeat from DROP_SEED on, interleaved; a seed that any system refuses to build is
    skipped for all. Then profile the same windows in fresh sim Worlds. Returns (rows, profile
    rows, the scenes used). The settling variants (SETTLING_VARIANTS) are timed with the systems,
    interleaved."""
    systems = SETTLING_SYSTEMS
    times = {system: [] for system in systems}
    build_s = {system: [] for system in systems}
    in_bin = {system: [] for system in systems}
    clamps = {system: [] for system in systems}
    last = {}
    scenes, skipped = [], []
    seed = DROP_SEED
    while len(scenes) < repeats:
        scene = BUILDERS[name](size, seed=seed)
        built = build_all(scene)
        if built is None:
            skipped.append(seed)
            seed += 1
            if len(skipped) > 10 * repeats:
                raise ValueError(
                    f"bench_step: some system refuses {len(skipped)} seeds of {name}({size}) "
                    f"({skipped[:5]}...); only {len(scenes)} of {repeats} were built by all"
                )
            continue
        runners, seconds = built
        r = len(scenes)
        scenes.append(scene)
        seed += 1
        for system in systems if r % 2 == 0 else systems[::-1]:
            runner = runners[system]
            build_s[system].append(seconds[system])
            times[system].append(1e3 * timed(runner, window) / window)
            in_bin[system].append(bodies_in_bin(scene, runner))
            if last.get(system) is not None:
                last[system].close()
            last[system] = runner
            if progress is not None:
                progress.update()
        for system in systems:  # after the repeat's timings, untimed
            if getattr(runners[system], "checks_clamps_per_call", False):
                clamp = first_clamp(system, scene, window, runners[system])
                if clamp:
                    clamps[system].append(clamp)
    inspection = _inspection(last["sim-off"].world)
    profiles = []
    for scene in scenes:
        runner = build("sim-off", scene)
        profiles.append(runner.world.profile(window))
    named = {
        "label": f"{name}({size})",
        "seeds": " ".join(str(s.params["seed"]) for s in scenes),
        "seeds_skipped": " ".join(map(str, skipped)),
    }
    rows = []
    for system in systems:
        runner = last[system]
        rows.append(
            _row(
                scenes[0],
                runner,
                times[system],
                window,
                statistics.median(build_s[system]),
                f"settling (fresh build, one seed per repeat, steps 1..{window})",
                {
                    "max_displacement_m": np.nan,
                    # the fewest of any repeat's pile: every pile stayed in its bin
                    "bodies_in_bin": min(in_bin[system]),
                    # piles in which a body reached the engine's silent clamp (first_clamp)
                    "clamped_piles": len(clamps[system]),
                    "clamps": "; ".join(clamps[system]),
                    **named,
                    **(inspection if system == "sim-off" else {}),
                },
                system=system,
            )
        )
        runner.close()
    profile = _profile_rows(
        scenes[0],
        profiles,
        statistics.median(times["sim-off"]),
        window,
        inspection,
        last["sim-off"].settings,
    )
    return rows, [{**row, **named} for row in profile], scenes


def compile_kernels():
    """Compile (or load from Numba's cache) the kernels a freeze-off World runs, profiled or not,
    so that no timing includes JIT compilation."""
    world = sim.World(sim.scenes.stack(2), dt=DT, slop=SLOP)
    world.step(2)
    world.profile(1)


def run(config, repeats, steps):
    """Benchmark every scene of ``config``; returns (table, profile table, scenes)."""
    compile_kernels()
    sizes = [(name, p) for name in ("rest_row", "pyramid", "drop") for p in config[name]]
    rows, profile_rows, scenes = [], [], []
    runs = sum(len(SETTLING_SYSTEMS if name in SETTLING else SYSTEMS) for name, _ in sizes)
    with tqdm(total=runs * repeats, desc=NAME, unit="repeat") as bar:
        for name, p in sizes:
            bar.set_postfix_str(f"{name}({p})")
            if name in SETTLING:
                r, prof, used = bench_settling(name, p, repeats, config["window"], bar)
            else:
                used = [BUILDERS[name](p)]
                r, prof = bench_resting(used[0], repeats, steps, bar)
            rows += r
            profile_rows += prof
            scenes += used
    table = pd.DataFrame(rows)
    # ratio of medians, on the sim rows (sim-off and its variants, each its own): how many times
    # faster the row is than the peer on the same scene
    med = table.pivot_table(index=["scene", "param"], columns="system", values="ms_per_step_median")
    for peer in SYSTEMS[1:]:
        peer_ms = table.join(med[peer].rename("peer_ms"), on=["scene", "param"])["peer_ms"]
        table[f"speedup_vs_{peer}"] = (peer_ms / table["ms_per_step_median"]).where(
            table["system"].isin(SIM_ROWS)
        )
    return table, pd.DataFrame(profile_rows), scenes


def targets(table):
    """The issue's target on every target scene present: {label: {ratio, met}}."""
    out = {}
    sims = table[table["system"] == "sim-off"]
    for scene, param in TARGETS:
        row = sims[(sims["scene"] == scene) & (sims["param"] == param)]
        if len(row):
            ratio = float(row["speedup_vs_pymunk"].iloc[0])
            out[row["label"].iloc[0]] = {
                "speedup_vs_pymunk": ratio,
                "met": bool(ratio >= TARGET_RATIO),
            }
    return out


def main(argv=None, data_dir=None):
    """Command line entry; ``data_dir`` overrides results/data (tests)."""
    parser = argparse.ArgumentParser(
        prog=f"python -m experiments.{NAME}", description=first_paragraph(__doc__)
    )
    parser.add_argument("--quick", action="store_true", help="small sizes, few repeats (CI)")
    parser.add_argument(
        "--repeats", type=positive_int, default=None, help="timed repeats (default 7, quick 3)"
    )
    parser.add_argument(
        "--steps",
        type=positive_int,
        default=None,
        help="steps per repeat on resting scenes (default 50, quick 10)",
    )
    args = parser.parse_args(argv)
    started = code_state()  # the code that runs (collect says if it changes before the end)
    config = QUICK if args.quick else FULL
    repeats = or_default(args.repeats, config["repeats"])
    steps = or_default(args.steps, config["steps"])

    try:
        table, profile, scenes = run(config, repeats, steps)
    except KeyboardInterrupt:
        raise SystemExit(interrupted(NAME, data_folder(args.quick, data_dir))) from None
    settings = {}
    for name in SETTLING_SYSTEMS:
        with build_system(name, sim.scenes.rest_row(2)) as runner:
            settings[name] = runner.settings
    parameters = {
        "dt": DT,
        "slop": SLOP,
        "warmup_steps": WARMUP_STEPS,
        "repeats": repeats,
        "steps_per_repeat": steps,
        "settle_window_steps": config["window"],
        "drop_seed_first": DROP_SEED,
        "quick": args.quick,
        "sizes": config,
        "systems": list(SYSTEMS),
        # timed on the settling scene only: {name: {system, settings}}
        "settling_variants": {
            name: {"system": base, "settings": dict(extra)}
            for name, (base, extra) in SETTLING_VARIANTS.items()
        },
        "system_settings": settings,
        "solver_summary": {name: solver_summary(s) for name, s in settings.items()},
        "target_ratio": TARGET_RATIO,
        "targets": targets(table),
        "stages": list(STAGES),
    }
    folder = data_folder(args.quick, data_dir)
    # the piles' seeds as timed (one per repeat, from DROP_SEED on, skipping any a system refused:
    # DROP_SEED alone was recorded while seeds 0-4, 6 and 7 ran)
    used = sorted({int(x) for s in table["seeds"].dropna() for x in str(s).split()})
    metadata = collect(scenes, parameters, script=NAME, seed=used or None, started=started)
    csv_path, _ = write_results(NAME, table, metadata, folder=folder)
    profile_path, _ = write_results(
        PROFILE_NAME, profile, {**metadata, "script": NAME, "table": PROFILE_NAME}, folder=folder
    )
    with pd.option_context("display.width", 250, "display.max_columns", 30):
        print(
            table.drop(columns=["mode", "relax_iterations", "build_s"]).to_string(
                index=False, float_format=lambda x: f"{x:.4g}"
            )
        )
        wide = profile.pivot_table(index="stage", columns="label", values="ms_per_step", sort=False)
        print(wide.to_string(float_format=lambda x: f"{x:.4f}"))
    print(f"wrote {csv_path} and {profile_path}")
    return table


if __name__ == "__main__":
    main()
