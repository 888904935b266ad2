"""experiments.fig_scaling and analysis.fig_scaling end to end on --quick sizes, into temporary
folders, and the standard error of b/a that cost_fit.fit_cost now reports.

Asserted are the set-up's checks (the row frozen/asleep and the flyers awake and in flight while
timed, for every system, including pymunk-sleep, whose row sleeps only after a 0.5 s timer), that a
frozen body costs far less than a solved resting one (b vs b_off: ~100x apart even on quick
sizes), and that the delta-method standard error matches the spread of b/a over noisy fits."""

import json
import math

import numpy as np
import pandas as pd
import pytest

from analysis import fig_scaling as analysis
from study import cost_fit, paths
from experiments import fig_scaling


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fig_scaling")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(paths, "DATA", folder / "data")
        mp.setattr(paths, "FIGURES", folder / "figures")
        mp.setattr(paths, "GENERATED", folder / "generated")
        fig_scaling.main(["--quick"], data_dir=paths.DATA)
        numbers = analysis.main([])
    table = pd.read_csv(folder / "data" / "fig_scaling.csv")
    table["flag"] = table["flag"].astype(object).fillna("")
    return table, numbers, folder


def _fit(table, system, key, scene="fit"):
    return table[
        (table["scene"] == scene) & (table["system"] == system) & (table["metric"] == f"fit_{key}")
    ]["value"].item()


def test_every_mix_was_timed_as_designed(quick_run):
    table, _, _ = quick_run
    cfg = fig_scaling.QUICK
    med = table[~table["scene"].str.startswith("fit") & (table["metric"] == "ms_per_step_median")]
    assert len(med) == len(cfg["mix_frozen"]) * len(cfg["mix_awake"]) * len(fig_scaling.SYSTEMS)
    assert med["value"].map(math.isfinite).all() and (med["value"] > 0).all()
    assert (med["flag"] == "").all()  # awake counts and flight checks held
    for metric in ("n_awake_before", "n_awake_after"):
        rows = table[~table["scene"].str.startswith("fit") & (table["metric"] == metric)]
        for system in fig_scaling.SYSTEMS:
            r = rows[rows["system"] == system]
            expected = r["n_awake"] + (r["n_frozen"] if system == "sim-off" else 0)
            assert (r["value"] == expected).all(), (system, metric)
    lowest = table[table["metric"] == "lowest_flying_y"]["value"]
    assert (lowest > 100).all()


def test_fits_and_a_frozen_body_is_far_cheaper_than_a_solved_one(quick_run):
    table, numbers, _ = quick_run
    points = len(fig_scaling.QUICK["mix_frozen"]) * len(fig_scaling.QUICK["mix_awake"])
    for scene in ("fit", "fit_min"):
        for system in fig_scaling.SYSTEMS:
            for key in ("a", "b", "c", "a_stderr", "b_stderr", "b_over_a", "b_over_a_stderr", "r2"):
                assert math.isfinite(_fit(table, system, key, scene)), (scene, system, key)
            assert _fit(table, system, "points", scene) == points
        b_off = _fit(table, "sim-off", "b", scene)
        assert b_off > 0
        for system in ("sim-extended", "pymunk-sleep"):
            assert _fit(table, system, "b", scene) < 0.2 * b_off, (scene, system)
            assert _fit(table, system, "b_over_b_off", scene) < 0.2, (scene, system)
    for system in fig_scaling.SYSTEMS:
        assert numbers[system]["a"] == pytest.approx(_fit(table, system, "a"))
        assert numbers[system]["fastest_repeat"]["a"] == pytest.approx(
            _fit(table, system, "a", "fit_min")
        )


def test_figure_table_and_numbers(quick_run):
    _, numbers, folder = quick_run
    svg = (folder / "figures" / "fig_scaling.svg").read_text()
    assert svg.startswith("<?xml") and svg.count("<path") > 50, "figure is empty"
    paper = pd.read_csv(folder / "generated" / "fig_scaling.csv")
    assert set(paper["system"]) == set(fig_scaling.SYSTEMS)
    assert len(paper) == 2 * len(fig_scaling.SYSTEMS)  # median and fastest-repeat fits
    written = json.loads((folder / "generated" / "fig_scaling.json").read_text())
    assert written["numbers"] == json.loads(json.dumps(numbers)) and written["quick"] is True
    assert numbers["mixes_failing_checks"] == 0
    assert numbers["sim-extended"]["b_ns"] == pytest.approx(numbers["sim-extended"]["b"] * 1e6)


def test_b_over_a_stderr_matches_the_spread_of_noisy_fits():
    rng = np.random.default_rng(0)
    n_aw, n_fr = np.meshgrid([100, 200, 400, 800], [0, 1000, 2000, 4000])
    n_aw, n_fr = n_aw.ravel(), n_fr.ravel()
    a, b, c, noise = 1e-4, 2e-6, 5e-3, 2e-3  # ms; noise like the measured residuals
    ratios, stderrs = [], []
    for _ in range(2000):
        fit = cost_fit.fit_cost(
            n_aw, n_fr, a * n_aw + b * n_fr + c + rng.normal(0.0, noise, n_aw.size)
        )
        ratios.append(fit["b_over_a"])
        stderrs.append(fit["b_over_a_stderr"])
    assert np.median(stderrs) == pytest.approx(np.std(ratios), rel=0.15)
    exact = cost_fit.fit_cost(n_aw, n_fr, a * n_aw + b * n_fr + c)
    assert exact["b_over_a"] == pytest.approx(b / a) and exact["b_over_a_stderr"] < 1e-9
