"""How a World calls its compiled kernels from Python, at the least cost per call.

A program that steps a World once per call (a viewer, a controller reading the state every step)
pays this every step, and on a frozen scene it is all a step costs (the quiet fast path skips the
step itself). Measured on pyramid(10), frozen, ``World.step(1)``: 72 us a call, of which Numba's
type dispatch over the 109 arrays of the state took ~15 us and swapping the SIGINT handler through
the ``signal`` module ~10-20 us (its enum conversions raise and catch an exception per call).

- ``Deferred``: Ctrl-C (SIGINT) is recorded, not raised, while compiled code runs. Raised inside
  the compiled step loop, KeyboardInterrupt surfaced only when the call returned, as "SystemError:
  CPUDispatcher(run) returned a result with an exception set". Only the main thread can take
  signals, and a handler the program installed itself is left alone. The handler is swapped
  through ``_signal``, the C module that ``signal`` wraps (the same calls, without the enum
  conversions); ``signal`` itself where there is no ``_signal``.
- ``Compiled``: a kernel called through the compiled function Numba chose for the arguments' types
  the last time, as long as the arguments are the same objects (named tuples are immutable and an
  array's type cannot change in place, so the same objects have the same types); other objects
  are typed again (``numba.typeof``, the dispatcher's own typing) and looked up
  (``Dispatcher.get_overload``), and a signature not compiled yet goes through the dispatcher,
  which compiles it. A new named tuple of arrays (a buffer the World grew) whose arrays have the
  dtypes, dimensions and flags of the old one's has its type (``_same_type``): the entry stands.
  Typing the whole state again cost ~0.5 ms a time, and a pile of 200 polygons settling grows its
  buffers three times in its first 80 steps: 6% of its first 240 steps (``bench_step``). The
  entries found are shared by every ``Compiled`` of the process, keyed on what the arguments'
  types are made of (``_type_key``, a walk over the arrays' flags at ~1/6 of ``numba.typeof``'s
  cost): a new World's first step cost 0.71 ms, typing its state, and costs 0.12 ms (drop(200);
  a step after the first, 0.05 ms).
"""

import signal
import threading

import numba
import numpy as np

try:
    import _signal as _raw_signal
except ImportError:  # another Python implementation: the public module, slower
    _raw_signal = signal


class Deferred:
    """``with Deferred() as d:`` Ctrl-C within is recorded; ``d.came`` says whether it came."""

    __slots__ = ("came", "_previous", "_swapped")

    def __init__(self):
        self.came = False
        self._previous = None
        self._swapped = False

    def _record(self, signum, frame):
        self.came = True

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            previous = _raw_signal.signal(signal.SIGINT, self._record)
            if previous is _raw_signal.default_int_handler:
                self._previous = previous
                self._swapped = True
            else:  # the program's own handler (or SIG_IGN): left alone
                _raw_signal.signal(signal.SIGINT, previous)
        return self

    def __exit__(self, *exc):
        if self._swapped:
            _raw_signal.signal(signal.SIGINT, self._previous)
            self._swapped = False
        return False


class Compiled:
    """``Compiled(dispatcher)(*args)`` calls ``dispatcher(*args)``, skipping its type dispatch
    when ``args`` are the objects of the call before (see the module docstring). The first and
    the last argument (a step count and a fresh output array) are typed by value, not by
    identity: pass an int and a 1-D float64 array there, as ``World`` does."""

    __slots__ = ("dispatcher", "_args", "_entry")

    def __init__(self, dispatcher):
        self.dispatcher = dispatcher
        self._args = ()
        self._entry = None

    def __call__(self, *args):
        middle = args[1:-1]
        cached = self._args
        if (
            self._entry is None
            or len(middle) != len(cached)
            or any(a is not b for a, b in zip(middle, cached))
        ):
            if self._entry is not None and all(
                a is b or _same_type(a, b) for a, b in zip(middle, cached)
            ):
                self._args = middle  # replaced buffers of the same types
            else:
                self._entry = self._lookup(args)
                self._args = middle if self._entry is not None else ()
        if self._entry is None:
            return self.dispatcher(*args)
        return self._entry(*args)

    def _lookup(self, args):
        """The compiled function for ``args``' types, or None if none is compiled yet."""
        if not (isinstance(args[0], int) and _is_float_vector(args[-1])):
            return None
        key = _type_key(args)
        if key is not None:
            entry = _ENTRIES.get((self.dispatcher, key))
            if entry is not None:
                return entry
        try:
            entry = self.dispatcher.get_overload(tuple(numba.typeof(a) for a in args))
        except KeyError:  # not compiled for these types yet
            return None
        if key is not None:
            _ENTRIES[(self.dispatcher, key)] = entry
        return entry


#: (dispatcher, ``_type_key`` of the arguments) -> the compiled function Numba chose for them,
#: shared by every ``Compiled``: a new World's state has the types of the last one's, and typing
#: its 109 arrays with ``numba.typeof`` cost ~0.6 ms of its first step (0.05 ms a step after)
_ENTRIES = {}


def _type_key(value):
    """What Numba's type of ``value`` is made of, cheaply, as a hashable key; None for a value
    whose type it does not surely tell (then ``numba.typeof`` decides, and nothing is shared).
    Arrays: ``_array_type``; named tuples: their class and their members' keys (Numba types a
    named tuple from its class and its members' types); a tuple of arguments: its members' keys;
    Python bool and float: their type; Python int: int when it fits int64 (Numba's int64; a
    larger one would be typed uint64 or refused); NumPy scalars: their type (their dtype)."""
    if isinstance(value, np.ndarray):
        return _array_type(value)
    kind = type(value)
    if kind is bool or kind is float or isinstance(value, np.generic):
        return kind
    if kind is int:
        return int if -(2**63) <= value < 2**63 else None
    if isinstance(value, tuple) and (kind is tuple or hasattr(value, "_fields")):
        members = tuple(_type_key(m) for m in value)
        return None if any(m is None for m in members) else (kind, members)
    return None


def _is_float_vector(a):
    return (
        getattr(a, "dtype", None) == "float64"
        and getattr(a, "ndim", 0) == 1
        and a.flags.c_contiguous
    )


def _array_type(a):
    """What Numba's type of an ndarray is made of (``numba.typeof``: dtype, dimensions, layout
    read from the contiguity flags as Numba reads them, read-only, aligned)."""
    f = a.flags
    layout = "C" if f.c_contiguous else ("F" if f.f_contiguous else "A")
    return (a.dtype, a.ndim, layout, f.writeable, f.aligned)


def _same_type(new, old):
    """Is ``new`` surely of ``old``'s Numba type? True for two arrays of the same ``_array_type``
    and for two named tuples of one class whose members are each the same object or such arrays;
    anything else (a scalar that differs, a nested tuple) is left to ``numba.typeof``."""
    if isinstance(new, np.ndarray):
        return isinstance(old, np.ndarray) and _array_type(new) == _array_type(old)
    if type(new) is not type(old) or not hasattr(new, "_fields"):
        return False
    return all(
        a is b
        or (
            isinstance(a, np.ndarray)
            and isinstance(b, np.ndarray)
            and _array_type(a) == _array_type(b)
        )
        for a, b in zip(new, old)
    )
