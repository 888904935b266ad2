"""experiments.bench_fast_paths: quick mode end to end into a temporary folder, the PAYS rule on
known numbers, and that it reads sim through the public API only (World, profile, inspect).
No speed is asserted (speed lives in the results)."""

import ast
import json
import pathlib

import pandas as pd
import pytest

from experiments import bench_fast_paths as bfp
from sim.data import STAGES

SOURCE = pathlib.Path(bfp.__file__)


def test_uses_only_public_names_of_sim():
    """No sim submodule imported, no underscore attribute read (world._counters and the like
    were what broke when the solver changed)."""
    tree = ast.parse(SOURCE.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            assert not (node.module or "").startswith("sim"), node.module
            assert not any(a.name.startswith("_") for a in node.names), node.module
        if isinstance(node, ast.Import):
            assert all(a.name == "sim" or not a.name.startswith("sim") for a in node.names)
        if isinstance(node, ast.Attribute):
            assert not (node.attr.startswith("_") and not node.attr.startswith("__")), node.attr


def _table(friction_saving, sat_bound, rotation_bound, statics_saving, quiet_saving=0.9):
    rows = [
        ("quiet", "pyramid(10)", "fast_paths=True", quiet_saving),
        ("friction", "columns(mu=0.0)", "fast_paths=True", friction_saving),
        ("friction", "columns(mu=0.6)", "fast_paths=True", 0.01),
        ("box_sat", "pyramid(40)", "narrowphase stage", sat_bound),
        ("rotation", "rest_row(1000)", "broadphase stage", rotation_bound),
        ("statics", "rest_row(1000)", "ledges", statics_saving),
    ]
    return pd.DataFrame(
        [{"part": p, "scene": s, "variant": v, "saving_share_of_step": x} for p, s, v, x in rows]
    )


def test_verdicts_follow_the_five_percent_rule():
    v = {r["candidate"]: r for r in bfp.verdicts(_table(0.08, 0.03, 0.02, -0.01))}
    assert v["friction"]["verdict"] == "kept"
    assert v["box_sat"]["verdict"].startswith("removed: cannot pay")
    assert v["rotation"]["verdict"] == "not built: cannot pay"
    assert v["quiet"]["verdict"] == "kept"
    v = {r["candidate"]: r for r in bfp.verdicts(_table(0.04, 0.07, 0.12, 0.0, 0.03))}
    assert v["friction"]["verdict"] == "does not pay"
    assert v["quiet"]["verdict"] == "does not pay"
    assert "looser" in v["box_sat"]["verdict"]
    assert v["rotation"]["verdict"].startswith("not built: may pay")


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bench_fast_paths")
    bfp.main(["--quick"], data_dir=folder)
    return (
        pd.read_csv(folder / "bench_fast_paths.csv"),
        json.loads((folder / "bench_fast_paths.json").read_text()),
    )


def test_quick_run_measures_every_candidate(quick):
    table, meta = quick
    assert set(table["part"]) == {"friction", "box_sat", "statics", "rotation", "quiet"}
    assert (table["ms_per_step_median"] > 0).all()
    friction = table[table["part"] == "friction"]
    assert len(friction) == 4 and set(friction["variant"]) == {
        "fast_paths=False",
        "fast_paths=True",
    }
    for part, stage in (("box_sat", "narrowphase"), ("rotation", "broadphase")):
        rows = table[table["part"] == part]
        assert stage in STAGES
        share = rows["saving_share_of_step"].dropna()
        assert len(share) == 1 and 0 < share.iloc[0] < 1  # a stage is part of a step
    p = meta["parameters"]
    assert [v["candidate"] for v in p["verdicts"]] == [
        "friction",
        "box_sat",
        "rotation",
        "quiet",
        "statics",
    ]
    quiet = table[table["part"] == "quiet"]
    assert list(quiet["variant"]) == ["fast_paths=('friction',)", "fast_paths=True"]
    # the pyramid was frozen when timed (else the comparison measures nothing), and the fast
    # path skipped steps
    assert all("frozen before the timing: True" in n for n in quiet["note"])
    skipped = quiet["note"].iloc[1]
    assert "steps skipped" in skipped and " 0 steps skipped" not in skipped
    assert p["pays"] == bfp.PAYS
    assert p["system_settings"]["sim-off"]["substeps"] == p["substeps"] >= 1
    assert meta["script"] == "bench_fast_paths" and meta["git"]["commit"]
