"""The arms pass's and the warm start's scratch: one batch's body rows, gathered from the state so
that the lanes compute on consecutive addresses (packed), in a buffer on the kernel's own stack.

Why the stack. The gathered rows are written, used and dropped batch by batch; a buffer that
every batch reuses stays in the L1 cache, where rows kept in each batch's own run of fields are
more cache lines per batch that the pass must fetch before overwriting them (rest_row(5000)'s
batches, 2.2 MB, do not fit the 2 MB L2 cache). A second array argument would not do: LLVM must
assume it may overlap the batch fields, and keeps the scalar code. A stack buffer (an ``alloca``
in the kernel's entry block) is an object of its own that nothing else can point into, so the
loads and stores stay independent and the lane loops are still vectorised
(``experiments/bench_kernels.py`` checks the packed instructions).

Why not the sweeps. Solve, relax and restitution gather the velocities into the batch's own
VELOCITIES fields (``layout``) instead: with this buffer they ran slower (World.profile,
interleaved: pyramid(40)'s solve 31 -> 46 us a step, relax 46 -> 65), in the L1 cache as well as
out of it, for a reason not found (the compiled loops have the same shape). The arms pass and the
warm start, passes that read each batch once, gained: rest_row(5000) 77 -> 50 and 82 -> 56 us a
step, pyramid(40) 21 -> 14 and 22 -> 16."""

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array

from .layout import LANES, U64

#: scratch fields: VAX..WB (the sweeps: gathered, changed, scattered back) or DPAX..QSB (the arms
#: pass: gathered, read); a kernel holds one set at a time
GATHER_FIELDS = 8
SIZE = GATHER_FIELDS * LANES
VAX, VAY, WA, VBX, VBY, WB, _G6, _G7 = [U64(k * LANES) for k in range(GATHER_FIELDS)]
DPAX, DPAY, QCA, QSA, DPBX, DPBY, QCB, QSB = [U64(k * LANES) for k in range(GATHER_FIELDS)]


@intrinsic
def scratch(typingctx):
    """A C-contiguous float64 array of SIZE elements on the stack of the calling kernel, 64-byte
    aligned and uninitialised (every field is gathered before it is read). The ``alloca`` goes to
    the kernel's entry block, so calling this in a loop does not grow the stack; the array owns
    no memory (no reference count), so it must not outlive the kernel."""
    array_type = types.Array(types.float64, 1, "C")

    def codegen(context, builder, signature, args):
        block = cgutils.alloca_once(builder, ir.ArrayType(ir.DoubleType(), SIZE))
        block.align = 64
        intp = context.get_value_type(types.intp)
        array = make_array(array_type)(context, builder)
        populate_array(
            array,
            data=builder.bitcast(block, ir.DoubleType().as_pointer()),
            shape=[intp(SIZE)],
            strides=[intp(8)],
            itemsize=intp(8),
            meminfo=None,
        )
        return array._getvalue()

    return array_type(), codegen
