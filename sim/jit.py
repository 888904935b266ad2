"""The one decorator every kernel uses, so that compilation options are set in one place.

- cache=True: compiled code is stored on disk (see ``sim/__init__``, which keys the cache folder by a
  hash of the sources, because Numba does not notice edits to a kernel's callees).
- error_model="numpy": a float division by zero gives inf/nan instead of raising; the Python model
  puts a test-and-raise branch on every division, which costs ~15% of a solver sweep. Non-finite
  state is caught once per step instead (``kernel._first_non_finite``).
"""
from numba import njit

kernel = njit(cache=True, error_model="numpy")

#: For helpers called inside hot loops: a call that LLVM does not inline passes every array
#: argument through a reference-count increment and decrement (atomic operations), which made the
#: block solver's call cost more than its arithmetic. Numba-level inlining removes the call.
inline_kernel = njit(cache=True, error_model="numpy", inline="always")

#: For kernels that allocate nothing: compiled without Numba's reference counting (a private but
#: long-standing Numba flag; the version is pinned). With it, every array an inlined helper takes
#: costs an atomic increment and decrement per call: half of the narrowphase's time.
lean_kernel = njit(cache=True, error_model="numpy", _nrt=False)
