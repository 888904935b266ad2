"""A cycle counter readable from compiled code, so the step loop can time its own stages.

Timing stages from Python would mean calling each stage as its own compiled function, a second
step loop that could drift from the real one. Instead ``kernel.step`` reads the processor's
time-stamp counter (LLVM's ``readcyclecounter``: ``rdtsc`` on x86, the virtual counter on ARM64)
around each named stage when ``settings.profile`` is on; a read costs ~20 cycles.
``ticks_per_second``
calibrates the counter against ``time.perf_counter`` (the counter runs at a constant rate on any
CPU this project runs on: Linux's ``constant_tsc``).
"""

import time

from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from .jit import kernel


@intrinsic
def cycles(typingctx):
    """The cycle counter, int64."""

    def codegen(context, builder, signature, args):
        fn = builder.module.declare_intrinsic(
            "llvm.readcyclecounter", fnty=ir.FunctionType(ir.IntType(64), [])
        )
        return builder.call(fn, [])

    return types.int64(), codegen


@kernel
def _read():
    return cycles()


_RATE = []


def ticks_per_second():
    """Counter ticks per second, measured once per process over ~20 ms."""
    if not _RATE:
        _read()  # compile first
        t0, c0 = time.perf_counter(), _read()
        while time.perf_counter() - t0 < 0.02:
            pass
        t1, c1 = time.perf_counter(), _read()
        _RATE.append((c1 - c0) / (t1 - t0))
    return _RATE[0]
