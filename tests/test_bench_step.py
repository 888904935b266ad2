"""experiments.bench_step end to end on --quick sizes, into a temporary results folder."""
import json
import math

import pandas as pd

from experiments import bench_step


def test_quick_run_writes_every_row_and_the_metadata(tmp_path):
    bench_step.main(["--quick"], data_dir=tmp_path)
    table = pd.read_csv(tmp_path / "bench_step.csv")
    expected = {(scene, p, system) for scene, params in bench_step.QUICK.items() for p in params
                for system in ("sim-off", "pymunk")}
    assert set(zip(table["scene"], table["param"], table["system"])) == expected
    assert len(table) == len(expected)
    for column in ("ms_per_step_median", "ms_per_step_min"):
        assert (table[column] > 0).all() and table[column].map(math.isfinite).all()
    assert (table["ms_per_step_min"] <= table["ms_per_step_median"]).all()
    assert (table["repeats"] == 3).all() and (table["steps_per_repeat"] == 10).all()
    sim_rows = table[table["system"] == "sim-off"]
    assert (sim_rows["speedup_vs_pymunk"] > 0).all()
    assert table.loc[table["system"] == "pymunk", "speedup_vs_pymunk"].isna().all()
    assert (table["max_displacement_m"] < 0.5).all()       # resting scenes stayed put

    meta = json.loads((tmp_path / "bench_step.json").read_text())
    for key in ("script", "scenes", "parameters", "seed", "git", "packages", "python",
                "platform", "cpu", "cpu_count", "date_utc"):
        assert key in meta
    assert meta["script"] == "bench_step"
    assert {"commit", "dirty"} <= set(meta["git"])
    assert meta["packages"]["pymunk"] == "7.3.1"
    assert len(meta["scenes"]) == 4
    assert not list(tmp_path.glob("*.tmp"))                 # atomic writes left no temp files


def test_metadata_survives_missing_git_and_packages(monkeypatch):
    from experiments import metadata

    def no_git(*args, **kwargs):
        raise FileNotFoundError("git")
    monkeypatch.setattr(metadata.subprocess, "run", no_git)
    monkeypatch.setattr(metadata, "PACKAGES", ("numpy", "no-such-package-freeze2d"))
    meta = metadata.collect(None, {"x": 1}, script="t")
    assert meta["git"] == {"commit": "unknown", "dirty": "unknown"}
    assert meta["packages"]["no-such-package-freeze2d"] == "not installed"
    json.dumps(meta)
