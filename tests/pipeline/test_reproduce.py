"""`make reproduce QUICK=1` end to end, into a temporary tree: every experiment, figure, table,
recording and the PDF must exist and be non-trivial, and re-plotting must not re-simulate.

This is the slowest test (the whole pipeline on small sizes, a few minutes on 2 cores); it is the
one that proves the README's `make reproduce` works from the Makefile down."""

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from study import scenarios

ROOT = Path(__file__).resolve().parents[2]


def _make(*args, timeout=900):
    env = {**os.environ, "PYTHONHASHSEED": "0"}
    env.pop("FREEZE2D_RESULTS", None)
    env.pop("FREEZE2D_PAPER_OUT", None)
    return subprocess.run(
        ["make", "-C", str(ROOT), *args, f"PY={sys.executable}"],
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def _list(variable):
    out = _make("-s", f"print-{variable}", "QUICK=1")
    assert out.returncode == 0, out.stderr
    return out.stdout.split()


@pytest.fixture(scope="module")
def quick_tree(tmp_path_factory):
    tree = tmp_path_factory.mktemp("reproduce")
    results, paper = tree / "results", tree / "paper"
    t0 = time.perf_counter()
    out = _make("reproduce", "QUICK=1", f"RESULTS_DIR={results}", f"PAPER_OUT={paper}")
    elapsed = time.perf_counter() - t0
    assert out.returncode == 0, (
        f"make reproduce QUICK=1 failed:\n{out.stdout[-3000:]}\n{out.stderr[-3000:]}"
    )
    return results, paper, elapsed


def test_every_output_exists_and_is_nontrivial(quick_tree):
    results, paper, elapsed = quick_tree
    for name in _list("ALL"):
        csv = results / "data" / f"{name}.csv"
        meta = json.loads((results / "data" / f"{name}.json").read_text())
        assert csv.stat().st_size > 100, f"{csv} is nearly empty"
        assert meta["parameters"]["quick"] is True
        assert meta["git"]["commit"] != "" and meta["cpu"] and meta["packages"]["numba"]
        numbers = json.loads((paper / "generated" / f"{name}.json").read_text())
        assert numbers["numbers"], f"{name}: analysis quoted no numbers"
    figures = sorted((paper / "figures").glob("*.svg"))
    assert len(figures) >= 8, [f.name for f in figures]
    for svg in figures:
        assert svg.stat().st_size > 5000 and svg.read_text().count("<path") > 10, svg
    tables = sorted((paper / "generated").glob("*.csv"))
    assert len(tables) >= 6, [t.name for t in tables]
    for recording in _list("RECORDINGS"):
        rrd = results / "recordings" / f"{recording}.rrd"
        assert rrd.stat().st_size > 10_000, rrd
    rows = results / "recordings" / "table_failures"  # one per row, every system
    for scenario in scenarios.SCENARIOS:
        assert (rows / f"{scenario}.rrd").stat().st_size > 10_000, scenario
        assert f"{scenario}.rrd" in (rows / "index.txt").read_text()
    pdf = paper / "paper.pdf"
    assert pdf.read_bytes()[:5] == b"%PDF-" and pdf.stat().st_size > 50_000
    glance = (paper / "generated" / "glance.md").read_text()
    assert "speed" in glance.lower()
    # the budget for the quick pipeline is 3 minutes; leave room for a slow CI machine
    assert elapsed < 600, f"quick pipeline took {elapsed:.0f} s"


def test_replotting_does_not_simulate(quick_tree):
    results, paper, _ = quick_tree
    # touching an analysis script re-draws; nothing under results/data may be rewritten
    before = {p: p.stat().st_mtime_ns for p in (results / "data").glob("*.csv")}
    os.utime(ROOT / "analysis" / "style.py")
    out = _make("figures", "QUICK=1", f"RESULTS_DIR={results}", f"PAPER_OUT={paper}")
    assert out.returncode == 0, out.stderr
    assert "python -m experiments." not in out.stdout
    assert {p: p.stat().st_mtime_ns for p in before} == before


def test_the_glance_names_the_commit_of_an_experiment_rerun_alone(quick_tree):
    # Only analysis.paper writes generated/setup.json, and the glance read its commit from there
    # without depending on it: after an experiment rerun alone at another commit (`make
    # fig_speedup`), `make glance` named the last paper's commit for every result, and `make
    # reproduce` never corrected it. The glance reads the data's metadata itself. (Runs last: it
    # leaves fig_speedup's metadata naming a made-up commit.)
    results, paper, _ = quick_tree
    meta_path = results / "data" / "fig_speedup.json"
    meta = json.loads(meta_path.read_text())
    meta["git"] = {"commit": "feedbeef" * 5, "dirty": False}
    meta_path.write_text(json.dumps(meta))
    os.utime(results / "data" / "fig_speedup.csv")  # rerun: newer than what was drawn from it
    out = _make("glance", "QUICK=1", f"RESULTS_DIR={results}", f"PAPER_OUT={paper}")
    assert out.returncode == 0, out.stderr
    glance = (paper / "generated" / "glance.md").read_text()
    assert "`fig_speedup` from commit `feedbeeffe`" in glance, glance.splitlines()[2]
