"""experiments.fig_speedup and analysis.fig_speedup end to end on --quick sizes, into temporary
folders.

Wall-clock speed-ups are not asserted to any target; what is asserted are behaviours that a broken
policy or a broken harness would change: which bodies were frozen while being timed, when each
system froze a resting row, that sim-paper freezes only a pyramid's two lowest rows, that a fully
frozen sim step is several times cheaper than solving the same row (a margin of ~20x is measured:
only a harness timing the wrong thing fails it), and that pybullet's cap gives marked NaN rows."""

import json
import math

import pandas as pd
import pytest

import sim
from analysis import fig_speedup as analysis
from study import paths, systems
from experiments import fig_speedup
from study.common import SYSTEMS

COLUMNS = [
    "family",
    "size",
    "scene",
    "bodies",
    "system",
    "engine",
    "reference",
    "ms_per_step_median",
    "ms_per_step_min",
    "speedup",
    "speedup_paired",
    "speedup_vs_sim_off",
    "ms_per_call_median",
    "speedup_single",
    "calls_per_repeat",
    "n_awake_before",
    "n_awake_after",
    "steps_to_all_frozen",
    "settle_steps",
    "steps_per_repeat",
    "repeats",
    "max_displacement_m",
    "flag",
]
FREEZING = systems.FREEZING


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fig_speedup")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(paths, "DATA", folder / "data")
        mp.setattr(paths, "FIGURES", folder / "figures")
        mp.setattr(paths, "GENERATED", folder / "generated")
        fig_speedup.main(["--quick"], data_dir=paths.DATA)
        numbers = analysis.main([])
    table = pd.read_csv(folder / "data" / "fig_speedup.csv")
    table["flag"] = table["flag"].astype(object).fillna("")
    return table, numbers, folder


def _get(table, scene, system, column):
    return table[(table["scene"] == scene) & (table["system"] == system)][column].item()


def test_table_has_every_scene_and_system(quick_run):
    table, _, _ = quick_run
    assert list(table.columns) == COLUMNS
    cfg = fig_speedup.QUICK
    n_scenes = len(cfg["rest_row"]) + len(cfg["pyramid"])
    assert len(table) == n_scenes * len(SYSTEMS)
    assert set(table["system"]) == set(SYSTEMS)
    # quick sizes are all under pybullet's cap: everything ran
    assert not table["flag"].str.startswith("not run").any()
    for column in (
        "ms_per_step_median",
        "ms_per_step_min",
        "speedup",
        "ms_per_call_median",
        "speedup_single",
    ):
        assert table[column].map(math.isfinite).all() and (table[column] > 0).all(), column
    assert (table["ms_per_step_min"] <= table["ms_per_step_median"]).all()
    assert (table["calls_per_repeat"] >= 5).all()
    refs = table[table["system"] == table["reference"]]
    assert (refs["speedup"] == 1.0).all() and (refs["speedup_single"] == 1.0).all()
    # a one-step call costs at least a step of the same system in a long call (no timing
    # threshold: a call holds a step)
    sim_rows = table[table["engine"] == "sim"]
    assert (sim_rows["ms_per_call_median"] > sim_rows["ms_per_step_min"]).all()
    settle = int(round(cfg["settle_s"] / fig_speedup.DT))
    assert (table["settle_steps"] == settle).all()  # every system timed at the same age


def test_resting_rows_are_timed_fully_frozen(quick_run):
    table, _, _ = quick_run
    for n in fig_speedup.QUICK["rest_row"]:
        scene = f"rest_row({n})"
        for system in SYSTEMS:
            before = _get(table, scene, system, "n_awake_before")
            after = _get(table, scene, system, "n_awake_after")
            if system in FREEZING:
                assert before == after == 0, (scene, system)
                assert _get(table, scene, system, "flag") == "all frozen"
            else:
                assert before == after == n, (scene, system)  # sleeping off solves all
        steps = lambda system: _get(table, scene, system, "steps_to_all_frozen")
        assert steps("sim-paper") <= 3 and steps("sim-extended") <= 3
        assert steps("sim-sleep") >= 30 and steps("pymunk-sleep") >= 30  # 0.5 s timers
        assert steps("pybullet-sleep") >= 120  # Bullet's 2 s


def test_paper_freezes_only_the_two_lowest_pyramid_rows(quick_run):
    table, numbers, _ = quick_run
    for base in fig_speedup.QUICK["pyramid"]:
        scene = f"pyramid({base})"
        bodies = base * (base + 1) // 2
        assert _get(table, scene, "sim-paper", "n_awake_before") == bodies - (2 * base - 1)
        assert _get(table, scene, "sim-paper", "flag") == "NOT all frozen"
        for system in ("sim-sleep", "sim-extended"):
            assert _get(table, scene, system, "n_awake_before") == 0, (scene, system)
    assert any("sim-paper" in s for s in numbers["not_all_frozen"])


def test_a_frozen_row_is_much_cheaper_than_a_solved_one(quick_run):
    table, _, _ = quick_run
    scene = f"rest_row({max(fig_speedup.QUICK['rest_row'])})"
    for system in ("sim-sleep", "sim-paper", "sim-extended"):
        assert _get(table, scene, system, "speedup") > 3, system


def test_the_numbers_carry_both_speed_ups(quick_run):
    _, numbers, _ = quick_run
    row = numbers["rest_row"]
    for system in SYSTEMS:
        assert row["ms_per_call"][system] > 0 and row["speedup_single"][system] > 0


def test_pybullet_cap_gives_marked_nan_rows():
    scene = sim.scenes.rest_row(fig_speedup.PYBULLET_MAX_BODIES + 1)
    systems = fig_speedup.systems_for(scene)
    assert "pybullet" not in systems and "pybullet-sleep" not in systems
    assert len(systems) == len(SYSTEMS) - 2
    assert fig_speedup.systems_for(sim.scenes.rest_row(10)) == SYSTEMS
    fake = [
        {
            "froze_at": None,
            "before": 0,
            "after": 0,
            "times": [1.0, 2.0, 3.0],
            "steps": 10,
            "call_times": [1.5, 2.5, 3.5],
            "calls": 5,
            "age": 5,
            "moved": 0.0,
        }
        for _ in systems
    ]
    rows = pd.DataFrame(fig_speedup.scene_rows(scene, fake, systems, 3))
    assert list(rows.columns) == COLUMNS and len(rows) == len(SYSTEMS)
    skipped = rows[rows["engine"] == "pybullet"]
    assert len(skipped) == 2 and skipped["ms_per_step_median"].isna().all()
    assert skipped["flag"].str.startswith("not run: pybullet capped").all()


def test_figure_table_and_numbers(quick_run):
    table, numbers, folder = quick_run
    svg = (folder / "figures" / "fig_speedup.svg").read_text()
    assert svg.startswith("<?xml") and svg.count("<path") > 50, "figure is empty"
    paper = pd.read_csv(folder / "generated" / "fig_speedup.csv")
    assert len(paper) == table["scene"].nunique()
    assert set(SYSTEMS) <= set(paper.columns)
    written = json.loads((folder / "generated" / "fig_speedup.json").read_text())
    assert written["numbers"] == json.loads(json.dumps(numbers)) and written["quick"] is True
    for family, sizes in (
        ("rest_row", fig_speedup.QUICK["rest_row"]),
        ("pyramid", fig_speedup.QUICK["pyramid"]),
    ):
        fam = numbers[family]
        assert fam["largest_scene"] == f"{family}({max(sizes)})"
        assert set(fam["speedup"]) == set(SYSTEMS)
        assert fam["speedup"]["sim-off"] == 1.0
