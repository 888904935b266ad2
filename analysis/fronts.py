"""Pareto fronts of speed-up against error, and how one system's front compares with the other
systems' settings (fig_tradeoff's question: does ``extended``'s front dominate?).

"Dominate" has two readings, and the study reports both, since they differ exactly where a system
cannot go:
  - ``beyond_front``, the strict one: the other settings that the front does not dominate, that
    is, no setting of the challenger is at least as fast *and* at least as accurate. A setting
    faster than every challenger setting is beyond it whatever its error (a sleep timer of one
    step freezes boxes in mid-air: 37x, with an error of 1.5 m), and so is one that falls in a
    gap of the challenger's grid.
  - ``beating_front``, the issue's: the other settings that have both more speed-up *and* less
    error than some point of the challenger's front. None means that no point of the front can be
    bettered in both by another system; what is beyond the front without beating it is faster
    than one of its points and less accurate than it, and more accurate than a faster one only
    where it is also slower than that one (or faster than all of them and less accurate than
    every one).
Errors closer than a tie (a micrometre, see ``TIE_M``) count as equal; speed-ups are compared as
they are (each engine's over itself with sleeping off, so a peer's point also measures how cheap
its engine's sleeping is).
"""

import math

import numpy as np

#: m: errors closer than this are a tie when fronts are compared (a micrometre: round-off and
#: the solvers' resting jitter on a pyramid placed at rest, 1e-8 to 1e-7 m, are far below it;
#: nothing the study reports turns on less)
TIE_M = 1e-6


def pareto(points, column):
    """The rows of ``points`` on the speed-up / ``column`` Pareto front (higher speed-up and
    lower error both better), sorted by speed-up ascending; NaN errors are left out."""
    p = points[np.isfinite(points[column]) & np.isfinite(points["speedup"])]
    p = p.sort_values(["speedup", column], ascending=[False, True])
    keep, best = [], math.inf
    for idx, err in zip(p.index, p[column]):
        if err < best:
            keep.append(idx)
            best = err
    return p.loc[keep].sort_values("speedup")


def setting_label(row):
    """'parameter=value' of a table row (3 significant digits), 'sleeping off' for a baseline,
    'defaults' for a sweep's point at the system's defaults (every sweep has one: labelled by
    its parameter, the defaults read as a setting of their own, "rest_speed=0.02")."""
    if row["parameter"] == "none":
        return "sleeping off"
    if row.get("role") == "sweep" and str(row.get("is_default")).lower() == "true":
        return "defaults"
    return f"{row['parameter']}={row['value']:.3g}"


def _split(rows, column, challenger, freezing):
    """(the challenger's rows, every other freezing system's sweep rows), finite in ``column``."""
    finite = np.isfinite(rows[column])
    own = rows[(rows["system"] == challenger) & finite]
    others = rows[
        rows["system"].isin(freezing)
        & (rows["system"] != challenger)
        & (rows["role"] == "sweep")
        & finite
    ]
    return own, others


def _point(p, column):
    return {
        "system": p["system"],
        "setting": setting_label(p),
        "speedup": p["speedup"],
        "error_m": p[column],
    }


def beyond_front(rows, column, challenger, freezing, tie=TIE_M):
    """The settings of the systems ``freezing`` other than ``challenger`` among ``rows`` (one
    scene's timed rows; role "sweep" only) that ``challenger``'s front does not dominate in
    ``column``: no setting of the challenger is at least as fast *and* at least as accurate
    (errors within ``tie`` m count as equal). [] when it dominates every one (NaN errors are left
    out). Each: system, setting, speed-up, error, and the challenger's best error at that
    speed-up or more (``challenger_error_m``; None: the challenger is never that fast)."""
    own, others = _split(rows, column, challenger, freezing)
    out = []
    for _, p in others.iterrows():
        fast_enough = own[own["speedup"] >= p["speedup"]]
        best = float(fast_enough[column].min()) if len(fast_enough) else None
        if best is None or best > p[column] + tie:
            out.append({**_point(p, column), "challenger_error_m": best})
    return sorted(out, key=lambda d: (d["system"], d["speedup"]))


def beating_front(rows, column, challenger, freezing, tie=TIE_M):
    """The settings (as ``beyond_front`` takes them) that beat a point of ``challenger``'s
    Pareto front in ``column``: more speed-up *and* less error (by more than ``tie`` m) than it.
    [] when no point of the front is beaten. Each: system, setting, speed-up, error, and
    ``beats``: the front points it beats (setting, speed-up, error), slowest first."""
    own, others = _split(rows, column, challenger, freezing)
    front = pareto(own, column)
    out = []
    for _, p in others.iterrows():
        beaten = front[(front["speedup"] < p["speedup"]) & (front[column] > p[column] + tie)]
        if len(beaten):
            beats = [_point(e, column) for _, e in beaten.iterrows()]
            out.append({**_point(p, column), "beats": beats})
    return sorted(out, key=lambda d: (d["system"], d["speedup"]))
