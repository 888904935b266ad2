"""Is a wrench a non-negative combination of given wrenches? The rest certificate's cone test
(``certificate``): the supports of a body can hold a load when minus the load lies in the cone
their friction cones' edges generate.

Membership in a cone of K generators in three dimensions is decided exactly, without an LP
solver: by Caratheodory's theorem, a wrench in the cone of generators that span all three
dimensions is a non-negative combination of three linearly independent ones, so every
independent triple is tried (Cramer's rule). With at most ``certificate.MAX_SUPPORT_POINTS`` points
(2 generators each) that is at most C(32, 3) = 4960 small solves; a body with more supports than
that is not certified (it stays awake: the conservative answer). A certificate for a box on the
floor tries 4 triples; a pyramid box (four support points) 56.

``in_cone`` is the validating wrapper (tests; reading a certificate by hand); ``combination`` is
the kernel, which checks nothing, for the certificate's kernels.
"""

import numpy as np

from ..jit import inline_kernel, kernel

#: generator triples whose determinant (generators of unit force, moments in units of the
#: body's extent) is below this are treated as dependent and skipped
DEPENDENT = 1e-9


@inline_kernel
def combination(gens, n_gens, tx, ty, tm, weights):
    """Is the wrench (tx, ty, tm) a non-negative combination of gens[0:n_gens] (rows: force x,
    force y, moment / extent)? If so, the weights of one such combination are written to
    weights[0:n_gens] (zero but for three). Exact up to round-off, by trying every independent
    triple in order, then (generators in a plane) every pair and every single one."""
    scale = np.sqrt(tx * tx + ty * ty + tm * tm)
    weights[:n_gens] = 0.0
    if scale == 0.0:
        return True
    tol = -1e-9 * scale
    for a in range(n_gens):
        ax, ay, am = gens[a, 0], gens[a, 1], gens[a, 2]
        for b in range(a + 1, n_gens):
            bx, by, bm = gens[b, 0], gens[b, 1], gens[b, 2]
            # b x c is needed for every c: its parts are formed inside the loop
            for c in range(b + 1, n_gens):
                cx, cy, cm = gens[c, 0], gens[c, 1], gens[c, 2]
                kx = by * cm - bm * cy
                ky = bm * cx - bx * cm
                kz = bx * cy - by * cx
                det = ax * kx + ay * ky + am * kz  # a . (b x c)
                if abs(det) < DEPENDENT:
                    continue
                # Cramer: lambda_a = t.(b x c) / det, lambda_b = a.(t x c) / det,
                # lambda_c = a.(b x t) / det
                la = (tx * kx + ty * ky + tm * kz) / det
                if la < tol:
                    continue
                lb = (
                    ax * (ty * cm - tm * cy) + ay * (tm * cx - tx * cm) + am * (tx * cy - ty * cx)
                ) / det
                if lb < tol:
                    continue
                lc = (
                    ax * (by * tm - bm * ty) + ay * (bm * tx - bx * tm) + am * (bx * ty - by * tx)
                ) / det
                if lc >= tol:
                    weights[a] = max(la, 0.0)
                    weights[b] = max(lb, 0.0)
                    weights[c] = max(lc, 0.0)
                    return True
    # No independent triple holds it. If the generators span only a plane (every support normal
    # parallel and no friction, as in a frictionless stack) the wrench may still be a combination
    # of two, or be one's multiple: solve those and check the equation left over.
    for a in range(n_gens):
        ax, ay, am = gens[a, 0], gens[a, 1], gens[a, 2]
        for b in range(a + 1, n_gens):
            bx, by, bm = gens[b, 0], gens[b, 1], gens[b, 2]
            # solve on the two rows with the largest minor; the third must then agree
            dxy = ax * by - ay * bx
            dxm = ax * bm - am * bx
            dym = ay * bm - am * by
            if abs(dxy) >= abs(dxm) and abs(dxy) >= abs(dym):
                det, la, lb = dxy, tx * by - ty * bx, ax * ty - ay * tx
            elif abs(dxm) >= abs(dym):
                det, la, lb = dxm, tx * bm - tm * bx, ax * tm - am * tx
            else:
                det, la, lb = dym, ty * bm - tm * by, ay * tm - am * ty
            if abs(det) < DEPENDENT:
                continue
            la /= det
            lb /= det
            if la < tol or lb < tol:
                continue
            if (
                abs(la * ax + lb * bx - tx)
                + abs(la * ay + lb * by - ty)
                + abs(la * am + lb * bm - tm)
            ) <= -tol:
                weights[a] = max(la, 0.0)
                weights[b] = max(lb, 0.0)
                return True
    for a in range(n_gens):
        ax, ay, am = gens[a, 0], gens[a, 1], gens[a, 2]
        la = (tx * ax + ty * ay + tm * am) / (ax * ax + ay * ay + am * am)
        if la >= 0.0 and (abs(la * ax - tx) + abs(la * ay - ty) + abs(la * am - tm)) <= -tol:
            weights[a] = la
            return True
    return False


@kernel
def _in_cone_kernel(gens, n_gens, tx, ty, tm):
    weights = np.empty(max(n_gens, 1))
    found = combination(gens, n_gens, tx, ty, tm, weights)
    return found, weights[:n_gens].copy()


def in_cone(generators, wrench):
    """Is ``wrench`` (3,) a non-negative combination of the rows of ``generators`` (K, 3)? Returns
    (bool, weights (K,)): the certificate's own test (``_combination``), for tests and for
    reading a certificate by hand. Raises ValueError for wrong shapes or non-finite values."""
    gens = np.ascontiguousarray(generators, dtype=np.float64)
    target = np.asarray(wrench, dtype=np.float64)
    if gens.ndim != 2 or gens.shape[1] != 3 or target.shape != (3,):
        raise ValueError(
            f"generators must be (K, 3) and the wrench (3,), got {gens.shape} and {target.shape}"
        )
    if not (np.isfinite(gens).all() and np.isfinite(target).all()):
        raise ValueError("generators and wrench must be finite")
    found, weights = _in_cone_kernel(gens, len(gens), target[0], target[1], target[2])
    return bool(found), weights
