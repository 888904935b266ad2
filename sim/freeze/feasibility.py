"""Is A x = b solvable with x >= 0? The question the rest certificate asks of a group of bodies
(``certificate.group_holds``): do contact forces exist, each inside its friction cone, that hold
every member of the group still at once?

A dense phase-one simplex (minimise the sum of artificial variables, one per equation; the system
is solvable exactly when that minimum is zero). Bland's rule picks the entering and leaving
columns, so the method cannot cycle on the degenerate vertices a resting pile produces (many
equations hold with zero slack). No LAPACK (Numba's linear algebra needs SciPy, which the study
does not install) and nothing but the tableau is allocated. A group's system is small: three
equations per member, two cone edges per contact point, at most ``MAX_ROWS`` x ``MAX_COLUMNS``.

``solvable`` is the validating wrapper (tests; reading a group by hand); ``phase_one`` is the
kernel, which checks nothing, for the certificate's kernels.
"""

import numpy as np

from ..jit import inline_kernel, kernel

#: the largest system solved (three equations per member: 32 members; two cone edges per point:
#: 192 points); a larger group is not certified by forces solved for (``group_holds``). 16 members
#: until 2026-12, when a group that grew past them was not judged again: drop(30) seeds 46 and 93
#: then kept 28 and 26 bodies awake for good, still (1e-12 m/s) and held as one group of them
#: all (``extended_rest.wedges``)
MAX_ROWS = 96
MAX_COLUMNS = 384
#: the sum of artificials left, relative to |b|_1, below which the system counts as solved; and
#: the smallest pivot taken (the entries are unit forces and moments over a length, so O(1))
RESIDUAL = 1e-9
PIVOT = 1e-12


@inline_kernel
def phase_one(a, b, n_rows, n_cols):
    """Is a[:n_rows, :n_cols] x = b[:n_rows] solvable with x >= 0? Returns (bool, the sum of
    artificials left relative to |b|_1). a and b are left unchanged."""
    scale = 0.0
    for i in range(n_rows):
        scale += abs(b[i])
    if scale == 0.0:
        return True, 0.0
    width = n_cols + n_rows + 1
    rhs = width - 1
    t = np.zeros((n_rows + 1, width))  # the last row: the reduced costs of phase one
    basis = np.empty(n_rows, np.int64)
    for i in range(n_rows):
        sign = 1.0 if b[i] >= 0.0 else -1.0  # every right-hand side >= 0
        for j in range(n_cols):
            t[i, j] = sign * a[i, j]
        t[i, n_cols + i] = 1.0
        t[i, rhs] = sign * b[i] / scale
        basis[i] = n_cols + i
        for j in range(n_cols):
            t[n_rows, j] -= t[i, j]
        t[n_rows, rhs] -= t[i, rhs]
    for _ in range(50 * (n_rows + n_cols)):
        enter = -1
        for j in range(n_cols + n_rows):  # Bland: the first column that lowers the sum
            if t[n_rows, j] < -PIVOT:
                enter = j
                break
        if enter < 0:
            break
        leave = -1
        best = np.inf
        for i in range(n_rows):
            if t[i, enter] > PIVOT:
                ratio = t[i, rhs] / t[i, enter]
                if ratio < best or (ratio == best and basis[i] < basis[leave]):
                    best = ratio
                    leave = i
        if leave < 0:
            break  # unbounded: cannot happen in phase one (the sum is >= 0)
        p = t[leave, enter]
        for j in range(width):
            t[leave, j] /= p
        for i in range(n_rows + 1):
            f = t[i, enter]
            if i != leave and f != 0.0:
                for j in range(width):
                    t[i, j] -= f * t[leave, j]
        basis[leave] = enter
    left = -t[n_rows, rhs]
    return left <= RESIDUAL, left


@kernel
def _solvable_kernel(a, b):
    return phase_one(a, b, a.shape[0], a.shape[1])


def solvable(a, b):
    """Is ``a`` (R, C) x = ``b`` (R,) solvable with x >= 0? Returns (bool, the sum of artificial
    variables left relative to |b|_1: 0 when solvable). Raises ValueError for wrong shapes,
    non-finite values or a system larger than MAX_ROWS x MAX_COLUMNS."""
    a = np.ascontiguousarray(a, dtype=np.float64)
    b = np.ascontiguousarray(b, dtype=np.float64)
    if a.ndim != 2 or b.shape != (a.shape[0],):
        raise ValueError(f"a must be (R, C) and b (R,), got {a.shape} and {b.shape}")
    if a.shape[0] > MAX_ROWS or a.shape[1] > MAX_COLUMNS:
        raise ValueError(
            f"at most {MAX_ROWS} equations and {MAX_COLUMNS} unknowns, got {a.shape[0]} and "
            f"{a.shape[1]}"
        )
    if not (np.isfinite(a).all() and np.isfinite(b).all()):
        raise ValueError("a and b must be finite")
    ok, left = _solvable_kernel(a, b)
    return bool(ok), float(left)
