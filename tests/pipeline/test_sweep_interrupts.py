"""A sweep's process pool and its interrupts, end to end in a child process: pool workers die with
their parent however it dies, even when a worker is inside compiled code that holds the GIL."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from study import common, executor, paths

#: a sweep whose runs hold the GIL (a C loop, as a Numba kernel without nogil does) for minutes
SWEEP = """
import os, sys
sys.path.insert(0, {root!r})  # this checkout's study, not an installed one's
from study import executor

def busy(task):
    open(os.path.join({pids!r}, str(os.getpid())), "w").close()
    return sum(range(10**12))  # one C call: the GIL is never released

if __name__ == "__main__":
    executor.run_tasks(busy, [{{"x": x}} for x in range(4)], workers=2)
"""


def _alive(pid):
    """Whether process ``pid`` still runs: its state in /proc (after the command's closing
    parenthesis) is not Z, a zombie that has exited and waits to be reaped."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rpartition(")")[2].split()[0]
    except FileNotFoundError:
        return False
    return state != "Z"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG is Linux's")
@pytest.mark.parametrize("signum", ["SIGKILL", "SIGTERM"])
def test_workers_inside_compiled_code_die_with_their_parent(tmp_path, signum):
    # The workers' watcher thread needs the GIL to notice its parent is gone: a worker inside a
    # kernel outlived its killed parent by seconds (by the whole run, for a long one). The kernel
    # kills each worker when its parent dies (PR_SET_PDEATHSIG), GIL or not.
    pids = tmp_path / "pids"
    pids.mkdir()
    script = tmp_path / "sweep.py"
    script.write_text(SWEEP.format(root=str(paths.ROOT), pids=str(pids)))
    proc = subprocess.Popen(
        [sys.executable, str(script)],
        cwd=paths.ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        deadline = time.monotonic() + 60
        while len(list(pids.iterdir())) < 2:
            assert proc.poll() is None and time.monotonic() < deadline
            time.sleep(0.05)
        time.sleep(0.2)  # both inside their C loop
        workers = [int(p.name) for p in pids.iterdir()]
        proc.send_signal(getattr(signal, signum))
        proc.wait(timeout=10)
        t0 = time.monotonic()
        while any(_alive(pid) for pid in workers) and time.monotonic() - t0 < 5:
            time.sleep(0.01)
        gone_after = time.monotonic() - t0
        left = [pid for pid in workers if _alive(pid)]
    finally:
        proc.kill()
        for pid in [int(p.name) for p in pids.iterdir()]:
            if _alive(pid):
                os.kill(pid, signal.SIGKILL)
    assert not left and gone_after < 0.5, f"workers alive {gone_after:.2f} s after their parent"


def _stopped_sweep(config, args):
    """A sweep that finishes two runs into its store, then is stopped by Ctrl-C."""
    store, header = common.sweep_store("fake", args, config)
    executor.run_tasks(abs, [1, 2], workers=1, store=store, header=header)
    raise KeyboardInterrupt


def _stopped_at_once(config, args):
    raise KeyboardInterrupt


@pytest.mark.parametrize(
    "run, said",
    [
        (_stopped_sweep, "stopped (Ctrl-C); 2 finished run(s) kept in {store}: the same command"),
        (_stopped_at_once, "stopped (Ctrl-C); nothing kept ({data}/fake.csv left as it was)"),
    ],
    ids=["sweep", "nothing_stored"],
)
def test_ctrl_c_says_in_one_line_what_was_kept(tmp_path, capsys, run, said):
    # a sweep stopped by Ctrl-C printed a KeyboardInterrupt traceback
    data = tmp_path / "data"
    data.mkdir()
    (data / "fake.csv").write_text("x\n1\n")
    main = common.entry("fake", "A fake.", {"n": 2}, {"n": 1}, run, sweep=True)
    try:
        main(["--quick"], data_dir=data)
    except KeyboardInterrupt:  # (caught: pytest would take it for the user's and stop)
        pytest.fail("Ctrl-C came out as a KeyboardInterrupt traceback")
    except SystemExit as stop:
        assert stop.code == 130  # as the shell's for SIGINT
    else:
        pytest.fail("a stopped run exited normally")
    err = capsys.readouterr().err.strip().splitlines()
    store = tmp_path / "partial" / "fake-quick.jsonl"
    assert err[-1].startswith("python -m experiments.fake: " + said.format(store=store, data=data))
    assert (data / "fake.csv").read_text() == "x\n1\n"
