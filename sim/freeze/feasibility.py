"""Is A x = b solvable with x >= 0? The question the rest certificate asks of a group of bodies
(``certificate.group_holds``): do contact forces exist, each inside its friction cone, that hold
every member of the group still at once?

A dense phase-one simplex (minimise the sum of artificial variables, one per equation; the system
is solvable exactly when that minimum is zero). Dantzig's rule picks the entering column until a
run of degenerate pivots (a resting pile makes many degenerate vertices: equations that hold with
zero slack), then Bland's, which cannot cycle (``_simplex``). No LAPACK (Numba's linear algebra
needs SciPy, which the study does not install) and nothing but the tableau is allocated. A group's
system is small: three equations per member, two cone edges per contact point, at most
``MAX_ROWS`` x ``MAX_COLUMNS``.

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
    artificials left relative to |b|_1). a and b are left unchanged. Dantzig's pricing, Bland's
    after a run of degenerate pivots (``_simplex``)."""
    return _simplex(a, b, n_rows, n_cols, n_rows)


@inline_kernel
def _simplex(a, b, n_rows, n_cols, stall_limit):
    """``phase_one``, switching from Dantzig's pricing (the column that lowers the sum fastest)
    to Bland's (the first column that lowers it) for good after more than ``stall_limit``
    degenerate pivots in a row (0: Bland's throughout).

    Why both: Bland's rule cannot cycle, but it takes many pivots: on 519 systems captured from
    drop(30) piles (2026-12-08) a median of 37 and at most 301, against Dantzig's 28 and 150,
    and the largest systems (a whole still set of 28-30 bodies, 90 x 130) took 0.3-1.4 ms each.
    Dantzig's rule can cycle on a degenerate vertex (a resting pile makes many: equations that
    hold with zero slack), where no pivot lowers the sum; a run of them longer than the rows
    hands over to Bland's, which ends from any basis. The answer is the same either way in
    exact arithmetic (the system is solvable or not); on those 519 systems the decisions agreed.

    The artificial variables' columns are not kept: an artificial that leaves the basis never
    has to re-enter it (phase one only asks whether the minimum is zero), so the tableau is
    (n_rows + 1) x (n_cols + 1), not n_rows columns wider, and each pivot costs that much less."""
    scale = 0.0
    for i in range(n_rows):
        scale += abs(b[i])
    if scale == 0.0:
        return True, 0.0
    rhs = n_cols  # the tableau's last column: the basic variables' values
    t = np.zeros((n_rows + 1, n_cols + 1))  # the last row: the reduced costs of phase one
    basis = np.empty(n_rows, np.int64)  # the basic variable of each row: artificials n_cols + i
    for i in range(n_rows):
        sign = 1.0 if b[i] >= 0.0 else -1.0  # every right-hand side >= 0
        for j in range(n_cols):
            t[i, j] = sign * a[i, j]
        t[i, rhs] = sign * b[i] / scale
        basis[i] = n_cols + i
        for j in range(n_cols + 1):
            t[n_rows, j] -= t[i, j]
    bland = stall_limit <= 0
    stalled = 0
    for _ in range(50 * (n_rows + n_cols)):
        enter = -1
        steepest = -PIVOT
        for j in range(n_cols):
            if t[n_rows, j] < steepest:
                enter = j
                if bland:
                    break
                steepest = t[n_rows, j]
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
        stalled = stalled + 1 if best == 0.0 else 0
        if stalled > stall_limit:
            bland = True
        p = t[leave, enter]
        for j in range(n_cols + 1):
            t[leave, j] /= p
        for i in range(n_rows + 1):
            f = t[i, enter]
            if i != leave and f != 0.0:
                for j in range(n_cols + 1):
                    t[i, j] -= f * t[leave, j]
        basis[leave] = enter
    left = -t[n_rows, rhs]
    return left <= RESIDUAL, left


@kernel
def _solvable_kernel(a, b, bland):
    if bland:
        return _simplex(a, b, a.shape[0], a.shape[1], np.int64(0))
    return phase_one(a, b, a.shape[0], a.shape[1])


#: ``solvable``'s pricing rules: the certificate's (Dantzig's, then Bland's after a degenerate
#: run), and Bland's throughout (the slow rule, to check the fast one against)
PRICING = ("dantzig", "bland")


def solvable(a, b, pricing="dantzig"):
    """Is ``a`` (R, C) x = ``b`` (R,) solvable with x >= 0? Returns (bool, the sum of artificial
    variables left relative to |b|_1: 0 when solvable). ``pricing``: one of PRICING. Raises
    ValueError for wrong shapes, non-finite values, a system larger than MAX_ROWS x MAX_COLUMNS or
    an unknown pricing rule."""
    if pricing not in PRICING:
        raise ValueError(f"pricing must be one of {PRICING}, got {pricing!r}")
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
    ok, left = _solvable_kernel(a, b, pricing == "bland")
    return bool(ok), float(left)
