"""experiments.table_extremes end to end on --quick sizes into a temporary results tree, its
analysis into a temporary paper tree, and the measuring code (rules, overlap, tunnelling) on
cases whose answer is known."""

import json
import math

import numpy as np
import pandas as pd
import pytest

import sim
from analysis import table_extremes as analysis
from study import paths, systems
from experiments import table_extremes as T
from study.common import DT, SYSTEMS
from study.extremes import axes, geometry, rules, runs, scenes
from study.extremes.judge import Judge
from study.extremes.record import COLUMNS, Measurement


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    results = tmp_path_factory.mktemp("results")
    paper = tmp_path_factory.mktemp("paper")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(paths, "RESULTS", results)  # the incremental store goes here
        mp.setattr(paths, "DATA", results / "data")
        mp.setattr(paths, "FIGURES", paper / "figures")
        mp.setattr(paths, "GENERATED", paper / "generated")
        T.main(["--quick"], data_dir=results / "data")
        numbers = analysis.main([])
    table = pd.read_csv(results / "data" / f"{T.NAME}.csv")
    for col in ("reason", "outcome", "ref_outcome", "error", "tunnelled", "chattering", "decision"):
        table[col] = table[col].astype(object).fillna("")  # all-empty reads back as NaN
    meta = json.loads((results / "data" / f"{T.NAME}.json").read_text())
    return table, meta, numbers, results, paper


def _row(table, axis, value, system):
    r = table[
        (table["axis"] == axis) & np.isclose(table["value"], value) & (table["system"] == system)
    ]
    assert len(r) == 1, (axis, value, system)
    return r.iloc[0]


def test_every_cell_once_with_the_columns(quick_run):
    table, meta, _, results, _ = quick_run
    assert list(table.columns) == list(COLUMNS)  # the Row record's fields, in order
    # every applicable (axis, value, system) once: the no-presolve systems on the placed axes
    # only, the sim-only axes for sim only
    expected = {
        (a, float(v), s)
        for a, values in T.QUICK["axes"].items()
        for v in values
        for s in axes.ALL_SYSTEMS
        if axes.applies(a, s)
    }
    assert {s for _, _, s in expected} == set(axes.ALL_SYSTEMS)
    got = list(zip(table["axis"], table["value"].astype(float), table["system"]))
    assert len(got) == len(set(got)) == len(expected)
    assert set(got) == expected
    assert set(table["status"]) <= set(rules.STATUSES)
    # a finished sweep leaves no store behind (nothing left to resume); the store was used
    assert (results / "partial").is_dir()
    assert not list((results / "partial").glob("*.jsonl"))
    assert meta["parameters"]["rules"]["penetration_rel"] == rules.PENETRATION_REL
    # what ran is recorded: sim's iterations are per substep and its substeps are a column
    sim_rows = table[table["system"].str.startswith("sim-") & (table["status"] != "rejected")]
    assert (sim_rows["substeps"] >= 1).all()
    assert table[~table["system"].str.startswith("sim-")]["substeps"].isna().all()
    sub = table[table["axis"] == "substeps"]
    assert (sub["substeps"] == sub["value"]).all()
    it = table[(table["axis"] == "iterations") & (table["status"] != "not run")]
    assert (it["iterations"] == it["value"]).all()
    # the no-presolve runs are sim's four policies with initial_iterations=0, placed axes only
    nop = table[table["system"].isin(systems.NO_PRESOLVE_SYSTEMS)]
    assert set(nop["axis"]) == set(axes.PLACED_AXES) & set(T.QUICK["axes"])
    assert meta["parameters"]["no_presolve"]["settings"] == {"initial_iterations": 0}


def test_marks_follow_the_stated_rules(quick_run):
    table, _, _, _, _ = quick_run
    ran = table[~table["status"].isin(["not run", "rejected"])]
    assert len(ran) > 0
    for r in ran.itertuples():
        if r.status == "stable":
            assert r.reason == "" or r.reason.startswith("reference not valid"), r
            assert r.finite and not r.tunnelled and r.ke_max_rel <= rules.EXPLOSION_FACTOR
            assert r.penetration_rel <= rules.PENETRATION_REL
            assert not (r.drift_rel > rules.DRIFT_REL) and r.energy_growth <= rules.ENERGY_GROWTH
            if r.ref_valid:
                assert r.outcome == r.ref_outcome
        else:
            assert r.reason, r
        if r.tunnelled or not r.finite or r.error:
            assert r.status == "failed", r
    # every executed cell stepped, and timed its steps (indicative, only sanity-checked)
    assert (ran["steps_done"] > 0).all()
    timed = ran[ran["steps_done"] > 1]["ms_per_step"]
    assert timed.map(math.isfinite).all() and (timed > 0).all()


def test_physical_facts(quick_run):
    table, meta, _, _, _ = quick_run
    # every reference is a valid run at the stated solver settings, and a placed resting scene
    # stands in it
    for ref in meta["parameters"]["references"]:
        assert ref["valid"], ref
        assert ref["iterations"] == runs.REF_ITERATIONS, ref
        assert ref["substeps"] >= runs.REF_SUBSTEPS, ref
    for axis in ("mass_light_on_heavy", "size_large", "polygon_vertices", "collinear"):
        for r in table[table["axis"] == axis].itertuples():
            assert r.ref_outcome == "stands", r
    # a light box on heavy ones stands in sim under every policy, with nothing measurable lost,
    # with or without the presolve
    for system in (
        "sim-off",
        "sim-sleep",
        "sim-paper",
        "sim-extended",
    ) + systems.NO_PRESOLVE_SYSTEMS:
        r = _row(table, "mass_light_on_heavy", 0.001, system)
        assert r.status == "stable" and r.outcome == "stands", r
    # sim refuses nothing at 1 cm; a refusal is a ValueError with its message, and only ever
    # sim's step-size check, a builder's range check or what Box2D 2.3 cannot hold (a 1 cm box
    # is thinner than twice its 1 cm polygon skin)
    for system in axes.ALL_SYSTEMS:
        if axes.applies("size_small", system):
            r = _row(table, "size_small", 0.01, system)
            if system.startswith("box2d"):
                assert r.status == "rejected" and "skin" in r.error, r
            else:
                assert r.status != "rejected", r
    for r in table[table["status"] == "rejected"].itertuples():
        assert r.error.startswith("ValueError: ") and r.reason == r.error, r
    # knife edge: offset by a tilt, the reference falls; balanced exactly, it stays
    assert _row(table, "knife_edge", 1e-6, "sim-off").ref_outcome.startswith("falls")
    assert _row(table, "knife_edge", 0.0, "sim-off").ref_outcome == "stays"
    # the wall is either stopped or passed through; passing through is tunnelling. Box2D 2.3
    # refuses a body faster than its per-step motion cap (2 m per step: 120 m/s at 1/60 s)
    for r in table[table["axis"] == "projectile_wall"].itertuples():
        if r.system.startswith("box2d") and r.value > 120:
            assert r.status == "rejected" and "per step" in r.error, r
        else:
            assert r.outcome in ("stopped", "passed"), r
        if r.outcome == "passed":
            assert "tunnelling" in r.reason and r.status == "failed"


def test_impact_threshold_decisions_flip_at_v_star(quick_run):
    table, meta, _, _, _ = quick_run
    thresholds = meta["parameters"]["thresholds"]
    assert set(thresholds) == {"paper", "extended"}
    for t in thresholds.values():
        lo, hi = t["bracket"]
        assert lo < t["v_star"] < hi and (hi - lo) < 1e-9 * t["v_star"]
    for eps in (-1e-6, 1e-6):
        paper = _row(table, "impact_threshold", eps, "sim-paper")
        extended = _row(table, "impact_threshold", eps, "sim-extended")
        assert paper.decision == ("held" if eps < 0 else "bounces")
        assert extended.decision == ("anvil stays frozen" if eps < 0 else "anvil woken")
        for r in (paper, extended):
            assert r.state_changes_max <= rules.MAX_STATE_CHANGES and not r.chattering


def test_analysis_outputs(quick_run):
    table, _, numbers, _, paper = quick_run
    svg = paper / "figures" / f"{analysis.FIGURE}.svg"
    assert svg.exists() and svg.stat().st_size > 20_000
    text = svg.read_text()
    for system in SYSTEMS:
        assert system in text
    for system in systems.NO_PRESOLVE_SYSTEMS:
        assert system in text
    summary = pd.read_csv(paper / "generated" / f"{T.NAME}.csv", keep_default_na=False)
    assert list(summary.columns) == ["axis", "value", *SYSTEMS, *systems.NO_PRESOLVE_SYSTEMS]
    assert len(summary) == len(table.drop_duplicates(["axis", "value"]))
    # not applicable is written as such, never as a mark
    for system in systems.NO_PRESOLVE_SYSTEMS:
        marks = set(summary[system])
        assert analysis.NOT_APPLICABLE in marks and len(marks) > 1
    assert json.loads((paper / "generated" / f"{T.NAME}.json").read_text())[
        "numbers"
    ] == json.loads(json.dumps(numbers))
    # the default systems and the no-presolve ones are counted apart, and every cell once
    nop = numbers["no_presolve"]
    assert set(numbers["counts"]) == set(SYSTEMS)
    assert set(nop["counts"]) == set(systems.NO_PRESOLVE_SYSTEMS)
    assert sum(sum(c.values()) for c in numbers["counts"].values()) == numbers["cells"]
    assert sum(sum(c.values()) for c in nop["counts"].values()) == nop["cells"]
    assert numbers["cells"] + nop["cells"] == len(table)
    assert set(numbers["per_axis"]) == set(T.QUICK["axes"])
    assert set(nop["per_axis"]) == set(axes.PLACED_AXES) & set(T.QUICK["axes"])
    # the headline the study states reads the fair rows on every placed axis, the rest elsewhere
    assert set(numbers["breaks_first"]) == set(numbers["per_axis"])
    for axis, entry in numbers["breaks_first"].items():
        source = nop["per_axis"] if axis in nop["per_axis"] else numbers["per_axis"]
        assert entry["protocol"] == (
            "sim without presolve" if axis in nop["per_axis"] else "as run"
        )
        assert entry["breaks_first"] == source[axis]["breaks_first"], axis
        assert entry["breaks_first_at"] == source[axis]["breaks_first_at"], axis
    # a sim-only axis names nobody as breaking first
    for axis in axes.SIM_ONLY_AXES:
        assert numbers["per_axis"][axis]["breaks_first"] == []
        assert not numbers["per_axis"][axis]["compared"]
    # the first value at which a system breaks is one where it is degraded or failed; without
    # the presolve the same holds, and sim's default systems are swapped for their twins
    for per_axis in (numbers["per_axis"], nop["per_axis"]):
        for axis, entry in per_axis.items():
            for system in entry["breaks_first"]:
                label = entry["first_degraded_or_failed"][system]
                hits = [
                    r
                    for r in table[
                        (table["axis"] == axis) & (table["system"] == system)
                    ].itertuples()
                    if analysis.value_label(axis, r.value) == label
                ]
                assert hits and hits[0].status in ("degraded", "failed")
    for entry in nop["per_axis"].values():
        assert not any(
            s in entry["first_degraded_or_failed"] for s in SYSTEMS if s.startswith("sim-")
        )
    # every refused cell is listed with its message
    assert len(numbers["rejected_cells"]) == int((table["status"] == "rejected").sum())


# ---- the measuring code on known cases (no sweep) ----------------------------------------------
def _result(**kw):
    base = {
        "status_hint": "",
        "error": "",
        "finite": True,
        "exploded": False,
        "tunnelled": "",
        "outcome": "stands",
        "energy_growth": 0.0,
        "ke_max_rel": 0.5,
        "penetration_rel": 0.01,
        "drift_rel": 0.001,
        "chattering": "",
    }
    return Measurement(**{**base, **kw})


def test_classify_rules():
    ref = _result()
    assert rules.classify(_result(), ref) == ("stable", "")
    assert rules.classify(_result(penetration_rel=0.2), ref)[0] == "degraded"
    assert rules.classify(_result(drift_rel=0.02), ref)[0] == "degraded"
    assert rules.classify(_result(energy_growth=0.06), ref)[0] == "degraded"
    assert rules.classify(_result(finite=False, error="non-finite"), ref)[0] == "failed"
    assert rules.classify(_result(ke_max_rel=2.5), ref)[0] == "failed"
    assert rules.classify(_result(tunnelled="projectile passed through body 2"), ref)[0] == "failed"
    assert rules.classify(_result(outcome="collapsed"), ref)[0] == "failed"
    assert rules.classify(_result(chattering="a body woken 3 times"), ref)[0] == "failed"
    # an invalid reference is not compared with
    bad_ref = _result(tunnelled="projectile passed through the wall")
    assert rules.classify(_result(outcome="collapsed"), bad_ref)[0] == "stable"
    assert rules.classify(_result(status_hint="rejected", error="ValueError: x"), ref) == (
        "rejected",
        "ValueError: x",
    )


def test_deepest_overlap_known_depths():
    scene = sim.Scene(
        bodies=[sim.Body.box(1, 1, position=(0, 0.5)), sim.Body.box(0.5, 0.5, position=(3, 0.25))]
    )
    shapes = geometry.Shapes(scene)
    # box 1 pushed 0.1 m into box 0 from the right, and 0.02 m below the floor
    pos = np.array([[0.0, 0.5], [0.65, 0.23]])
    depth, rel = geometry.deepest_overlap(shapes, pos, np.zeros(2))
    assert depth == pytest.approx(0.1) and rel == pytest.approx(0.1 / 0.5)
    depth, rel = geometry.deepest_overlap(shapes, np.array([[0.0, 0.5], [3.0, 0.25]]), np.zeros(2))
    assert depth == pytest.approx(0.0, abs=1e-12)
    assert geometry.thinnest_width(sim.Body.box(2.0, 0.02).vertices) == pytest.approx(0.02)


class _Pose:
    """A stand-in runner: just the observables the Judge reads."""

    def __init__(self, positions):
        self.positions = np.asarray(positions, float)
        n = len(self.positions)
        self.angles = np.zeros(n)
        self.velocities = np.zeros((n, 2))
        self.angular_velocities = np.zeros(n)
        self.asleep = np.zeros(n, bool)


def test_tunnelling_is_seen_through_and_not_over():
    scene = scenes.projectile_wall(100.0)
    judge = Judge(scene, geometry.Shapes(scene))
    judge.sample(_Pose([[-0.5, 2.0]]), 0.0)
    judge.sample(_Pose([[1.2, 2.0]]), 0.1)  # jumped through the wall
    assert "passed through the wall" in judge.tunnelled
    judge = Judge(scene, geometry.Shapes(scene))
    judge.sample(_Pose([[-0.5, 2.0]]), 0.0)
    judge.sample(_Pose([[-0.4, 4.5]]), 0.1)  # rose above the wall's top
    judge.sample(_Pose([[0.5, 4.5]]), 0.2)  # passed over it
    judge.sample(_Pose([[1.0, 3.0]]), 0.3)  # and came down behind it
    assert judge.tunnelled == ""
    assert judge.outcome() == "passed"


def test_tunnelling_over_several_steps_and_not_when_pushed_back():
    scene = scenes.projectile_stack(100.0)  # body 2: the unit box centred at (0, 2.5)
    column = [[0.0, 0.5 + k] for k in range(5)]

    def judge_path(path):
        judge = Judge(scene, geometry.Shapes(scene))
        for k, xy in enumerate(path):
            judge.sample(_Pose(column + [xy]), 0.1 * k)
        return judge.tunnelled

    # in through the left face, a step inside, out through the right face, descending
    assert "passed through body 2" in judge_path([[-1.4, 2.4], [0.2, 2.2], [0.9, 2.1]])
    # in through the left face and pushed back out of it: an impact, not tunnelling
    assert judge_path([[-1.4, 2.4], [-0.3, 2.4], [-0.8, 2.4]]) == ""
    # inside all along (and a path that never entered it): nothing to say
    assert judge_path([[-0.2, 2.4], [0.1, 2.3], [0.2, 2.2]]) == ""
    # in through the left face, out through the bottom: not counted
    assert judge_path([[-1.4, 2.4], [-0.2, 2.2], [-0.1, 1.6]]) == ""
    assert geometry.clip_to_box(
        np.array([-2.0, 0.0]), np.array([2.0, 0.0]), np.array([0.5, 0.5])
    ) == ((0, -1), (0, 1))
    assert (
        geometry.clip_to_box(np.array([-2.0, 1.0]), np.array([2.0, 1.0]), np.array([0.5, 0.5]))
        is None
    )


@pytest.mark.parametrize(
    "builder,arg",
    [
        ("mass_stack", 0),
        ("mass_stack", -1.0),
        ("mass_stack", math.nan),
        ("size_stack", 0.0),
        ("size_stack", -1.0),
        ("size_stack", math.nan),
        ("plank_flat", 0),
        ("plank_upright", -3),
        ("polygon_on_box", 2),
        ("polygon_on_box", 3.5),
        ("collinear_box", -1e-3),
        ("projectile_wall", 0.0),
        ("impact", math.nan),
        ("knife_edge", math.inf),
        ("columns", 7),
    ],
)
def test_builders_refuse_out_of_range(builder, arg):
    with pytest.raises(ValueError):
        scenes.BUILDERS[builder](arg)


def test_a_refused_scene_is_recorded_not_raised():
    task = {
        "role": "run",
        "system": "sim-off",
        "scene": {"builder": "mass_stack", "args": [-1]},
        "dt": 1 / 60,
        "iterations": None,
        "steps": 10,
        "sample_every": 1,
        "budget_s": 5.0,
    }
    out = runs.simulate(task)
    assert out.status_hint == "rejected" and "mass ratio" in out.error


def test_a_body_too_small_for_the_step_is_refused_with_the_substeps_it_needs():
    """sim refuses 1 mm boxes at dt 1/60 s and 4 substeps with a ValueError naming the substeps
    that would do (11): recorded as "rejected" with the message, not as a failure of physics."""
    task = runs.run_task("size_small", 1e-3, "sim-off", T.QUICK)
    out = runs.simulate(task)
    assert out.status_hint == "rejected" and "substeps >= 11" in out.error, out.error
    status, reason = rules.classify(out, None)
    assert status == "rejected" and "substeps >= 11" in reason


def test_the_reference_is_sims_default_solver_at_a_fine_step():
    """The reference: sim-off at dt/fine with REF_SUBSTEPS substeps of REF_ITERATIONS sweeps,
    presolve on, whatever the run's own settings (so a no-presolve run, an iterations or a
    substeps row share their scene's reference)."""
    assert (runs.REF_SUBSTEPS, runs.REF_ITERATIONS) == (4, 1)
    keys = set()
    for axis, value, system in (
        ("stack_height", 20, "sim-off"),
        ("stack_height", 20, "sim-paper (no presolve)"),
        ("stack_height", 20, "pymunk"),
    ):
        ref = runs.reference_task(runs.run_task(axis, value, system, T.FULL), T.FULL)
        assert ref["system"] == ref["runner"] == "sim-off"
        assert ref["settings"] == {"substeps": runs.REF_SUBSTEPS}
        assert ref["iterations"] == runs.REF_ITERATIONS
        assert ref["dt"] == pytest.approx(DT / T.FULL["fine"])
        keys.add(runs.task_key(ref))
    assert len(keys) == 1
    refs = {
        runs.task_key(runs.reference_task(runs.run_task(a, v, "sim-off", T.FULL), T.FULL))
        for a, v in (("dt", 1 / 60), ("iterations", 1), ("substeps", 1))
    }
    assert len(refs) == 1


def test_a_reference_refused_at_its_step_gets_more_substeps():
    """0.1 mm boxes need more than 4 substeps even at dt 1/480 s: the reference doubles them
    (to 8) rather than losing the scene's reference; a run is never refined."""
    ref = runs.reference_task(runs.run_task("size_small", 1e-4, "sim-off", T.FULL), T.FULL)
    ref = {**ref, "steps": 20, "sample_every": 1}
    out = runs.simulate(ref)
    assert out.status_hint == "" and out.substeps == 8, out
    run = {**runs.run_task("size_small", 1e-4, "sim-off", T.FULL), "steps": 20}
    assert runs.simulate(run).status_hint == "rejected"


def test_systems_and_axes_that_apply():
    """The no-presolve systems run the placed axes only; the sim-only axes have no peer cell."""
    assert systems.NO_PRESOLVE_SYSTEMS == tuple(f"{s} (no presolve)" for s in SYSTEMS[:4])
    for axis in axes.AXES:
        for system in SYSTEMS:
            assert axes.applies(axis, system) == (
                axis not in axes.SIM_ONLY_AXES or system.startswith("sim-")
            )
        for system in systems.NO_PRESOLVE_SYSTEMS:
            assert axes.applies(axis, system) == (axis in axes.PLACED_AXES)
    assert set(axes.PLACED_AXES) <= set(axes.AXES) and set(axes.SIM_ONLY_AXES) <= set(axes.AXES)
    # the dropped columns start with nothing touching: no presolve to switch off
    for axis in ("dt", "iterations", "substeps", "mass_dropped", "projectile_wall"):
        assert axis not in axes.PLACED_AXES


def test_a_no_presolve_run_starts_sim_with_initial_iterations_zero():
    task = runs.run_task("stack_height", 20, "sim-extended (no presolve)", T.QUICK)
    assert task["runner"] == "sim-extended" and task["settings"] == {"initial_iterations": 0}
    runner = runs.build_runner(task, scenes.scene_of(task["scene"]))
    assert runner.world.initial_iterations == 0 and runner.world.freeze == "extended"
    task = runs.run_task("substeps", 2, "sim-off", T.QUICK)
    assert runs.build_runner(task, scenes.scene_of(task["scene"])).world.substeps == 2


def _cells(rows):
    return pd.DataFrame(
        [
            {
                "axis": a,
                "value": v,
                "system": s,
                "status": st,
                "reason": r,
                "error": r if st == "rejected" else "",
                "scene": f"{a}({v})",
                "drift_rel": 0.05 if st == "degraded" else 0.0,
            }
            for a, v, s, st, r in rows
        ]
    )


def test_breaks_first_ignores_refusals_and_sim_only_axes():
    """A refused cell is not breaking (a clear error is an answer, not a wrong result); a sim-only
    axis compares nobody."""
    values = {"size_small": [1.0, 0.01, 1e-3], "substeps": [4, 1]}
    table = _cells(
        [
            ("size_small", 1.0, "sim-off", "stable", ""),
            ("size_small", 0.01, "sim-off", "stable", ""),
            ("size_small", 1e-3, "sim-off", "rejected", "ValueError: too small"),
            ("size_small", 1.0, "pymunk", "stable", ""),
            ("size_small", 0.01, "pymunk", "stable", ""),
            ("size_small", 1e-3, "pymunk", "failed", "outcome collapsed"),
            ("substeps", 4, "sim-off", "stable", ""),
            ("substeps", 1, "sim-off", "failed", "outcome collapsed"),
        ]
    )
    per_axis, counts = analysis.headline(table, ["sim-off", "pymunk"], values)
    assert per_axis["size_small"]["breaks_first"] == ["pymunk"]
    assert per_axis["size_small"]["first_degraded_or_failed"]["sim-off"] is None
    assert per_axis["size_small"]["first_rejected"] == {"sim-off": "0.001 m"}
    assert per_axis["substeps"]["breaks_first"] == [] and not per_axis["substeps"]["compared"]
    assert per_axis["substeps"]["first_failed"] == {"sim-off": "1"}
    assert counts["sim-off"]["rejected"] == 1 and counts["pymunk"]["failed"] == 1


def test_systems_breaking_together_break_first_nowhere():
    """ "First" means before another system: where every system with a cell on the axis breaks at
    the same value, nobody breaks first and the value is reported as where they all break."""
    values = {"dt": [1 / 60, 1 / 15], "plank_flat": [1, 100]}
    table = _cells(
        [
            ("dt", 1 / 60, "sim-off", "stable", ""),
            ("dt", 1 / 15, "sim-off", "failed", "outcome"),
            ("dt", 1 / 60, "pymunk", "stable", ""),
            ("dt", 1 / 15, "pymunk", "degraded", "drift"),
            ("plank_flat", 1, "sim-off", "stable", ""),
            ("plank_flat", 100, "sim-off", "stable", ""),
            ("plank_flat", 1, "pymunk", "stable", ""),
            ("plank_flat", 100, "pymunk", "degraded", "drift"),
        ]
    )
    per_axis, _ = analysis.headline(table, ["sim-off", "pymunk"], values)
    assert per_axis["dt"]["breaks_first"] == [] and per_axis["dt"]["breaks_first_at"] is None
    assert per_axis["dt"]["breaks_together_at"] == "1/15 s"
    assert per_axis["plank_flat"]["breaks_first"] == ["pymunk"]
    assert per_axis["plank_flat"]["breaks_together_at"] is None


def test_the_headline_takes_placed_axes_from_the_fair_rows():
    """Where sim's presolve is what keeps it standing, the headline must say sim breaks first:
    on a placed axis the fair rows (sim without presolve, same peers) decide, elsewhere the
    systems as run."""
    values = {"stack_height": [10, 50], "dt": [1 / 60, 1 / 15]}
    nop = "sim-off" + systems.NO_PRESOLVE
    table = _cells(
        [
            ("stack_height", 10, "sim-off", "stable", ""),
            ("stack_height", 50, "sim-off", "stable", ""),
            ("stack_height", 10, nop, "degraded", "d"),
            ("stack_height", 50, nop, "failed", "outcome collapsed"),
            ("stack_height", 10, "pymunk", "stable", ""),
            ("stack_height", 50, "pymunk", "degraded", "d"),
            ("dt", 1 / 60, "sim-off", "stable", ""),
            ("dt", 1 / 15, "sim-off", "stable", ""),
            ("dt", 1 / 60, "pymunk", "stable", ""),
            ("dt", 1 / 15, "pymunk", "failed", "outcome collapsed"),
        ]
    )
    per_axis, _ = analysis.headline(table, ["sim-off", "pymunk"], values)
    assert per_axis["stack_height"]["breaks_first"] == ["pymunk"]  # with sim's presolve
    fair = analysis.no_presolve_numbers(table, ["sim-off", "pymunk"], [nop], values)
    assert fair["axes"] == ["stack_height"]
    # the degraded no-presolve cells, named with their drift (the paper lists them)
    assert fair["degraded_drift"] == {nop: {"stack_height(10)": 0.05}}
    headline = analysis.fair_headline(per_axis, fair)
    assert headline["stack_height"]["protocol"] == "sim without presolve"
    assert headline["stack_height"]["breaks_first"] == [nop]
    assert headline["stack_height"]["breaks_first_at"] == "10"
    assert headline["stack_height"]["with_presolve"]["breaks_first"] == ["pymunk"]
    assert headline["dt"]["protocol"] == "as run"
    assert headline["dt"]["breaks_first"] == ["pymunk"]
