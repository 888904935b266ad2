"""Same scene, parameters and seed give bit-identical trajectories: in one process, across
processes, and whatever size the contact buffers started at (they grow mid-run)."""

import hashlib
import os
import pathlib
import subprocess
import sys

import numpy as np

import sim
import sim.kernel

STEPS = 240


def fingerprint(world):
    """Hash of every body's exact transform and velocity (bit-level), as Box2D's determinism
    test."""
    h = hashlib.sha256()
    for arr in (world.positions, world.angles, world.velocities, world.angular_velocities):
        h.update(np.ascontiguousarray(arr).tobytes())
    return h.hexdigest()


def run(seed=4, n=40):
    world = sim.World(sim.scenes.drop(n, seed=seed))
    world.step(STEPS)
    return world


def fingerprint_in_another_process(env):
    """``fingerprint(run())`` computed by a fresh Python process with environment ``env``."""
    code = (
        "import sys; sys.path[:0] = ['tests', 'tests/unit']; import test_determinism as t; "
        "print(t.fingerprint(t.run()))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        cwd=str(pathlib.Path(__file__).parents[2]),
        env=env,
    )
    return out.stdout.strip()


def test_repeat_runs_are_bit_identical():
    assert fingerprint(run()) == fingerprint(run())


def test_different_seeds_differ():
    assert fingerprint(run(seed=4)) != fingerprint(run(seed=5))


def test_stepping_in_chunks_equals_one_call():
    a = sim.World(sim.scenes.drop(40, seed=4))
    a.step(STEPS)
    b = sim.World(sim.scenes.drop(40, seed=4))
    for _ in range(STEPS // 8):
        b.step(8)
    assert fingerprint(a) == fingerprint(b)


def test_buffer_growth_does_not_change_the_trajectory(monkeypatch):
    reference = fingerprint(run())
    # every buffer the step loop can outgrow starts with room for 2: contacts, both grids, the
    # solver's batches
    monkeypatch.setattr(sim.world, "INITIAL_CAPACITY", 2)
    world = run()
    assert world.inspect().regrown > 3  # it did grow, more than once
    assert fingerprint(world) == reference


def test_identical_across_processes(tmp_path):
    """Another process gives the same run, and it runs the other kind of compiled code: where
    this process compiled the kernels afresh (a fresh clone), the other loads them from Numba's
    cache; where this one loaded them from the cache, the other compiles afresh into an empty
    one. Fresh and cached code have differed: a buffer on the arms pass's stack (an ``alloca``
    intrinsic, reverted at 83793f8) gave drop(40, seed 4) one trajectory compiled and another
    loaded, apart from step 19, while every process of either kind agreed with the others."""
    reference = fingerprint(run())
    env = dict(os.environ)
    if sim.kernel.run.stats.cache_hits:  # this process loaded the step loop from the cache
        env["NUMBA_CACHE_DIR"] = str(tmp_path / "numba_cache")
    assert fingerprint_in_another_process(env) == reference


def test_identical_under_another_blas_kernel():
    """Results do not depend on which BLAS kernel numpy's OpenBLAS picks for this CPU. They did:
    body masses, centroids and inertias went through np.dot, whose AVX-512 kernel rounds
    otherwise than its AVX2 one, and drop(30) piles settled differently on an Intel AVX-512
    machine than on an AMD one (seed 1 came to rest on one and not on the other). Another process
    runs the same pile with OpenBLAS forced to its plainest x86-64 kernel (``Prescott``, SSE3);
    elsewhere (ARM) the variable is ignored and the two runs are trivially the same."""
    reference = fingerprint(run())
    env = dict(os.environ, OPENBLAS_CORETYPE="Prescott")
    assert fingerprint_in_another_process(env) == reference
