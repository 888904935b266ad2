"""study.executor: the same results from every backend, and sweeps that resume."""

import json

import pytest

from study import executor


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
    assert [e["key"] for e in saved[1:]] == [repr(t) for t in TASKS[:3]]  # 0, 1, 2 kept
    # a torn last line (killed mid-write) is ignored, and its run redone
    with open(store, "a") as f:
        f.write('{"key": "{\'x\': 4}", "resu')
    calls = []

    def counted(task):  # runs in this process (workers=1), so closures are fine
        calls.append(task["x"])
        return square(task)

    with pytest.warns(UserWarning, match="line 5: torn"):
        assert (
            executor.run_tasks(counted, TASKS, workers=1, store=store, header=header)
            == [{"x": 0}, {"x": 1}, {"x": 2}] + EXPECTED[3:]
        )
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
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        monkeypatch.setenv(executor.SCHEDULER_ENV, cluster.scheduler_address)
        on_cluster = executor.run_tasks(square, TASKS, store=tmp_path / "d.jsonl", header={"c": 1})
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


# ---- stores that cannot lie ----------------------------------------------------------------------
def _counting():
    calls = []

    def counted(task):  # runs in this process (workers=1), so closures are fine
        calls.append(task["x"])
        return square(task)

    return calls, counted


def test_a_changed_character_is_detected_and_its_run_redone(tmp_path):
    store = tmp_path / "sweep.jsonl"
    executor.run_tasks(square, TASKS, workers=1, store=store, header={"c": 1})
    lines = store.read_text().splitlines()
    assert '"y": 4' in lines[3]  # the run of x = 2
    lines[3] = lines[3].replace('"y": 4', '"y": 5')  # still valid JSON of the right shape
    store.write_text("\n".join(lines) + "\n")
    calls, counted = _counting()
    with pytest.warns(UserWarning, match="line 4: checksum mismatch"):
        assert (
            executor.run_tasks(counted, TASKS, workers=1, store=store, header={"c": 1}) == EXPECTED
        )
    assert calls == [2]
    calls, counted = _counting()  # the store is whole again
    assert executor.run_tasks(counted, TASKS, workers=1, store=store, header={"c": 1}) == EXPECTED
    assert calls == []


@pytest.mark.parametrize(
    "bad",
    [
        '{"foo": 1}',
        "[1, 2]",
        '"text"',
        "17",
        "null",
        '{"key": 5, "result": 1, "sha256": "0"}',
        '{"key": "{\'x\': 9}", "result": 1}',
        '{"key": "k", "pickle": "!!", "sha256": "0"}',
    ],
)
def test_a_line_of_the_wrong_shape_is_dropped_not_a_crash(tmp_path, bad):
    store = tmp_path / "sweep.jsonl"
    executor.run_tasks(square, TASKS[:3], workers=1, store=store, header={"c": 1})
    with open(store, "a") as f:
        f.write(bad + "\n")
    calls, counted = _counting()
    with pytest.warns(UserWarning, match="line 5"):
        assert (
            executor.run_tasks(counted, TASKS, workers=1, store=store, header={"c": 1}) == EXPECTED
        )
    assert calls == [3, 4, 5]
    assert bad not in store.read_text().splitlines()


def test_a_run_stored_after_a_torn_line_survives_the_next_resume(tmp_path):
    store = tmp_path / "sweep.jsonl"
    executor.run_tasks(square, TASKS[:2], workers=1, store=store, header={"c": 1})
    with open(store, "a") as f:
        f.write('{"key": "{\'x\': 2}", "resu')  # killed mid-write: no end of line
    with pytest.warns(UserWarning, match="torn"):
        executor.run_tasks(square, TASKS[:4], workers=1, store=store, header={"c": 1})
    calls, counted = _counting()
    assert executor.run_tasks(counted, TASKS, workers=1, store=store, header={"c": 1}) == EXPECTED
    assert calls == [4, 5]  # 2 and 3, stored after the fragment, kept


# ---- interrupts ----------------------------------------------------------------------------------
SWEEP = """
import os, sys, time
sys.path.insert(0, {here!r})
from study import executor

def slow(task):
    open(os.path.join({pids!r}, str(os.getpid())), "w").close()
    time.sleep(0.3)
    return {{"x": task["x"]}}

if __name__ == "__main__":
    executor.run_tasks(slow, [{{"x": x}} for x in range(40)], workers=2,
                       store={store!r}, header={{"c": 1}})
"""


def _alive(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            return "\nState:\tZ" not in f.read()  # a zombie has exited
    except FileNotFoundError:
        return False


def _start_sweep(tmp_path):
    import pathlib
    import subprocess
    import sys
    import time

    pids = tmp_path / "pids"
    pids.mkdir()
    store = tmp_path / "sweep.jsonl"
    script = tmp_path / "sweep.py"
    here = str(pathlib.Path(__file__).resolve().parents[2])
    script.write_text(SWEEP.format(here=here, pids=str(pids), store=str(store)))
    proc = subprocess.Popen(
        [sys.executable, str(script)], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    deadline = time.monotonic() + 60
    while len(store.read_text().splitlines()) < 3 if store.exists() else True:  # 2 runs done
        assert proc.poll() is None and time.monotonic() < deadline, proc.stderr.read()
        time.sleep(0.05)
    return proc, pids, store


def _workers_gone(pids, within):
    import time

    deadline = time.monotonic() + within
    while any(_alive(int(p.name)) for p in pids.iterdir()):
        if time.monotonic() > deadline:
            return False
        time.sleep(0.05)
    return True


def test_ctrl_c_stops_a_sweep_at_once_and_keeps_what_finished(tmp_path):
    import signal
    import subprocess
    import time

    proc, pids, store = _start_sweep(tmp_path)
    t0 = time.monotonic()
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(timeout=3)  # 38 queued runs of 0.3 s on 2 workers would take 5.7 s
    except subprocess.TimeoutExpired:
        proc.kill()
        raise AssertionError("the sweep did not stop within 3 s of SIGINT")
    assert proc.returncode != 0 and "KeyboardInterrupt" in proc.stderr.read()
    assert time.monotonic() - t0 < 3
    assert _workers_gone(pids, within=2)
    done = [json.loads(line) for line in store.read_text().splitlines()[1:]]
    assert 2 <= len(done) < 40 and all("sha256" in e for e in done)


@pytest.mark.parametrize("signum", ["SIGTERM", "SIGKILL"])
def test_a_killed_sweep_leaves_no_workers_behind(tmp_path, signum):
    import signal

    proc, pids, _ = _start_sweep(tmp_path)
    proc.send_signal(getattr(signal, signum))
    proc.wait(timeout=10)
    assert _workers_gone(pids, within=2), "pool workers outlived their parent"
