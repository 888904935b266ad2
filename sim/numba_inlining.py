"""Faster Numba inlining: the blocks of one inlined function share one copy of their scope.

Why. Every helper of the batch kernels is inlined by Numba (``jit.inline_kernel``,
``jit.wide_inline``: see there why), and Numba inlines by copying the callee's IR: it deep-copies
each of its blocks on its own (``numba.core.inline_closurecall``, ``InlineWorker.inline_ir``,
its ``copy_ir``), and each block's copy drags along a fresh copy of the callee's whole scope
(every variable of the function; ``ir.Var`` deep-copies its scope). The cost is blocks times
variables per inlined call, and the batch kernels' helpers are inlined into each other four levels
deep, with many blocks (every branch-free select is a conditional expression): measured with
``cProfile`` on the biased sweep, 33 of the 41 s spent compiling it went to these copies.

What. Inside ``inline_closurecall`` the name ``copy`` (the standard module, which it uses for
nothing but this) is replaced by ``_SharedScopeCopy``: a block is deep-copied as before, except
that all blocks with the same scope get one copy of it (made once per ``inline_ir`` call). The
copies are equal to Numba's own (the same statements, variables and names; Numba's copies of the
scope are all equal, and it renames the callee's variables by name), only not made once per
block. Measured 2026-12-06 (an empty cache, the first step of a World): 187 s -> 83 s, and the
compiled code of ``kernel.run`` and ``kernel.presolve`` (every stage of a step, inlined) is the
same machine code byte for byte (``inspect_asm``); ``tests/unit/test_jit.py`` compares a kernel
compiled with and without it.

Guard. This reaches into one Numba function, so it is installed only on the pinned Numba version
whose ``inline_closurecall`` was read (``PINNED_NUMBA``); on any other version Numba's own copies
are used (slower to compile, the same code), and ``test_jit`` fails, so that an upgrade looks at it
again.
"""

import copy

import numba
from numba.core import inline_closurecall, ir

#: the Numba version whose inliner this was written against (pyproject.toml pins it)
PINNED_NUMBA = "0.68.1"


class _SharedScopeCopy:
    """Stands for the ``copy`` module inside ``numba.core.inline_closurecall``: ``deepcopy`` of an
    IR block reuses one copy of the block's scope per scope (``fresh`` forgets them); everything
    else is the standard module's."""

    def __init__(self):
        self.scopes = {}  # id(scope) -> (scope, its copy): the scope kept, so that its id stays

    def fresh(self):
        self.scopes = {}

    def deepcopy(self, x, memo=None):
        if memo is not None or not isinstance(x, ir.Block):
            return copy.deepcopy(x, memo)
        shared = self.scopes.get(id(x.scope))
        if shared is None:
            shared = (x.scope, copy.deepcopy(x.scope))
            self.scopes[id(x.scope)] = shared
        return copy.deepcopy(x, {id(x.scope): shared[1]})

    def __getattr__(self, name):
        return getattr(copy, name)


_COPIER = _SharedScopeCopy()
#: Numba's own method, also when this module is imported again (``importlib.reload``, IPython's
#: autoreload) while an earlier copy of ``_inline_ir`` is installed: wrapping that one would call
#: itself
_NUMBA_INLINE_IR = getattr(
    inline_closurecall.InlineWorker.inline_ir,
    "numba_inline_ir",
    inline_closurecall.InlineWorker.inline_ir,
)


def _inline_ir(self, *args, **kwargs):
    """Numba's ``InlineWorker.inline_ir``, with the shared scope copies of this call only: the
    callee's scope is mutated after its blocks are copied (its variables renamed), so a copy is
    never reused by a later call."""
    copier = inline_closurecall.copy  # the one installed (this import's, see the end)
    copier.fresh()
    try:
        return _NUMBA_INLINE_IR(self, *args, **kwargs)
    finally:
        copier.fresh()


_inline_ir.numba_inline_ir = _NUMBA_INLINE_IR


def installable():
    """Is this the Numba whose inliner this module was written against?"""
    installed = inline_closurecall.copy
    # a stand-in of an earlier import of this module counts as Numba's own (it is replaced)
    ours = installed is copy or type(installed).__name__ == _SharedScopeCopy.__name__
    return numba.__version__ == PINNED_NUMBA and ours


def set_enabled(on):
    """Use the shared scope copies (``on``) or Numba's own; returns whether they were in use.
    Off on a Numba other than PINNED_NUMBA."""
    was = enabled()
    if on and installable():
        inline_closurecall.copy = _COPIER
        inline_closurecall.InlineWorker.inline_ir = _inline_ir
    else:
        inline_closurecall.copy = copy
        inline_closurecall.InlineWorker.inline_ir = _NUMBA_INLINE_IR
    return was


def enabled():
    """Are the shared scope copies in use?"""
    return inline_closurecall.copy is _COPIER


# imported again while an earlier import's stand-in is installed: put this import's in its place
if type(inline_closurecall.copy).__name__ == _SharedScopeCopy.__name__:
    set_enabled(True)
