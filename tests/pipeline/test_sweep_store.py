"""An interrupted sweep resumes only runs made by the same code, configuration and engines: its
store's header (study.common.sweep_store) names each, and a store with another header is set
aside (study.executor.ResultStore)."""

import argparse
import importlib.metadata

from study import common, executor

TASKS = [{"x": x} for x in range(3)]


def test_a_store_made_under_other_package_versions_is_not_resumed(tmp_path, monkeypatch):
    # the header named the commit, the configuration and the sources, not the engines: after a
    # changed pin (pymunk, numba...), a resumed sweep mixed runs of two engine versions
    args = argparse.Namespace(quick=True, data_dir=tmp_path / "data")
    store, header = common.sweep_store("fake", args, {"n": 3})
    assert header["packages"]["numpy"] == importlib.metadata.version("numpy")
    executor.run_tasks(lambda t: t["x"], TASKS, workers=1, store=store, header=header)

    real = importlib.metadata.version
    monkeypatch.setattr(
        importlib.metadata, "version", lambda name: "0.0" if name == "numpy" else real(name)
    )
    store, header = common.sweep_store("fake", args, {"n": 3})
    calls = []
    executor.run_tasks(calls.append, TASKS, workers=1, store=store, header=header)
    assert calls == TASKS  # every run made again
    assert store.with_suffix(".jsonl.stale").exists()  # the old runs set aside, not mixed in


def test_a_store_resumes_across_a_commit_that_changed_no_source(tmp_path, monkeypatch):
    """The header names what runs (configuration, sources, engines), not the commit: a commit of
    the README's results block threw an interrupted sweep's finished runs away (until
    2026-12-07)."""
    args = argparse.Namespace(quick=True, data_dir=tmp_path / "data")
    store, header = common.sweep_store("fake", args, {"n": 3})
    executor.run_tasks(lambda t: t["x"], TASKS[:2], workers=1, store=store, header=header)
    another = {"commit": "another", "dirty": False}
    monkeypatch.setattr(common, "git_state", lambda: another, raising=False)
    store, header = common.sweep_store("fake", args, {"n": 3})
    calls = []
    executor.run_tasks(calls.append, TASKS, workers=1, store=store, header=header)
    assert calls == TASKS[2:]  # only the run not made before
