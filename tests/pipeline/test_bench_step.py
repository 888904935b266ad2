"""experiments.bench_step end to end on --quick sizes, into a temporary results folder, and its
pieces (settings columns, the target check) on known inputs. No speed is asserted here: speed
lives in the benchmark's results."""

import json
import math

import numpy as np
import pandas as pd
import pytest

import sim
from experiments import bench_step
from study.peers import DEFAULT_ITERATIONS, SIM_DEFAULT_SUBSTEPS, solver_summary
from sim.data import STAGES


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bench_step")
    bench_step.main(["--quick"], data_dir=folder)
    return folder


def test_quick_run_writes_every_row_and_the_metadata(quick):
    table = pd.read_csv(quick / "bench_step.csv")
    q = bench_step.QUICK
    expected = {
        (scene, p, system)
        for scene in ("rest_row", "pyramid", "drop")
        for p in q[scene]
        for system in (bench_step.SETTLING_SYSTEMS if scene == "drop" else bench_step.SYSTEMS)
    }
    assert bench_step.SYSTEMS == ("sim-off", "pymunk", "box2d", "box2d3")
    # sim-off without its landing sweeps, on the settling scene only
    assert bench_step.SETTLING_VARIANTS == {
        "sim-off (no landing sweeps)": ("sim-off", {"impact_iterations": 0})
    }
    assert set(zip(table["scene"], table["param"], table["system"])) == expected
    assert len(table) == len(expected)
    for column in ("ms_per_step_median", "ms_per_step_min"):
        assert (table[column] > 0).all() and table[column].map(math.isfinite).all()
    assert (table["ms_per_step_min"] <= table["ms_per_step_median"]).all()
    assert (table["repeats"] == q["repeats"]).all()
    resting = table[table["scene"] != "drop"]
    settling = table[table["scene"] == "drop"]
    assert (resting["steps_per_repeat"] == q["steps"]).all()
    assert (settling["steps_per_repeat"] == q["window"]).all()
    assert settling["mode"].str.startswith("settling").all()
    sim_rows = table[table["system"] == "sim-off"]
    own = table[table["system"].isin(bench_step.SIM_ROWS)]
    for peer in bench_step.SYSTEMS[1:]:
        assert (own[f"speedup_vs_{peer}"] > 0).all()
        assert (
            table.loc[~table["system"].isin(bench_step.SIM_ROWS), f"speedup_vs_{peer}"].isna().all()
        )
        # each sim row's ratio is its own: the peer's median over the row's median
        for r in own.itertuples():
            theirs = table[
                (table["scene"] == r.scene)
                & (table["param"] == r.param)
                & (table["system"] == peer)
            ]["ms_per_step_median"].iloc[0]
            assert getattr(r, f"speedup_vs_{peer}") == pytest.approx(theirs / r.ms_per_step_median)
    assert (resting["max_displacement_m"] < 0.5).all()  # resting scenes stayed put
    assert (settling["bodies_in_bin"] == settling["param"]).all()  # the drop stayed in its bin
    assert (sim_rows["contacts"] > 0).all() and (sim_rows["batches"] > 0).all()

    meta = json.loads((quick / "bench_step.json").read_text())
    for key in (
        "script",
        "scenes",
        "parameters",
        "seed",
        "git",
        "packages",
        "python",
        "platform",
        "cpu",
        "cpu_count",
        "date_utc",
    ):
        assert key in meta
    assert meta["script"] == "bench_step"
    # which row ran with the landing sweeps: the column says it, a peer has none (NaN)
    by_system = table.groupby("system")["impact_iterations"]
    assert (by_system.get_group("sim-off (no landing sweeps)") == 0).all()
    assert (by_system.get_group("sim-off") == sim.soft_step.IMPACT_ITERATIONS).all()
    assert table.loc[~table["system"].isin(bench_step.SIM_ROWS), "impact_iterations"].isna().all()
    variant = meta["parameters"]["system_settings"]["sim-off (no landing sweeps)"]
    assert variant["impact_iterations"] == 0
    assert meta["parameters"]["system_settings"]["sim-off"]["impact_iterations"] > 0
    assert meta["parameters"]["settling_variants"] == {
        "sim-off (no landing sweeps)": {"system": "sim-off", "settings": {"impact_iterations": 0}}
    }
    assert {"commit", "dirty"} <= set(meta["git"])
    assert meta["packages"]["pymunk"] == "7.3.1" and meta["packages"]["pyb2d3"] == "0.11.1"
    repeats = meta["parameters"]["repeats"]
    assert len(meta["scenes"]) == len(q["rest_row"]) + len(q["pyramid"]) + len(q["drop"]) * repeats
    # the settling scene drops one seed per repeat, the same for every system (drop(20) seeds 0-2
    # are built by every system: none skipped)
    seeds = [s["params"]["seed"] for s in meta["scenes"] if s["name"] == "drop"]
    assert seeds == list(range(repeats)) * len(q["drop"])
    assert (settling["seeds"] == " ".join(map(str, range(repeats)))).all()
    assert meta["seed"] == list(range(repeats))  # the piles' seeds as timed, not the first alone
    assert settling["seeds_skipped"].isna().all()
    assert set(settling["label"]) == {f"drop({n})" for n in q["drop"]}
    assert meta["parameters"]["targets"] == {}  # no target scene in quick sizes
    assert not list(quick.glob("*.tmp"))  # atomic writes left no temp files


def test_a_pile_some_system_refuses_is_skipped_for_all():
    """Box2D's polygon skin refuses a sliver in drop(200) seed 5 (body 147): the settling bench
    skips that seed for every system, so each repeat times the same pile in each."""
    assert bench_step.build_all(sim.scenes.drop(200, seed=5)) is None
    runners, seconds = bench_step.build_all(sim.scenes.drop(200, seed=4))
    assert set(runners) == set(seconds) == set(bench_step.SETTLING_SYSTEMS)
    for runner in runners.values():
        runner.close()


def test_each_system_runs_at_its_own_defaults_and_the_rows_say_so(quick):
    table = pd.read_csv(quick / "bench_step.csv")
    meta = json.loads((quick / "bench_step.json").read_text())
    sim_rows = table[table["system"] == "sim-off"]
    pym_rows = table[table["system"] == "pymunk"]
    assert (sim_rows["substeps"] == SIM_DEFAULT_SUBSTEPS).all()
    assert (sim_rows["iterations"] == DEFAULT_ITERATIONS["sim"]).all()
    assert (pym_rows["substeps"] == 1).all()
    assert (pym_rows["iterations"] == DEFAULT_ITERATIONS["pymunk"]).all()
    settings = meta["parameters"]["system_settings"]
    assert settings["sim-off"]["substeps"] == SIM_DEFAULT_SUBSTEPS
    assert settings["sim-off"]["iterations"] == DEFAULT_ITERATIONS["sim"]
    assert settings["pymunk"]["iterations"] == DEFAULT_ITERATIONS["pymunk"]
    # Box2D v3 steps as sim's soft step does: 4 substeps, one biased and one relax sweep each
    v3_rows = table[table["system"] == "box2d3"]
    assert (v3_rows["substeps"] == 4).all() and (v3_rows["iterations"] == 1).all()
    assert (v3_rows["contact_sweeps_per_step"] == sim_rows["contact_sweeps_per_step"].iloc[0]).all()
    assert settings["box2d3"]["simd"].startswith("SSE2")


def test_profile_has_every_stage_of_every_scene_and_adds_up(quick):
    profile = pd.read_csv(quick / "bench_step_profile.csv")
    table = pd.read_csv(quick / "bench_step.csv")
    assert set(profile["label"]) == set(table["label"])
    for lbl, rows in profile.groupby("label"):
        assert list(rows["stage"]) == list(STAGES) + ["total"], lbl
        stages = rows[rows["stage"] != "total"]
        total = float(rows.loc[rows["stage"] == "total", "ms_per_step"].iloc[0])
        assert (stages["ms_per_step"] >= 0).all() and total > 0
        assert stages["ms_per_step"].sum() == pytest.approx(total, rel=1e-12)
        assert rows["share_of_total"].iloc[:-1].sum() == pytest.approx(1.0, rel=1e-12)
        assert (rows["profile_total_ms"] > 0).all()
        assert (rows["substeps"] == SIM_DEFAULT_SUBSTEPS).all()
        assert (rows["ms_per_step_unprofiled"] > 0).all()
    meta = json.loads((quick / "bench_step_profile.json").read_text())
    assert meta["table"] == "bench_step_profile" and meta["git"]["commit"]


def test_the_profile_total_is_the_sum_of_the_stage_medians_and_the_measured_total_is_kept():
    # three repeats in which the median of the totals (10) is not the sum of the medians (4):
    # the table must add up all the same, and say what was measured
    profiles = [
        {"collide": 1.0, "solve": 1.0, "total": 2.0},
        {"collide": 2.0, "solve": 8.0, "total": 10.0},
        {"collide": 8.0, "solve": 2.0, "total": 10.0},
    ]
    scene = sim.scenes.rest_row(3)
    settings = {"substeps": 4, "iterations": 1, "relax_iterations": 1}
    rows = bench_step._profile_rows(scene, profiles, 8.0, 5, {"contacts": 2}, settings)
    by_stage = {r["stage"]: r for r in rows}
    assert list(by_stage) == ["collide", "solve", "total"]
    assert by_stage["collide"]["ms_per_step"] == 2.0 and by_stage["solve"]["ms_per_step"] == 2.0
    assert by_stage["total"]["ms_per_step"] == 4.0
    assert by_stage["solve"]["share_of_total"] == 0.5
    assert {r["profile_total_ms"] for r in rows} == {10.0}
    assert {r["repeats"] for r in rows} == {3}


def test_solver_summary_counts_the_passes_over_the_contacts():
    sim_settings = {"substeps": 4, "iterations": 1, "relax_iterations": 1}
    assert solver_summary(sim_settings) == {
        "substeps": 4,
        "iterations": 1,
        "relax_iterations": 1,
        "contact_sweeps_per_step": 8,
    }
    assert solver_summary({"iterations": 10})["contact_sweeps_per_step"] == 10


def test_targets_are_judged_against_three_times_pymunk():
    table = pd.DataFrame(
        {
            "scene": ["pyramid", "rest_row", "drop", "pyramid"],
            "param": [40, 5000, 200, 10],
            "label": ["pyramid(40)", "rest_row(5000)", "drop(200,seed=0)", "pyramid(10)"],
            "system": ["sim-off"] * 4,
            "speedup_vs_pymunk": [3.2, 2.9, np.nan, 1.0],
        }
    )
    out = bench_step.targets(table)
    assert set(out) == {"pyramid(40)", "rest_row(5000)", "drop(200,seed=0)"}
    assert out["pyramid(40)"]["met"] and not out["rest_row(5000)"]["met"]
    assert not out["drop(200,seed=0)"]["met"]  # a missing ratio is not a pass


def test_metadata_survives_missing_git_and_packages(monkeypatch):
    from study import metadata

    def no_git(*args, **kwargs):
        raise FileNotFoundError("git")

    monkeypatch.setattr(metadata.subprocess, "run", no_git)
    monkeypatch.setattr(metadata, "PACKAGES", ("numpy", "no-such-package-freeze2d"))
    meta = metadata.collect(None, {"x": 1}, script="t")
    assert meta["git"] == {"commit": "unknown", "dirty": "unknown"}
    assert meta["packages"]["no-such-package-freeze2d"] == "not installed"
    json.dumps(meta)


def test_the_analysis_names_the_settling_piles(quick):
    from analysis.bench_step import settling_seeds

    table = pd.read_csv(quick / "bench_step.csv")
    repeats = bench_step.QUICK["repeats"]
    expected = [str(seed) for seed in range(repeats)]
    assert settling_seeds(table) == {f"drop({n})": expected for n in bench_step.QUICK["drop"]}
    # a table written before the column existed: no seeds to name, no error
    assert settling_seeds(table.drop(columns="seeds")) == {
        f"drop({n})": [] for n in bench_step.QUICK["drop"]
    }


def test_a_clamp_inside_the_timed_window_is_found_by_replaying_it_one_step_per_call():
    """Box2D 2.3 spins body 167 of drop(200) seed 4 to its per-step rotation limit (pi/2 rad a
    step, 94.25 rad/s) at step 84, and the pile settles: the timed window's one 240-step call
    ends without a word, since the runner checks only at the end of a call. The replay names
    the seed, the body and the step; seed 0 and Box2D v3 reach no clamp there."""
    from study.common import build
    from study.timing import timed

    for seed, system, expected in (
        (4, "box2d", "seed 4, box2d: body 167 reached Box2D's per-step motion limit at step 84"),
        (0, "box2d", ""),
        (4, "box2d3", ""),
    ):
        scene = sim.scenes.drop(200, seed=seed)
        with build(system, scene) as runner:
            assert runner.checks_clamps_per_call
            timed(runner, 240)  # what bench_step times: one call, no error
            clamp = bench_step.first_clamp(system, scene, 240, runner)
        assert clamp.startswith(expected) if expected else clamp == ""


def test_a_replay_that_does_not_end_where_the_timed_run_did_stops_the_bench():
    from study.common import build

    scene = sim.scenes.drop(20, seed=0)
    with build("box2d", scene) as runner:
        runner.step(29)  # one step short of the window replayed
        with pytest.raises(RuntimeError, match="did not end where its timed run did"):
            bench_step.first_clamp("box2d", scene, 30, runner)


def test_clamped_piles_are_counted_on_the_settling_rows_and_shown_in_the_table(quick):
    from analysis.bench_step import _clamp_note, clamped

    table = pd.read_csv(quick / "bench_step.csv")
    settling = table[table["scene"] == "drop"]
    resting = table[table["scene"] != "drop"]
    assert (settling["clamped_piles"] >= 0).all() and resting["clamped_piles"].isna().all()
    # a table with one clamped pile under Box2D 2.3 (as the full run's drop(200) seed 4)
    marked = table.assign(clamps=table["clamps"].fillna("").astype(str))  # CSV: empty is NaN
    row = (marked["system"] == "box2d") & (marked["scene"] == "drop")
    marked.loc[row, "clamped_piles"] = 1
    marked.loc[row, "clamps"] = "seed 1, box2d: body 3 reached ...; seed 2, box2d: ..."
    found = clamped(marked)
    label = f"drop({bench_step.QUICK['drop'][0]})"
    assert found == {
        label: {
            "box2d": {
                "piles": 1,
                "of": bench_step.QUICK["repeats"],
                "first": "seed 1, box2d: body 3 reached ...",
            }
        }
    }
    assert _clamp_note(label, found) == f"Box2D 2.3: 1 of {bench_step.QUICK['repeats']} piles"
    assert _clamp_note("pyramid(5)", found) == ""
    # a table written before the columns existed
    assert clamped(table.drop(columns=["clamped_piles", "clamps"])) == {}


def test_the_analysis_reads_the_variant_apart_with_its_own_ratios(quick):
    """analysis.bench_step.variants (what the paper and the README quote) on the quick run's table:
    the variant's own median and ratios, on the settling scene only; sim-off's ratios unchanged."""
    from analysis.bench_step import _ratios, variants

    table = pd.read_csv(quick / "bench_step.csv")
    found = variants(table)
    labels = {f"drop({n})" for n in bench_step.QUICK["drop"]}
    assert set(found) == labels
    for label in labels:
        (name, v), *rest = found[label].items()
        assert not rest and name == "sim-off (no landing sweeps)"
        row = table[(table["label"] == label) & (table["system"] == name)].iloc[0]
        assert v["ms"] == row["ms_per_step_median"]
        for peer in bench_step.SYSTEMS[1:]:
            theirs = table[(table["label"] == label) & (table["system"] == peer)].iloc[0]
            assert v[f"{peer}_over_variant"] == pytest.approx(
                theirs["ms_per_step_median"] / row["ms_per_step_median"]
            )
    ratios = _ratios(table).set_index("label")
    sims = table[table["system"] == "sim-off"].set_index("label")
    assert ratios["pymunk_over_sim"].to_dict() == pytest.approx(sims["speedup_vs_pymunk"].to_dict())


def test_a_table_and_a_profile_from_two_runs_are_refused():
    """bench_step writes its table and its profile with one run's provenance; a table copied from
    another run beside the old profile was drawn as one run (until 2026-12-07)."""
    from analysis import bench_step as analysis_bench_step
    from study.metadata import ResultsError

    meta = {"date_utc": "2026-12-07T10:00:00+00:00", "parameters": {"repeats": 3}}
    analysis_bench_step.check_same_run(meta, dict(meta))  # one run: fine
    for other in ({**meta, "date_utc": "2026-12-07T11:00:00+00:00"}, {**meta, "parameters": {}}):
        with pytest.raises(ResultsError, match="come from different runs"):
            analysis_bench_step.check_same_run(meta, other)
