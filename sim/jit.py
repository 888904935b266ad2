"""The decorators every kernel uses, so that compilation options are set in one place.

- cache=True: compiled code is stored on disk (see ``sim/__init__``, which keys the cache folder by
a
  hash of the sources, because Numba does not notice edits to a kernel's callees).
- error_model="numpy": a float division by zero gives inf/nan instead of raising; the Python model
  puts a test-and-raise branch on every division, which costs ~15% of a solver sweep. Non-finite
  state is caught once per step instead (``kernel.first_diverged``).

Vectorisation (see ``sim/soft_step/``). The contact solver works on batches of ``LANES``
constraints laid out field by field, and relies on LLVM's SLP vectoriser to turn each batch's
lane loop into packed instructions (``experiments/bench_kernels.py`` shows them in the compiled
code). Numba switches SLP off by default, so it is switched on here, before any kernel compiles.
It changes no result: SLP packs independent scalar operations into vector registers and never
reorders a sum. Two more conditions are met in the batch kernels themselves: every index is
unsigned (a signed index gets a wrap-around select per access, which breaks the consecutive
addresses SLP needs), and a batch lives in one flat array at compile-time offsets (two arrays, or
one with a run-time row stride, might alias, and LLVM then keeps the scalar code).
"""

import numba
from numba import njit

from . import numba_inlining

numba.config.SLP_VECTORIZE = 1
# Numba's inliner copies a callee's whole scope once per block: shared per callee instead, the
# kernels compile in less than half the time to the same machine code (see numba_inlining)
numba_inlining.set_enabled(True)

kernel = njit(cache=True, error_model="numpy")

#: For helpers called inside hot loops: a call that LLVM does not inline passes every array
#: argument through a reference-count increment and decrement (atomic operations), which made the
#: block solver's call cost more than its arithmetic. Numba-level inlining removes the call.
inline_kernel = njit(cache=True, error_model="numpy", inline="always")

#: For kernels that allocate nothing: compiled without Numba's reference counting (a private but
#: long-standing Numba flag; the version is pinned). With it, every array an inlined helper takes
#: costs an atomic increment and decrement per call: half of the narrowphase's time. The same
#: holds for a kernel's own arguments: a kernel that takes the World's state (named tuples of
#: dozens of arrays) pays two atomic operations per array per call. The step loop's stages
#: (broadphase, solve_step, the sweeps, first_diverged, ...) are therefore lean; with them
#: compiled with reference counting, the increments were 54% of a step of one falling body (8.0
#: against 4.4 us a step) and ~9% of drop(200)'s (perf, 2026-12-04). A lean kernel cannot call
#: one that allocates (Numba compiles the callee with the caller's flags), so the loop itself
#: (``kernel.run``) keeps counting, and so do the freeze policies' hooks, which allocate their
#: work arrays: each hook is inlined into ``run`` (a call would count every array of the state
#: again), allocates, and hands the arrays to a lean kernel that walks the bodies and contacts
#: (``sleep.before_solve`` took 14 us a step on a 24-body landing before, 0.7 after). ``run``
#: calls them only when they have work (a policy other than ``off``; contacts to sort).
#: tests/unit/test_jit.py lists the kernels that must stay lean.
lean_kernel = njit(cache=True, error_model="numpy", _nrt=False)

#: LITERALS. A kernel called from another with a constant argument (``f(x, 0)``, ``f(x, False)``,
#: or a count started at ``n = 0`` and passed on) is compiled for that constant's literal type
#: (``Literal[int](0)``) besides its ordinary one (``int64``): the callee is compiled twice, and so
#: is every kernel it calls that is not inlined. Seven kernels compiled so twice cost 27 of the
#: 205 s that the first step of a fresh clone spent compiling (the relax sweep alone 15 s, for the
#: presolve's ``False``; measured with Numba's compile events, 2026-12-06). So a constant passed
#: to a kernel is made a run-time value (``np.int64(0)``, ``np.bool_(False)``), the same number to
#: the bit; ``tests/unit/test_jit.py`` checks that no compiled kernel has a literal in its
#: signature.

#: The only fast-math flag used anywhere: ``contract`` lets LLVM fuse a multiply and an add into
#: one fused multiply-add (one rounding instead of two). It is used by the solver's batch kernels
#: alone, where it saves ~20% of a sweep. Runs stay bit-identical on one machine (the same compiled
#: code gives the same result every time); across machines, results agree bit for bit only when
#: both CPUs have FMA (every x86-64 since 2013, every ARM64) and the same LLVM (pinned numba) is
#: used (and no result goes through BLAS: see ``geometry.mass_properties``). No other flag is
#: set: no reassociation (sums keep their order, so vector width does not change a result) and no
#: "no NaN" (a NaN must reach the divergence check, not be optimised away).
wide_kernel = njit(cache=True, error_model="numpy", _nrt=False, fastmath={"contract"})
wide_inline = njit(cache=True, error_model="numpy", inline="always", fastmath={"contract"})
