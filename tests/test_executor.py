"""experiments.executor: the same results from every backend, and sweeps that resume."""
import json

import pytest

from experiments import executor


def square(task):
    """A module-level run (pools pickle it by name)."""
    return {"x": task["x"], "y": task["x"] ** 2}


def fails_on_three(task):
    if task["x"] == 3:
        raise ValueError("three")
    return {"x": task["x"]}


TASKS = [{"x": x} for x in range(6)]
EXPECTED = [{"x": x, "y": x * x} for x in range(6)]


def test_serial_and_pool_agree():
    assert executor.run_tasks(square, TASKS, workers=1) == EXPECTED
    assert executor.run_tasks(square, TASKS, workers=2) == EXPECTED


def test_a_failed_run_names_its_task():
    with pytest.raises(RuntimeError, match=r"run \{'x': 3\} failed: ValueError: three"):
        executor.run_tasks(fails_on_three, TASKS, workers=1)


def test_duplicate_keys_are_refused():
    with pytest.raises(ValueError, match="same key"):
        executor.run_tasks(square, [{"x": 1}, {"x": 1}], workers=1)


def test_interrupted_sweep_resumes_without_redoing(tmp_path):
    store = tmp_path / "sweep.jsonl"
    header = {"commit": "abc", "config": 1}
    with pytest.raises(RuntimeError):
        executor.run_tasks(fails_on_three, TASKS, workers=1, store=store, header=header)
    saved = [json.loads(line) for line in store.read_text().splitlines()]
    assert saved[0] == {"header": header}
    assert [e["key"] for e in saved[1:]] == [repr(t) for t in TASKS[:3]]   # 0, 1, 2 kept
    # a torn last line (killed mid-write) is ignored, and its run redone
    with open(store, "a") as f:
        f.write('{"key": "{\'x\': 4}", "resu')
    calls = []

    def counted(task):       # runs in this process (workers=1), so closures are fine
        calls.append(task["x"])
        return square(task)
    assert executor.run_tasks(counted, TASKS, workers=1, store=store,
                              header=header) == [{"x": 0}, {"x": 1}, {"x": 2}] + EXPECTED[3:]
    assert calls == [3, 4, 5]


def test_a_store_from_other_runs_is_set_aside(tmp_path):
    store = tmp_path / "sweep.jsonl"
    executor.run_tasks(square, TASKS[:2], workers=1, store=store, header={"commit": "old"})
    calls = []

    def counted(task):
        calls.append(task["x"])
        return square(task)
    executor.run_tasks(counted, TASKS[:2], workers=1, store=store, header={"commit": "new"})
    assert calls == [0, 1]
    assert (tmp_path / "sweep.jsonl.stale").exists()


def test_dask_local_cluster_gives_the_local_results(tmp_path, monkeypatch):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        monkeypatch.setenv(executor.SCHEDULER_ENV, cluster.scheduler_address)
        on_cluster = executor.run_tasks(square, TASKS, store=tmp_path / "d.jsonl",
                                        header={"c": 1})
    assert on_cluster == executor.run_tasks(square, TASKS, workers=2, scheduler="") == EXPECTED


def array_run(task):
    import numpy as np
    return {"x": task["x"], "positions": np.arange(3.0) * task["x"]}


def test_non_json_results_are_stored_exactly(tmp_path):
    """Sweeps whose runs return numpy arrays resume with the very same arrays."""
    import numpy as np
    store = tmp_path / "arrays.jsonl"
    first = executor.run_tasks(array_run, TASKS, workers=1, store=store, header={"c": 1})
    calls = []

    def never(task):
        calls.append(task)
        return array_run(task)
    again = executor.run_tasks(never, TASKS, workers=1, store=store, header={"c": 1})
    assert calls == []
    for a, b in zip(first, again):
        assert a["x"] == b["x"]
        np.testing.assert_array_equal(a["positions"], b["positions"])
        assert isinstance(b["positions"], np.ndarray)
