"""Table "bench_fast_paths": does the solver pay only for what a scene uses?

Question (issue "extremes", model only what a scene requires): which work can the solver skip
when a scene does not need it, and does skipping pay? Each candidate is measured, in this one
process run, and kept only when it saves at least PAYS (5 %) of a step on a scene where it applies.
Everything here goes through sim's public API: ``World(fast_paths=...)``, ``World.profile`` (ms
per step of each stage, ``sim.data.STAGES``) and ``World.inspect()``; every World runs sim's
defaults (soft step, 4 substeps, 1 iteration and 1 relax sweep per substep; recorded in the
metadata).

1. ``friction`` (built, ``World(fast_paths=...)``): batches of frictionless contacts skip their
   friction rows (in the solve and relax sweeps; exact, since those rows would clamp every
   impulse to zero). Scenes: ``columns`` (100 columns of 10 unit boxes, 1000 bodies, so the
   contacts are box-box and box-floor) frictionless and with mu 0.6 (where nothing may change),
   sim-off with fast paths on and off, interleaved repeats; the saving is 1 - on/off of the
   median ms per step. The profile of both says where it comes from (solve + relax stages).
2. ``box_sat`` (built, measured, removed): a separating-axis test specialised to box pairs. With
   the previous solver it saved 2.5-4.9 % of a pyramid(40) step on a quiet machine (two runs at
   commit c38ae49), under the rule, so it is no longer in sim. Measured before: the general SAT
   alone on every box pair of a step, timed in a loop over the step's own pairs (an upper bound
   of any SAT saving). That needed sim's internals (the contact store, the world vertices, the
   SAT routine) and cannot be measured with the public API. Measured now: the ``narrowphase``
   stage's share of a pyramid(40) step (every awake contact's SAT, clipping and manifold
   update): still an upper bound of any SAT saving, but a looser one (it contains the clipping
   and the bookkeeping too).
3. ``statics`` (structural): static polygons live in the resting grid with frozen bodies, so a
   scene pays for them only where awake bodies come near. Measured: rest_row(1000) under off with
   no static polygons and with 100 static ledges placed 50 m above the row (never touched).
4. ``rotation`` (not built unless it pays): skipping cos/sin and vertex rotation for bodies that
   do not rotate. Measured before: the geometry update of every awake body alone (sim's
   ``update_geometry``, an internal), as a share of a rest_row(1000) step. Not measurable alone
   with the public API; measured now: the ``broadphase`` stage's share of a rest_row(1000) step,
   which on a resting row is that geometry update (cos/sin, rotated vertices and normals, the
   bounding box) plus the test that no fat box moved (no pairs to find): a looser upper bound.
   Rotation in the substeps' position integration (one cos/sin pair per body per substep, in the
   ``integrate`` stage, shared with the translation) is not counted.

5. ``quiet`` (built, ``World(fast_paths=...)``): once a step has begun and ended with every body
   frozen, the steps after it only count (exact: nothing is awake, so the step would change
   nothing). Scene: ``pyramid`` under sim-extended, stepped one step at a time until every body
   is frozen (pyramid(40) takes longer than the warm-up), then timed in calls of ``quiet_steps``
   steps (300, fig_tradeoff's run) with fast paths on and with friction only, interleaved
   repeats; the saving is 1 - on/off of the median ms per step. Each call pays the World's call
   overhead, so the saving grows with the steps per call.

Shares from a profile are of the profiled step (``World.profile`` reads the cycle counter at every
stage boundary, which costs a little); the ms columns of those rows are the profiled ms per step.

    python -m experiments.bench_fast_paths [--quick]
"""

import math
import statistics

import pandas as pd
from tqdm import tqdm

import sim
from study.common import DT, SLOP, compile_kernels, entry, label, step_until_frozen
from study.peers import make_runner
from study.timing import interleaved

NAME = "bench_fast_paths"
PAYS = 0.05  # a fast path is kept when it saves at least this share of a step
QUIET_FREEZE_CAP = 600  # steps: part 5 steps its pyramid until frozen, at most this many
WARMUP_STEPS = 10
FULL = {
    "columns": (100, 10),
    "pyramid": 40,
    "row": 1000,
    "statics": 100,
    "steps": 30,
    "quiet_steps": 300,
    "repeats": 9,
}
QUICK = {
    "columns": (10, 5),
    "pyramid": 10,
    "row": 100,
    "statics": 10,
    "steps": 5,
    "quiet_steps": 30,
    "repeats": 3,
}


def columns(n_columns, height, mu):
    """``n_columns`` columns of ``height`` unit boxes, 0.5 m apart, friction ``mu`` (floor too)."""
    bodies = [
        sim.Body.box(1.0, 1.0, position=(1.5 * c, 0.5 + i), friction=mu)
        for c in range(n_columns)
        for i in range(height)
    ]
    return sim.Scene(
        bodies=bodies,
        floor_friction=mu,
        name="columns",
        params={"columns": n_columns, "height": height, "friction": mu},
    )


def with_ledges(scene, n, height=50.0):
    """``scene`` plus ``n`` static 1 x 0.2 m ledges ``height`` m up (never touched)."""
    ledges = [sim.Body.box(1.0, 0.2, position=(2.0 * k, height)) for k in range(n)]
    return sim.Scene(
        bodies=scene.bodies,
        static_bodies=ledges,
        name=scene.name + "+ledges",
        params={**scene.params, "ledges": n, "ledge_height": height},
    )


def warm_runner(scene, system="sim-off", **settings):
    """``system`` (default sim-off) on ``scene`` at the study's dt and slop, warmed up (first
    steps excluded); its World is ``.world``."""
    runner = make_runner(system, scene, dt=DT, slop=SLOP, **settings)
    runner.step(WARMUP_STEPS)
    return runner


def median_profile(w, steps, repeats, bar=None):
    """Median over ``repeats`` of ``w.profile(steps)``: {stage: ms per step, "total": ...}."""
    profiles = []
    for _ in range(repeats):
        profiles.append(w.profile(steps))
        if bar is not None:
            bar.update()
    return {stage: statistics.median(p[stage] for p in profiles) for stage in profiles[0]}


def _row(part, scene, variant, ms, share=math.nan, note=""):
    return {
        "part": part,
        "scene": scene,
        "variant": variant,
        "ms_per_step_median": ms,
        "saving_share_of_step": share,
        "note": note,
    }


def friction(config, repeats, bar):
    rows = []
    for mu in (0.0, 0.6):
        scene = columns(*config["columns"], mu)
        runners = [warm_runner(scene, fast_paths=fast) for fast in (False, True)]
        times = interleaved(runners, [config["steps"]] * 2, repeats, bar)
        off, on = (statistics.median(t) for t in times)
        profiles = [median_profile(r.world, config["steps"], repeats) for r in runners]
        rows_solved = [p["solve"] + p["relax"] for p in profiles]
        contacts = runners[1].world.inspect().n_active
        name = f"columns({config['columns'][0]}x{config['columns'][1]}, mu={mu})"
        rows.append(
            _row(
                "friction",
                name,
                "fast_paths=False",
                off,
                note=f"{contacts} contacts; solve+relax {rows_solved[0]:.4g} ms (profiled)",
            )
        )
        rows.append(
            _row(
                "friction",
                name,
                "fast_paths=True",
                on,
                1.0 - on / off,
                f"solve+relax {rows_solved[1]:.4g} ms (profiled)",
            )
        )
    return rows


def profile_share(part, scene, stage, config, repeats, bar, note):
    """Rows: a scene's profiled step, and one ``stage``'s share of it (an upper bound)."""
    runner = warm_runner(scene)
    p = median_profile(runner.world, config["steps"], repeats, bar)
    return [
        _row(part, label(scene), "step (profiled)", p["total"]),
        _row(part, label(scene), f"{stage} stage", p[stage], p[stage] / p["total"], note),
    ]


def box_sat(config, repeats, bar):
    scene = sim.scenes.pyramid(config["pyramid"])
    return profile_share(
        "box_sat",
        scene,
        "narrowphase",
        config,
        repeats,
        bar,
        "upper bound of any SAT saving (SAT, clipping and manifold update)",
    )


def statics(config, repeats, bar):
    base = sim.scenes.rest_row(config["row"])
    runners = [warm_runner(s) for s in (base, with_ledges(base, config["statics"]))]
    times = interleaved(runners, [config["steps"]] * 2, repeats, bar)
    without, with_ = (statistics.median(t) for t in times)
    name = label(base)
    return [
        _row("statics", name, "no static polygons", without),
        _row(
            "statics",
            name,
            f"{config['statics']} static ledges, untouched",
            with_,
            1.0 - with_ / without,
            "negative = the ledges' cost",
        ),
    ]


def rotation(config, repeats, bar):
    scene = sim.scenes.rest_row(config["row"])
    return profile_share(
        "rotation",
        scene,
        "broadphase",
        config,
        repeats,
        bar,
        "upper bound of skipping rotation work (geometry update and refit "
        "test of every awake body)",
    )


def quiet(config, repeats, bar):
    scene = sim.scenes.pyramid(config["pyramid"])
    variants = (("friction",), True)
    runners = [warm_runner(scene, "sim-extended", fast_paths=fast) for fast in variants]
    # timed frozen: a pyramid(40) placed at rest is not yet whole after the warm-up
    froze_at = [step_until_frozen(r, QUIET_FREEZE_CAP) for r in runners]
    frozen = [r.world.n_awake == 0 for r in runners]
    times = interleaved(runners, [config["quiet_steps"]] * 2, repeats, bar)
    off, on = (statistics.median(t) for t in times)
    skipped = runners[1].world.inspect().quiet_steps
    name = f"{label(scene)}, sim-extended, calls of {config['quiet_steps']} steps"
    return [
        _row(
            "quiet",
            name,
            "fast_paths=('friction',)",
            off,
            note=f"every body frozen before the timing: {frozen[0]} (at step {froze_at[0]})",
        ),
        _row(
            "quiet",
            name,
            "fast_paths=True",
            on,
            1.0 - on / off,
            f"every body frozen before the timing: {frozen[1]} (at step {froze_at[1]}); "
            f"{skipped} steps skipped",
        ),
    ]


def verdicts(table):
    """One line per candidate: kept or not, and why (the PAYS rule)."""
    out = []
    f = table[(table["part"] == "friction") & (table["variant"] == "fast_paths=True")]
    frictionless = float(f["saving_share_of_step"].iloc[0])
    frictional = float(f["saving_share_of_step"].iloc[1])
    out.append(
        {
            "candidate": "friction",
            "saving": frictionless,
            "verdict": "kept" if frictionless >= PAYS else "does not pay",
            "detail": f"saves {frictionless:.0%} of a frictionless step; {frictional:+.0%} "
            f"on the frictional scene (noise)",
        }
    )
    bound = float(table[table["part"] == "box_sat"]["saving_share_of_step"].dropna().iloc[0])
    out.append(
        {
            "candidate": "box_sat",
            "saving": bound,
            "verdict": (
                "removed: cannot pay (its bound is under the rule)"
                if bound < PAYS
                else "removed: built, it saved 2.5-4.9 %, under the rule (see "
                "docstring); this bound is looser"
            ),
            "detail": f"upper bound {bound:.1%} of a pyramid step (whole narrowphase)",
        }
    )
    share = float(table[table["part"] == "rotation"]["saving_share_of_step"].dropna().iloc[0])
    out.append(
        {
            "candidate": "rotation",
            "saving": share,
            "verdict": (
                "not built: may pay, the bound is above the rule"
                if share >= PAYS
                else "not built: cannot pay"
            ),
            "detail": f"upper bound {share:.1%} of a step (whole broadphase)",
        }
    )
    q = float(table[table["part"] == "quiet"]["saving_share_of_step"].dropna().iloc[0])
    out.append(
        {
            "candidate": "quiet",
            "saving": q,
            "verdict": "kept" if q >= PAYS else "does not pay",
            "detail": f"saves {q:.0%} of a frozen pyramid's step (calls of many steps)",
        }
    )
    s = float(table[table["part"] == "statics"]["saving_share_of_step"].dropna().iloc[0])
    out.append(
        {
            "candidate": "statics",
            "saving": s,
            "verdict": "structural (resting grid)",
            "detail": f"untouched static polygons change a step by {-s:+.1%}",
        }
    )
    return out


def run(config, args):
    compile_kernels()
    sim.World(sim.scenes.rest_row(2), dt=DT).profile(1)  # the profiled loop, compiled too
    repeats = config["repeats"]
    rows = []
    with tqdm(
        total=2 * (2 * repeats) + repeats + 2 * repeats + repeats + 2 * repeats,
        desc=NAME,
        unit="repeat",
    ) as bar:
        rows += friction(config, repeats, bar)
        rows += box_sat(config, repeats, bar)
        rows += statics(config, repeats, bar)
        rows += rotation(config, repeats, bar)
        rows += quiet(config, repeats, bar)
    table = pd.DataFrame(rows)
    scenes = [
        columns(*config["columns"], 0.0),
        columns(*config["columns"], 0.6),
        sim.scenes.pyramid(config["pyramid"]),
        sim.scenes.rest_row(config["row"]),
        with_ledges(sim.scenes.rest_row(config["row"]), config["statics"]),
    ]
    settings = make_runner("sim-off", sim.scenes.rest_row(2), dt=DT, slop=SLOP).settings
    return (
        table,
        scenes,
        {
            "dt": DT,
            "slop": SLOP,
            "warmup_steps": WARMUP_STEPS,
            "system_settings": {"sim-off": settings},
            "substeps": settings["substeps"],
            "iterations": settings["iterations"],
            "pays": PAYS,
            "verdicts": verdicts(table),
        },
    )


main = entry(NAME, __doc__, FULL, QUICK, run)

if __name__ == "__main__":
    main()
