"""The step loop's stages run without Numba's reference counting (sim/jit.py, ``lean_kernel``).

With reference counting, a kernel pays an atomic increment and decrement for every array of the
World's state it is passed, and for every array an inlined helper is passed inside its loops: 54%
of a one-body step, and 14 us of a 24-body step under ``sleep`` (its contact walk), before these
kernels were made lean. Nothing in the results shows it (the answers are bit-identical either
way), so this checks the compile options themselves.

A kernel called with a constant argument is compiled once more for the constant's literal type
(sim/jit.py, LITERALS); a test reads Numba's cache index for such signatures. And Numba's inliner
is made to share its copies of a callee's scope (sim/numba_inlining.py): the same machine code in
less than half the compile time, checked here on a kernel compiled both ways."""

import importlib
import pickle
import re
from pathlib import Path

import numba
import numpy as np
import pytest
from numba import njit
from numba.core import inline_closurecall

import sim
import sim.kernel
from sim import activity, numba_inlining, sweep
from sim.freeze import (
    certificate,
    extended,
    extended_freezing,
    extended_rest,
    extended_wake,
    paper,
    sleep,
)

#: every kernel the step loop calls each step, or each step a policy is active, that allocates
#: nothing (a lean kernel cannot allocate: Numba refuses to compile it)
LEAN = {
    "broadphase": sim.kernel.broadphase,
    "rebuild_resting": sim.kernel.rebuild_resting,
    "solve_step": sim.kernel.solve_step,
    "first_diverged": sim.kernel.first_diverged,
    "resting_bodies": activity.resting_bodies,
    "sweep_fast_bodies": sweep.sweep_fast_bodies,
    "sleep.before_solve": sleep.before_solve,
    "sleep._timers_and_islands": sleep._timers_and_islands,
    "paper.before_solve": paper.before_solve,
    "paper._after_solve": paper._after_solve,
    "extended._impacts": extended._impacts,
    "extended._candidates": extended._candidates,
    "extended_freezing.freeze_certified": extended_freezing.freeze_certified,
    "certificate._holds_into": certificate._holds_into,
    "extended_rest.whole_groups": extended_rest.whole_groups,
    "extended_rest.on_the_awake": extended_rest.on_the_awake,
    "extended_wake.wake_supported": extended_wake.wake_supported,
    "extended_wake.drop_links_of_awake": extended_wake.drop_links_of_awake,
    "extended_wake.judge_touched": extended_wake.judge_touched,
    "extended_wake.transmit": extended_wake.transmit,
}


@pytest.mark.parametrize("name", sorted(LEAN))
def test_step_kernels_are_lean(name):
    assert LEAN[name].targetoptions.get("_nrt") is False, (
        f"{name} is compiled with reference counting: every array it is passed costs two atomic "
        f"operations per call (see sim/jit.py)"
    )


def _cached_signatures():
    """{kernel file stem: [signature strings]} from Numba's on-disk cache index of this source
    tree (``sim/__init__`` keys the folder by the sources). The index format is Numba's own
    (``numba.core.caching.IndexDataCacheFile``; numba is pinned): a pickled version, then a
    pickled (stamp, {(signature, target, ...): file}) pair."""
    out = {}
    for index in Path(numba.config.CACHE_DIR).rglob("*.nbi"):
        with open(index, "rb") as f:
            pickle.load(f)
            _, overloads = pickle.loads(f.read())
        out[index.stem] = [str(key[0]) for key in overloads]
    return out


def test_no_kernel_is_compiled_for_a_literal_argument():
    # compile (or load) everything a step can run: the presolve, every policy's hooks (one
    # ``run`` holds them all), the fast-body sweep
    world = sim.World(sim.scenes.stack(3), freeze="extended")
    world.step(2)
    signatures = _cached_signatures()
    relax = [k for k in signatures if k.startswith("batches.relax-")]
    assert relax, f"no cache index of the relax sweep under {numba.config.CACHE_DIR}"
    literal = {k: [s for s in v if "Literal[" in s] for k, v in signatures.items()}
    literal = {k: v for k, v in literal.items() if v}
    assert not literal, (
        "kernels compiled a second time for a constant argument (pass np.int64(...) / "
        f"np.bool_(...) instead; sim/jit.py, LITERALS): {sorted(literal)}"
    )


def test_the_inliner_shares_scope_copies_on_the_pinned_numba():
    # on another Numba the kernels compile as Numba does it (slower): look at numba_inlining again
    assert numba.__version__ == numba_inlining.PINNED_NUMBA
    assert numba_inlining.enabled()


def _compiled_kernel():
    """Machine code of a fresh kernel that inlines helpers (branches, a loop, a helper used
    twice), with the symbols' names (which carry a per-compile number) left out."""

    @njit(inline="always")
    def clamp(x, lo, hi):
        return lo if x < lo else (hi if x > hi else x)

    @njit(inline="always")
    def row(v, k, lo, hi):
        total = 0.0
        for i in range(v.shape[0]):
            total += clamp(v[i] * k, lo, hi) if v[i] > 0.0 else -clamp(-v[i], lo, hi)
        return total

    @njit(cache=False)
    def kernel(v, k):
        return row(v, k, 0.0, 1.0) + row(v, -k, -1.0, 2.0)

    v = np.linspace(-2.0, 2.0, 9)
    value = kernel(v, 0.7)
    asm = kernel.inspect_asm(kernel.signatures[0])
    return value, re.sub(r"_ZN\S+", "NAME", asm)


def test_shared_scope_copies_compile_to_the_same_code():
    was = numba_inlining.set_enabled(False)
    try:
        numba_value, numba_code = _compiled_kernel()
        numba_inlining.set_enabled(True)
        shared_value, shared_code = _compiled_kernel()
    finally:
        numba_inlining.set_enabled(was)
    assert shared_value == numba_value
    assert shared_code == numba_code


def test_importing_the_inliner_patch_again_keeps_one_patch():
    # importlib.reload (IPython's autoreload) runs the module again while its patch is in place:
    # the new patch must wrap Numba's method, not the old patch (which would call itself)
    try:
        importlib.reload(numba_inlining)
        importlib.reload(numba_inlining)
        assert numba_inlining.enabled()  # the last import's stand-in is the one installed
        patched = inline_closurecall.InlineWorker.inline_ir
        assert not hasattr(patched.numba_inline_ir, "numba_inline_ir")  # wraps Numba's own
        value, _ = _compiled_kernel()
        numba_inlining.set_enabled(False)
        assert value == _compiled_kernel()[0]
    finally:
        numba_inlining.set_enabled(True)
