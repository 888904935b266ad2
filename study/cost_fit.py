"""The per-body cost model of a step, ms/step = a N_awake + b N_frozen + c, fitted by least squares
(bench_freeze part 2, fig_scaling): the coefficients with their standard errors, and b/a."""

import math

import numpy as np


def fit_cost(n_aw, n_fr, ms):
    """Least squares ms = a n_aw + b n_fr + c: dict of a, b, c, their standard errors, b/a and
    its standard error (delta method, with the a-b covariance), RMS and largest residual (ms),
    R^2 and the number of points."""
    x = np.column_stack([n_aw, n_fr, np.ones(len(ms))]).astype(float)
    y = np.asarray(ms, dtype=float)
    coef, _, rank, _ = np.linalg.lstsq(x, y, rcond=None)
    resid = y - x @ coef
    dof = len(y) - 3
    sigma2 = float(resid @ resid) / dof if dof > 0 else math.nan
    try:
        cov = sigma2 * np.linalg.inv(x.T @ x)
    except np.linalg.LinAlgError:
        cov = np.full((3, 3), math.nan)
    stderr = np.sqrt(np.diag(cov))
    total = float(((y - y.mean()) ** 2).sum())
    a, b, c = (float(v) for v in coef)
    # d(b/a) = (-b/a^2, 1/a, 0) . d(a, b, c)
    grad = np.array([-b / (a * a), 1.0 / a, 0.0]) if a else np.full(3, math.nan)
    return {
        "a": a,
        "b": b,
        "c": c,
        "a_stderr": float(stderr[0]),
        "b_stderr": float(stderr[1]),
        "c_stderr": float(stderr[2]),
        "b_over_a": b / a if a else math.nan,
        "rms_residual": float(np.sqrt(np.mean(resid**2))),
        "max_abs_residual": float(np.abs(resid).max()),
        "r2": 1.0 - float(resid @ resid) / total if total > 0 else math.nan,
        "points": len(y),
        "rank": int(rank),
        "b_over_a_stderr": float(np.sqrt(max(0.0, grad @ cov @ grad)))
        if np.isfinite(grad).all() and np.isfinite(cov).all()
        else math.nan,
    }


#: the unit of each fit key, for the long-form table's fit rows
FIT_UNITS = {
    "a": "ms/(step*body)",
    "b": "ms/(step*body)",
    "c": "ms/step",
    "a_stderr": "ms/(step*body)",
    "b_stderr": "ms/(step*body)",
    "c_stderr": "ms/step",
    "b_over_a": "ratio",
    "rms_residual": "ms/step",
    "max_abs_residual": "ms/step",
    "r2": "ratio",
    "points": "count",
    "rank": "count",
}


def relative_to_off(fits):
    """Add b_over_b_off and a_over_a_off (against the sim-off fit, if there is one) to every other
    system's fit, in place."""
    off = fits.get("sim-off")
    if off is None:
        return fits
    for system, fit in fits.items():
        if system != "sim-off":
            fit["b_over_b_off"] = fit["b"] / off["b"] if off["b"] else math.nan
            fit["a_over_a_off"] = fit["a"] / off["a"] if off["a"] else math.nan
    return fits
