"""A sweep's process pool and its interrupts, end to end in a child process: pool workers die with
their parent however it dies, even when a worker is inside compiled code that holds the GIL."""

import os
import signal
import subprocess
import sys
import time

import pytest

from study import paths

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
    try:
        with open(f"/proc/{pid}/status") as f:
            return "\nState:\tZ" not in f.read()  # a zombie has exited
    except FileNotFoundError:
        return False


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
