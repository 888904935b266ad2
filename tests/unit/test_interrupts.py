"""A long ``World.step`` stops on Ctrl-C within a fraction of a second, at a step boundary, with
the World whole; a World that diverged refuses to step on and says why."""

import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import sim

ROOT = Path(__file__).resolve().parents[2]

SCRIPT = """
import sys, time
sys.path.insert(0, {root!r})
import numpy as np
import sim
w = sim.World(sim.scenes.pyramid(6))
w.step(2)                                     # compiled (or loaded from the cache) before ready
print("ready", flush=True)
start = time.perf_counter()
try:
    w.step(10 ** 9)
except KeyboardInterrupt as exc:
    print("interrupted", time.perf_counter() - start, w.step_count, flush=True)
k = w.step_count
w.step(5)
fresh = sim.World(sim.scenes.pyramid(6)).step(k + 5)
same = np.array_equal(w.positions, fresh.positions) and np.array_equal(w.angles, fresh.angles)
print("identical" if same else "different", flush=True)
"""


def _line(proc, timeout):
    """The next line the process prints, or None after ``timeout`` s."""
    ready, _, _ = select.select([proc.stdout], [], [], timeout)
    return proc.stdout.readline().strip() if ready else None


def test_ctrl_c_stops_a_long_step_at_a_step_boundary():
    proc = subprocess.Popen(
        [sys.executable, "-c", SCRIPT.format(root=str(ROOT))],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        bufsize=1,
    )
    try:
        assert _line(proc, 600) == "ready"
        time.sleep(0.5)
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)  # as Ctrl-C
        line = _line(proc, 5.0)
        stopped = time.monotonic() - sent
        assert line is not None, "step(10**9) did not stop within 5 s of SIGINT"
        assert line.split()[0] == "interrupted", (line, proc.stderr.read())
        assert stopped < 1.0, f"took {stopped:.2f} s to stop"
        assert int(line.split()[2]) > 2
        assert _line(proc, 120) == "identical"
        assert proc.wait(timeout=60) == 0
    finally:
        proc.kill()


def test_a_diverged_world_refuses_to_step_again_and_says_why():
    fast = sim.Body.box(1, 1, position=(0.0, 5.0), velocity=(1e12, 0.0), name="bullet")
    world = sim.World(
        sim.Scene(bodies=[sim.Body.box(1, 1, position=(-10, 0.5)), fast], gravity=(0, 0)), dt=1e297
    )
    with pytest.raises(sim.SimulationError, match=r"step 1: bullet diverged"):
        world.step(5)
    for _ in range(2):
        with pytest.raises(
            sim.SimulationError, match=r"step 1: bullet diverged.*cannot step any further"
        ):
            world.step(1)
    assert world.step_count == 1


def test_cutting_a_run_into_pieces_changes_nothing(monkeypatch):
    one = sim.World(sim.scenes.drop(20, seed=1)).step(200)
    monkeypatch.setattr(sim.world, "FIRST_CHUNK", 3)
    monkeypatch.setattr(sim.world, "CHUNK_S", 1e-5)  # pieces of a few steps
    cut = sim.World(sim.scenes.drop(20, seed=1)).step(200)
    assert np.array_equal(one.positions, cut.positions)
    assert np.array_equal(one.velocities, cut.velocities)
    assert one.max_penetration == cut.max_penetration and one.penetration == cut.penetration


@pytest.mark.parametrize("name", ["bench_step", "bench_freeze", "peer_agreement"])
def test_ctrl_c_in_a_timed_experiment_is_one_line_and_status_130(
    name, monkeypatch, tmp_path, capsys
):
    """The timed experiments have their own command line (no sweep store to resume): Ctrl-C
    printed a 14-frame traceback there (until 2026-12-07). Now one line, nothing written."""
    import importlib

    module = importlib.import_module(f"experiments.{name}")

    def stopped(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(module, "run", stopped)
    with pytest.raises(SystemExit) as exit_:
        module.main(["--quick"], data_dir=tmp_path)
    assert exit_.value.code == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"python -m experiments.{name}: stopped (Ctrl-C); nothing kept"]
    assert list(tmp_path.iterdir()) == []
