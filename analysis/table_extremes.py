"""Table "table_extremes" and figure "fig_extremes": every (axis, value) x system run of the
extremes sweep marked stable / degraded / failed / rejected / not run by the experiment's stated
rules (experiments/table_extremes.py), drawn as a grid; the numbers say, per axis, which system
breaks first and how many cells each system has of each mark.

Writes paper/figures/fig_extremes.svg, paper/generated/table_extremes.csv (one row per
(axis, value), one column per system, each cell its mark and reason codes) and
paper/generated/table_extremes.json. Never simulates.
"""
import math

import matplotlib.pyplot as plt
import pandas as pd
from matplotlib.patches import Patch

from analysis import style
from experiments.common import REFERENCE, SYSTEMS

NAME = "table_extremes"
FIGURE = "fig_extremes"

#: one colour per mark (Okabe-Ito-like; failed and stable differ in lightness too, for grey print)
STATUS_COLOR = {"stable": "#c7e9c0", "degraded": "#f0c571", "failed": "#d55e00",
                "rejected": "#56b4e9", "not run": "#e8e8e8"}
STATUS_ORDER = ("stable", "degraded", "failed", "rejected", "not run")
#: how bad a mark is, to compare a freezing system with its engine's sleeping-off system
SEVERITY = {"stable": 0, "degraded": 1, "failed": 2}
#: reason -> one-letter code drawn in the cell (failed: capitals, degraded: lower case)
CODES = (("error", "X"), ("non-finite", "N"), ("explosion", "E"), ("tunnelling", "T"),
         ("chattering", "C"), ("outcome", "O"), ("penetration", "p"), ("drift", "d"),
         ("energy growth", "e"))
CODE_TEXT = {"X": "error raised", "N": "non-finite", "E": "explosion", "T": "tunnelling",
             "C": "state chattering", "O": "outcome differs from reference",
             "p": "penetration", "d": "drift", "e": "energy growth"}
AXIS_LABEL = {
    "mass_heavy_on_light": "mass, heavy on light", "mass_light_on_heavy": "mass, light on heavy",
    "size_small": "box size, small", "size_large": "box size, large",
    "plank_flat": "plank across a box", "plank_upright": "plank on its end",
    "polygon_vertices": "n-gon on a box", "collinear": "near-collinear vertex",
    "projectile_stack": "projectile into stack", "projectile_wall": "projectile into wall",
    "dt": "time step (10-box stack)", "iterations": "iterations (10-box stack)",
    "stack_height": "stack height", "pyramid_base": "pyramid base", "bodies": "many bodies",
    "long_run": "long resting run", "impact_threshold": "impact at threshold",
    "knife_edge": "knife edge",
}


def value_label(axis, value):
    """A value as the grid prints it."""
    v = float(value)
    if axis.startswith("mass"):
        return "1:1" if v == 1 else (f"{v:g}:1" if v > 1 else f"1:{1 / v:g}")
    if axis.startswith("size"):
        return f"{v:g} m"
    if axis.startswith("plank"):
        return f"{v:g}:1"
    if axis == "collinear":
        return f"eps {v:.0e} m"
    if axis.startswith("projectile"):
        return f"{v:g} m/s"
    if axis == "dt":
        return f"1/{round(1 / v)} s"
    if axis in ("bodies", "long_run"):
        exp = math.log10(v)
        return f"10^{exp:.0f}" if exp == int(exp) else f"{v:g}"
    if axis == "impact_threshold":
        return f"v*(1{v:+.0e})"
    if axis == "knife_edge":
        return "exact" if v == 0 else f"tilt {v:.0e} rad"
    return f"{v:g}"


def codes(reason, status):
    """The cell's reason letters, in CODES order: a failed cell shows why it failed (capitals), a
    degraded one what degraded (lower case)."""
    reason = reason if isinstance(reason, str) else ""
    letters = "".join(code for word, code in CODES if word in reason)
    if status == "failed":
        return "".join(c for c in letters if c.isupper())
    if status == "degraded":
        return "".join(c for c in letters if c.islower())
    return ""


def _grid(table):
    """[(axis, value, {system: (status, codes)})] in the table's order (benign to extreme)."""
    rows = {}
    for r in table.itertuples():
        key = (r.axis, r.value)
        rows.setdefault(key, {})[r.system] = (r.status, codes(r.reason, r.status))
    return [(axis, value, cells) for (axis, value), cells in rows.items()]


def draw_grid(grid, systems):
    """The heat map: two panels side by side, split at an axis boundary near the middle."""
    n = len(grid)
    axes_order = list(dict.fromkeys(a for a, _, _ in grid))
    split, count = n, 0
    for axis in axes_order:
        count += sum(1 for a, _, _ in grid if a == axis)
        if count >= n / 2:
            split = count
            break
    halves = [grid[:split], grid[split:]] if split < n else [grid]
    tall = max(len(h) for h in halves)
    row_in, head_in, foot_in = 0.125, 0.62, 0.5           # inches: a row, the header, the key
    height = head_in + row_in * tall + foot_in
    fig, panels = plt.subplots(1, len(halves), figsize=(style.WIDTH, height), squeeze=False)
    for ax, half in zip(panels[0], halves):
        for y, (axis, value, cells) in enumerate(half):
            for x, system in enumerate(systems):
                status, letters = cells.get(system, ("not run", ""))
                ax.add_patch(plt.Rectangle((x, y), 1, 1, facecolor=STATUS_COLOR[status],
                                           edgecolor="white", linewidth=0.6,
                                           hatch="////" if status == "not run" else None))
                if letters:
                    ax.text(x + 0.5, y + 0.55, letters, ha="center", va="center",
                            fontsize=4.6 if len(letters) < 4 else 3.8,
                            color="white" if status == "failed" else "black")
        labels, previous = [], None
        for axis, value, _ in half:
            head = AXIS_LABEL.get(axis, axis) + ": " if axis != previous else ""
            labels.append(head + value_label(axis, value))
            previous = axis
        # a thin rule between axes
        for y in range(1, len(half)):
            if half[y][0] != half[y - 1][0]:
                ax.axhline(y, color="black", linewidth=0.6)
        ax.set_xlim(0, len(systems))
        ax.set_ylim(tall, 0)
        ax.set_yticks([y + 0.5 for y in range(len(half))])
        ax.set_yticklabels(labels, fontsize=5.2)
        ax.set_xticks([x + 0.5 for x in range(len(systems))])
        ax.set_xticklabels(systems, rotation=60, ha="left", fontsize=5.5)
        ax.xaxis.tick_top()
        ax.tick_params(length=0, pad=1.5)
        ax.grid(False)
        for side in ax.spines.values():
            side.set_visible(False)
    handles = [Patch(facecolor=STATUS_COLOR[s], edgecolor="0.6", label=s,
                     hatch="////" if s == "not run" else None) for s in STATUS_ORDER]
    failed_codes = "   ".join(f"{c} {t}" for c, t in CODE_TEXT.items() if c.isupper())
    degraded_codes = "   ".join(f"{c} {t}" for c, t in CODE_TEXT.items() if c.islower())
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=6,
               frameon=False, bbox_to_anchor=(0.5, 0.22 / height))
    fig.text(0.5, 0.06 / height, f"failed because: {failed_codes}\ndegraded by: {degraded_codes}",
             ha="center", va="bottom", fontsize=5.2, linespacing=1.4)
    fig.subplots_adjust(left=0.17, right=0.99, top=1 - head_in / height,
                        bottom=foot_in / height, wspace=0.9)
    return fig


def _position(values, value):
    """Index of ``value`` in the axis's values (read back from CSV: compared to round-off)."""
    for k, v in enumerate(values):
        if math.isclose(float(v), float(value), rel_tol=1e-9, abs_tol=1e-15):
            return k
    raise ValueError(f"value {value!r} is not one of the axis's values {values}")


def headline(table, systems, axes_values):
    """Per axis, the first value (benign to extreme) at which each system degrades or fails and
    the system(s) that break first; counts of each mark per system."""
    per_axis = {}
    for axis, values in axes_values.items():
        t = table[table["axis"] == axis]
        if t.empty:
            continue
        breaks, fails = {}, {}
        for system in systems:
            s = t[t["system"] == system]
            order = sorted(s.itertuples(), key=lambda r: _position(values, r.value))
            first_break = next((r for r in order if r.status in ("degraded", "failed")), None)
            first_fail = next((r for r in order if r.status == "failed"), None)
            breaks[system] = (_position(values, first_break.value) if first_break is not None
                              else math.inf, first_break)
            fails[system] = first_fail.value if first_fail is not None else None
        earliest = min(i for i, _ in breaks.values())
        first = ([s for s, (i, _) in breaks.items() if i == earliest]
                 if math.isfinite(earliest) else [])
        per_axis[axis] = {
            "breaks_first": first,
            "breaks_first_at": (value_label(axis, values[earliest]) if math.isfinite(earliest)
                                else None),
            "first_degraded_or_failed": {s: (value_label(axis, r.value) if r is not None else None)
                                         for s, (_, r) in breaks.items()},
            "first_failed": {s: (value_label(axis, v) if v is not None else None)
                             for s, v in fails.items()},
        }
    counts = {s: {st: int(((table["system"] == s) & (table["status"] == st)).sum())
                  for st in STATUS_ORDER} for s in systems}
    return per_axis, counts


def freezing_effect(table):
    """Cells where a freezing system (sim-sleep/-paper/-extended, pymunk-sleep, pybullet-sleep)
    is marked worse, or better, than its engine with sleeping off (experiments.common.REFERENCE)
    on the same (axis, value): what freezing itself costs or saves at the extremes."""
    marks = {(r.axis, r.value, r.system): r.status for r in table.itertuples()}
    worse, better = [], []
    for (axis, value, system), status in marks.items():
        base = REFERENCE.get(system, system)
        other = marks.get((axis, value, base))
        if base == system or status not in SEVERITY or other not in SEVERITY:
            continue
        text = f"{system} {AXIS_LABEL.get(axis, axis)} {value_label(axis, value)}: {status} " \
               f"({base}: {other})"
        if SEVERITY[status] > SEVERITY[other]:
            worse.append(text)
        elif SEVERITY[status] < SEVERITY[other]:
            better.append(text)
    return worse, better


def summary_table(grid, systems):
    """One row per (axis, value), one column per system: the mark and its reason letters."""
    rows = []
    for axis, value, cells in grid:
        row = {"axis": AXIS_LABEL.get(axis, axis), "value": value_label(axis, value)}
        for system in systems:
            status, letters = cells.get(system, ("not run", ""))
            row[system] = status + (f" ({letters})" if letters else "")
        rows.append(row)
    return pd.DataFrame(rows)


def draw(table, meta):
    table = table.copy()
    for col in ("reason", "decision"):               # an all-empty column reads back as NaN
        table[col] = table[col].astype(object).fillna("").astype(str)
    params = meta.get("parameters", {})
    axes_values = {a: v["values"] for a, v in params.get("axes", {}).items()}
    if not axes_values:
        raise ValueError("table_extremes.json has no parameters.axes: rerun the experiment")
    systems = [s for s in SYSTEMS if s in set(table["system"])]
    grid = _grid(table)
    fig = draw_grid(grid, systems)
    style.save_figure(fig, FIGURE)
    style.write_table(summary_table(grid, systems), NAME)
    per_axis, counts = headline(table, systems, axes_values)
    sim_systems = [s for s in systems if s.startswith("sim-")]
    sim_failed = table[table["system"].isin(sim_systems) & (table["status"] == "failed")]
    thresholds = params.get("thresholds", {})
    decisions = {f"{r.system} {value_label(r.axis, r.value)}": r.decision
                 for r in table[(table["axis"] == "impact_threshold")
                                & (table["decision"] != "")].itertuples()}
    chatter = table[table["reason"].str.contains("chattering")]
    worse, better = freezing_effect(table)
    refs = params.get("references", [])
    return {
        "cells": int(len(table)),
        "counts": counts,
        "per_axis": per_axis,
        "sim_failures": [f"{r.system} {AXIS_LABEL.get(r.axis, r.axis)} "
                         f"{value_label(r.axis, r.value)}: {r.reason}"
                         for r in sim_failed.itertuples()],
        "freezing_worse_than_off": worse,
        "freezing_better_than_off": better,
        "chattering_cells": [f"{r.system} {r.axis} {value_label(r.axis, r.value)}"
                             for r in chatter.itertuples()],
        "impact_threshold_v_star": {p: thresholds[p].get("v_star") for p in thresholds},
        "impact_decisions": decisions,
        "references_invalid": [r["key"] for r in refs if not r.get("valid", True)],
        "rules": params.get("rules", {}),
    }


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
