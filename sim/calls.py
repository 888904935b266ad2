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
  which compiles it.
"""

import signal
import threading

import numba

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
            self._entry = self._lookup(args)
            self._args = middle if self._entry is not None else ()
        if self._entry is None:
            return self.dispatcher(*args)
        return self._entry(*args)

    def _lookup(self, args):
        """The compiled function for ``args``' types, or None if none is compiled yet."""
        if not (isinstance(args[0], int) and _is_float_vector(args[-1])):
            return None
        try:
            return self.dispatcher.get_overload(tuple(numba.typeof(a) for a in args))
        except KeyError:  # not compiled for these types yet
            return None


def _is_float_vector(a):
    return (
        getattr(a, "dtype", None) == "float64"
        and getattr(a, "ndim", 0) == 1
        and a.flags.c_contiguous
    )
