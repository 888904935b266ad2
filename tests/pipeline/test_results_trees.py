"""Where an experiment's results go: a --quick run never writes into the full results tree (where
make would take it for a full result), however it is started; the Makefile names the tree itself.

The experiments' measurements are replaced by tiny fakes here: what is checked is the command
line and where the files land, not the numbers."""

import os
import subprocess
import sys

import pandas as pd
import pytest

from experiments import bench_freeze, bench_step, peer_agreement
from study import common, paths

FAKE_DOC = """A fake experiment: one row.

It measures nothing.
"""


def _fake_run(config, args):
    _fake_run.args = args
    return pd.DataFrame({"x": [1.0]}), None, {}


FAKE = common.entry("fake", FAKE_DOC, {"size": "full"}, {"size": "quick"}, _fake_run)


@pytest.fixture
def tree(tmp_path, monkeypatch):
    """A results tree in tmp_path, as if FREEZE2D_RESULTS were not set (a script run by hand)."""
    monkeypatch.setattr(paths, "RESULTS", tmp_path)
    monkeypatch.setattr(paths, "RESULTS_GIVEN", False, raising=False)
    monkeypatch.setattr(paths, "DATA", tmp_path / "data")
    return tmp_path


def test_a_quick_run_by_hand_writes_into_the_quick_tree(tree):
    FAKE(["--quick"])
    assert (tree / "quick" / "data" / "fake.csv").exists()
    assert (tree / "quick" / "data" / "fake.json").exists()
    assert not (tree / "data").exists()
    # its sweep store too is the quick tree's
    store = common.store_path("fake", _fake_run.args)
    assert store == tree / "quick" / "partial" / "fake-quick.jsonl"


def test_a_full_run_writes_into_the_full_tree(tree):
    FAKE([])
    assert (tree / "data" / "fake.csv").exists()
    assert not (tree / "quick").exists()
    assert common.store_path("fake", _fake_run.args) == tree / "partial" / "fake.jsonl"


def test_a_named_tree_is_used_as_it_is(tree, monkeypatch):
    """`make reproduce QUICK=1` sets FREEZE2D_RESULTS=results/quick: no quick/ inside it."""
    monkeypatch.setattr(paths, "RESULTS_GIVEN", True)
    FAKE(["--quick"])
    assert (tree / "data" / "fake.csv").exists()
    assert not (tree / "quick").exists()


def test_an_explicit_data_dir_wins(tree, tmp_path_factory):
    folder = tmp_path_factory.mktemp("elsewhere")
    FAKE(["--quick"], data_dir=folder)
    assert (folder / "fake.csv").exists()
    assert not (tree / "quick").exists() and not (tree / "data").exists()


def _paper_out(env):
    """study.paths.PAPER_OUT in a fresh process with FREEZE2D_* set as ``env`` says."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("FREEZE2D_")} | env
    return subprocess.run(
        [sys.executable, "-c", "from study import paths; print(paths.PAPER_OUT)"],
        cwd=paths.ROOT,
        env=env,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()


def test_the_paper_outputs_follow_the_results_tree(tmp_path):
    # FREEZE2D_RESULTS=results/quick alone wrote the quick tree's figures, numbers and set-up into
    # the full paper's paper/generated (then failed on what it lacked there)
    assert _paper_out({"FREEZE2D_RESULTS": str(tmp_path)}) == str(tmp_path / "paper")
    assert _paper_out({}) == str(paths.PAPER)
    assert _paper_out({"FREEZE2D_RESULTS": str(paths.ROOT / "results")}) == str(paths.PAPER)
    given = tmp_path / "elsewhere"
    assert _paper_out({"FREEZE2D_RESULTS": str(tmp_path), "FREEZE2D_PAPER_OUT": str(given)}) == (
        str(given)
    )


# ---- the experiments with a command line of their own ----------------------------------------
def _fake_bench_freeze(monkeypatch):
    table = pd.DataFrame({"part": ["frozen_cost"], "ms": [1.0]})
    monkeypatch.setattr(bench_freeze, "run", lambda config, repeats: (table, {}))
    monkeypatch.setattr(bench_freeze, "verdicts", lambda table, config, fits: {})
    monkeypatch.setattr(bench_freeze, "summary", lambda *args: "")
    monkeypatch.setattr(bench_freeze, "scenes_of", lambda config, repeats: [])


def _fake_bench_step(monkeypatch):
    table = pd.DataFrame(
        {
            "system": ["sim-off"],
            "scene": ["rest_row"],
            "param": [2],
            "label": ["rest_row(2)"],
            "mode": ["long"],
            "relax_iterations": [1],
            "build_s": [0.0],
            "speedup_vs_pymunk": [1.0],
            "seeds": [None],  # a row of a scene with no seed, as bench_step writes it
        }
    )
    profile = pd.DataFrame({"stage": ["solve"], "label": ["rest_row(2)"], "ms_per_step": [0.1]})
    monkeypatch.setattr(bench_step, "run", lambda config, repeats, steps: (table, profile, []))


def _fake_peer_agreement(monkeypatch):
    table = pd.DataFrame({"case": ["fall"], "reference_kind": ["exact"]})
    monkeypatch.setattr(peer_agreement, "run", lambda sizes, repeats, steps: table)


@pytest.mark.parametrize(
    "module, fake, names",
    [
        (bench_freeze, _fake_bench_freeze, ["bench_freeze"]),
        (bench_step, _fake_bench_step, ["bench_step", "bench_step_profile"]),
        (peer_agreement, _fake_peer_agreement, ["peer_agreement"]),
    ],
    ids=["bench_freeze", "bench_step", "peer_agreement"],
)
def test_every_experiment_keeps_quick_results_apart(tree, monkeypatch, module, fake, names):
    fake(monkeypatch)
    module.main(["--quick"])
    for name in names:
        assert (tree / "quick" / "data" / f"{name}.csv").exists(), name
    assert not (tree / "data").exists()
