"""Table "table_extremes" and figure "fig_extremes": every (axis, value) x system run of the
extremes sweep marked stable / degraded / failed / rejected / not run by the experiment's stated
rules (experiments/table_extremes.py, study/extremes/), drawn as a grid; the numbers say, per
axis, which system breaks first and how many cells each system has of each mark.

Two things are kept apart, for fairness by construction:
- every system as it runs by default (sim with its presolve: a scene placed at rest starts
  in equilibrium), which give ``counts``, ``per_axis`` (which system breaks first) and the rest;
- sim's four policies with the presolve off ("sim-off (no presolve)" ...), run only on the placed
  axes: the peers have no presolve, so this is sim without an advantage only it has. They are
  drawn to the right of a gap in the figure and summarised under ``no_presolve``, whose
  ``per_axis`` says which system breaks first when sim runs without its presolve.
The headline the study states, ``breaks_first``, takes each placed axis from those fair rows and
every other axis from the systems as run (``fair_headline``).
Axes of a knob only sim has (``substeps``) name no system as breaking first: there is nothing to
compare with. Cells refused with a clear error ("rejected": a ValueError before the first step,
e.g. sim refusing a body too small for its substeps) are never counted as breaking; they are
listed, with their messages, under ``rejected_cells`` and per axis under ``first_rejected``.

Writes paper/figures/fig_extremes.svg, paper/generated/table_extremes.csv (one row per
(axis, value), one column per system, each cell its mark and reason codes, "n/a" where the system
has no cell on that axis) and paper/generated/table_extremes.json. Never simulates.
"""

import math

import matplotlib.pyplot as plt
import pandas as pd
from matplotlib.patches import Patch

from analysis import style
from study.metadata import ResultsError, rerun_hint
from study.common import REFERENCE, SYSTEMS
from study.extremes.axes import AXES, SIM_ONLY_AXES, applies
from study.systems import NO_PRESOLVE, NO_PRESOLVE_SYSTEMS, runner_system

NAME = "table_extremes"
FIGURE = "fig_extremes"

#: one colour per mark (Okabe-Ito-like; failed and stable differ in lightness too, for grey print)
STATUS_COLOR = {
    "stable": "#c7e9c0",
    "degraded": "#f0c571",
    "failed": "#d55e00",
    "rejected": "#56b4e9",
    "not run": "#e8e8e8",
}
STATUS_ORDER = ("stable", "degraded", "failed", "rejected", "not run")
#: the legend's words for a mark
STATUS_LABEL = {"rejected": "refused (clear error)"}
#: a system that has no cell on an axis (no-presolve systems off the placed axes, peers on a
#: sim-only axis): drawn blank, written "n/a"
NOT_APPLICABLE = "n/a"
#: how bad a mark is, to compare a freezing system with its engine's sleeping-off system
SEVERITY = {"stable": 0, "degraded": 1, "failed": 2}
#: reason -> one-letter code drawn in the cell (failed: capitals, degraded: lower case)
CODES = (
    ("error", "X"),
    ("non-finite", "N"),
    ("explosion", "E"),
    ("tunnelling", "T"),
    ("chattering", "C"),
    ("outcome", "O"),
    ("penetration", "p"),
    ("drift", "d"),
    ("energy growth", "e"),
)
CODE_TEXT = {
    "X": "error raised",
    "N": "non-finite",
    "E": "explosion",
    "T": "tunnelling",
    "C": "state chattering",
    "O": "outcome differs from reference",
    "p": "penetration",
    "d": "drift",
    "e": "energy growth",
}
#: the figure's words for each axis (its Axis record's label)
AXIS_LABEL = {name: axis.label for name, axis in AXES.items()}


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


def columns_x(systems, variants, gap=0.5):
    """{system: left edge of its column}: the systems, then a gap, then the no-presolve ones
    (reported apart, see the module docstring)."""
    x = {s: float(k) for k, s in enumerate(systems)}
    x.update({s: len(systems) + gap + k for k, s in enumerate(variants)})
    return x


def draw_grid(grid, systems, variants=()):
    """The heat map: two panels side by side, split at an axis boundary near the middle; the
    no-presolve systems (``variants``) to the right of a gap. A system with no cell on an axis
    (not applicable) is left blank; an applicable cell missing from the table is "not run"."""
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
    row_in, head_in, foot_in = 0.125, 0.62, 0.5  # inches: a row, the header, the key
    height = head_in + row_in * tall + foot_in
    fig, panels = plt.subplots(1, len(halves), figsize=(style.WIDTH, height), squeeze=False)
    where = columns_x(systems, variants)
    every = list(systems) + list(variants)
    right = max(where.values()) + 1 if where else 0
    for ax, half in zip(panels[0], halves):
        for y, (axis, value, cells) in enumerate(half):
            for system in every:
                x = where[system]
                if system not in cells and not applies(axis, system):
                    continue  # not applicable: blank
                status, letters = cells.get(system, ("not run", ""))
                ax.add_patch(
                    plt.Rectangle(
                        (x, y),
                        1,
                        1,
                        facecolor=STATUS_COLOR[status],
                        edgecolor="white",
                        linewidth=0.6,
                        hatch="////" if status == "not run" else None,
                    )
                )
                if letters:
                    ax.text(
                        x + 0.5,
                        y + 0.55,
                        letters,
                        ha="center",
                        va="center",
                        fontsize=4.6 if len(letters) < 4 else 3.8,
                        color="white" if status == "failed" else "black",
                    )
        labels, previous = [], None
        for axis, value, _ in half:
            head = AXIS_LABEL.get(axis, axis) + ": " if axis != previous else ""
            labels.append(head + value_label(axis, value))
            previous = axis
        # a thin rule between axes
        for y in range(1, len(half)):
            if half[y][0] != half[y - 1][0]:
                ax.axhline(y, color="black", linewidth=0.6)
        if variants:  # the no-presolve systems are reported apart
            ax.axvline(
                where[variants[0]] - 0.25,
                color="0.4",
                linewidth=0.6,
                ymax=len(half) / tall if tall else 1,
            )
        ax.set_xlim(0, right)
        ax.set_ylim(tall, 0)
        ax.set_yticks([y + 0.5 for y in range(len(half))])
        ax.set_yticklabels(labels, fontsize=5.2)
        ax.set_xticks([where[s] + 0.5 for s in every])
        ax.set_xticklabels(every, rotation=60, ha="left", fontsize=5.5)
        ax.xaxis.tick_top()
        ax.tick_params(length=0, pad=1.5)
        ax.grid(False)
        for side in ax.spines.values():
            side.set_visible(False)
    handles = [
        Patch(
            facecolor=STATUS_COLOR[s],
            edgecolor="0.6",
            label=STATUS_LABEL.get(s, s),
            hatch="////" if s == "not run" else None,
        )
        for s in STATUS_ORDER
    ]
    handles.append(Patch(facecolor="white", edgecolor="0.6", label="blank: not applicable"))
    failed_codes = "   ".join(f"{c} {t}" for c, t in CODE_TEXT.items() if c.isupper())
    degraded_codes = "   ".join(f"{c} {t}" for c, t in CODE_TEXT.items() if c.islower())
    fig.legend(
        handles=handles,
        loc="lower center",
        ncol=len(handles),
        fontsize=6,
        frameon=False,
        bbox_to_anchor=(0.5, 0.22 / height),
    )
    fig.text(
        0.5,
        0.06 / height,
        f"failed because: {failed_codes}\ndegraded by: {degraded_codes}",
        ha="center",
        va="bottom",
        fontsize=5.2,
        linespacing=1.4,
    )
    fig.subplots_adjust(
        left=0.17, right=0.99, top=1 - head_in / height, bottom=foot_in / height, wspace=0.9
    )
    return fig


def _position(values, value):
    """Index of ``value`` in the axis's values (read back from CSV: compared to round-off)."""
    for k, v in enumerate(values):
        if math.isclose(float(v), float(value), rel_tol=1e-9, abs_tol=1e-15):
            return k
    raise ValueError(f"value {value!r} is not one of the axis's values {values}")


def headline(table, systems, axes_values):
    """Per axis, the first value (benign to extreme) at which each of ``systems`` degrades or
    fails (a refused cell, "rejected", is not breaking: its first value is listed apart) and the
    system(s) that break first: before at least one other system (none on a sim-only axis:
    nothing to compare with). Where every system with a cell on the axis breaks at the same
    value, none breaks *first*: ``breaks_together_at`` says where they all break. Counts of each
    mark per system. Only ``systems``' cells are read."""
    per_axis = {}
    for axis, values in axes_values.items():
        t = table[(table["axis"] == axis) & table["system"].isin(systems)]
        if t.empty:
            continue
        breaks, fails, refused = {}, {}, {}
        for system in systems:
            s = t[t["system"] == system]
            if s.empty:  # not applicable on this axis
                continue
            order = sorted(s.itertuples(), key=lambda r: _position(values, r.value))
            first_break = next((r for r in order if r.status in ("degraded", "failed")), None)
            first_fail = next((r for r in order if r.status == "failed"), None)
            first_refused = next((r for r in order if r.status == "rejected"), None)
            breaks[system] = (
                _position(values, first_break.value) if first_break is not None else math.inf,
                first_break,
            )
            fails[system] = first_fail.value if first_fail is not None else None
            refused[system] = first_refused.value if first_refused is not None else None
        compared = axis not in SIM_ONLY_AXES
        earliest = min((i for i, _ in breaks.values()), default=math.inf) if compared else math.inf
        first = (
            [s for s, (i, _) in breaks.items() if i == earliest] if math.isfinite(earliest) else []
        )
        together = len(breaks) > 1 and len(first) == len(breaks)
        per_axis[axis] = {
            "breaks_first": [] if together else first,
            "breaks_first_at": (
                value_label(axis, values[earliest])
                if math.isfinite(earliest) and not together
                else None
            ),
            "breaks_together_at": value_label(axis, values[earliest]) if together else None,
            "compared": compared,
            "first_degraded_or_failed": {
                s: (value_label(axis, r.value) if r is not None else None)
                for s, (_, r) in breaks.items()
            },
            "first_failed": {
                s: (value_label(axis, v) if v is not None else None) for s, v in fails.items()
            },
            "first_rejected": {
                s: value_label(axis, v) for s, v in refused.items() if v is not None
            },
        }
    counts = {
        s: {
            st: int(((table["system"] == s) & (table["status"] == st)).sum()) for st in STATUS_ORDER
        }
        for s in systems
    }
    return per_axis, counts


def freezing_effect(table, systems=None):
    """Cells where a freezing system (sim-sleep/-paper/-extended, pymunk-sleep, pybullet-sleep,
    and the no-presolve sim policies) is marked worse, or better, than its engine with sleeping
    off (study.common.REFERENCE; a no-presolve policy against sim-off without presolve too)
    on the same (axis, value): what freezing itself costs or saves at the extremes. Only the
    cells of ``systems`` (default: all) are compared."""
    marks = {
        (r.axis, r.value, r.system): r.status
        for r in table.itertuples()
        if systems is None or r.system in systems
    }
    worse, better = [], []
    for (axis, value, system), status in marks.items():
        runner = runner_system(system)
        base = REFERENCE.get(runner, runner) + system[len(runner) :]
        other = marks.get((axis, value, base))
        if base == system or status not in SEVERITY or other not in SEVERITY:
            continue
        text = (
            f"{system} {AXIS_LABEL.get(axis, axis)} {value_label(axis, value)}: {status} "
            f"({base}: {other})"
        )
        if SEVERITY[status] > SEVERITY[other]:
            worse.append(text)
        elif SEVERITY[status] < SEVERITY[other]:
            better.append(text)
    return worse, better


def summary_table(grid, systems):
    """One row per (axis, value), one column per system: the mark and its reason letters, "n/a"
    where the system has no cell on that axis."""
    rows = []
    for axis, value, cells in grid:
        row = {"axis": AXIS_LABEL.get(axis, axis), "value": value_label(axis, value)}
        for system in systems:
            if system not in cells and not applies(axis, system):
                row[system] = NOT_APPLICABLE
                continue
            status, letters = cells.get(system, ("not run", ""))
            row[system] = status + (f" ({letters})" if letters else "")
        rows.append(row)
    return pd.DataFrame(rows)


def _failures(table, systems):
    failed = table[table["system"].isin(systems) & (table["status"] == "failed")]
    return [
        f"{r.system} {AXIS_LABEL.get(r.axis, r.axis)} {value_label(r.axis, r.value)}: {r.reason}"
        for r in failed.itertuples()
    ]


def draw(table, meta):
    table = table.copy()
    for col in ("reason", "decision", "error"):  # an all-empty column reads back as NaN
        if col in table:
            table[col] = table[col].astype(object).fillna("").astype(str)
    params = meta.get("parameters", {})
    axes_values = {a: v["values"] for a, v in params.get("axes", {}).items()}
    if not axes_values:
        raise ResultsError(f"{NAME}.json has no parameters.axes: {rerun_hint(NAME)}")
    present = set(table["system"])
    systems = [s for s in SYSTEMS if s in present]
    variants = [s for s in NO_PRESOLVE_SYSTEMS if s in present]
    grid = _grid(table)
    fig = draw_grid(grid, systems, variants)
    style.save_figure(fig, FIGURE)
    style.write_table(summary_table(grid, systems + variants), NAME)
    main_table = table[table["system"].isin(systems)]
    per_axis, counts = headline(main_table, systems, axes_values)
    sim_systems = [s for s in systems if s.startswith("sim-")]
    thresholds = params.get("thresholds", {})
    decisions = {
        f"{r.system} {value_label(r.axis, r.value)}": r.decision
        for r in main_table[
            (main_table["axis"] == "impact_threshold") & (main_table["decision"] != "")
        ].itertuples()
    }
    chatter = table[table["reason"].str.contains("chattering")]
    worse, better = freezing_effect(table, systems)
    refs = params.get("references", [])
    rejected = table[table["status"] == "rejected"]
    no_presolve = no_presolve_numbers(table, systems, variants, axes_values)
    return {
        "cells": int(len(main_table)),
        "counts": counts,
        "per_axis": per_axis,
        "sim_failures": _failures(table, sim_systems),
        "freezing_worse_than_off": worse,
        "freezing_better_than_off": better,
        "chattering_cells": [
            f"{r.system} {r.axis} {value_label(r.axis, r.value)}" for r in chatter.itertuples()
        ],
        "rejected_cells": [
            f"{r.system} {AXIS_LABEL.get(r.axis, r.axis)} "
            f"{value_label(r.axis, r.value)}: {r.error or r.reason}"
            for r in rejected.itertuples()
        ],
        "impact_threshold_v_star": {p: thresholds[p].get("v_star") for p in thresholds},
        "impact_decisions": decisions,
        "references_invalid": [r["key"] for r in refs if not r.get("valid", True)],
        "rules": params.get("rules", {}),
        "no_presolve": no_presolve,
        "breaks_first": fair_headline(per_axis, no_presolve),
    }


def fair_headline(per_axis, no_presolve):
    """Which system breaks first, axis by axis, as the study states it: on the axes that start
    placed at rest, from the fair rows (sim without its presolve, which no peer has, against the
    same peers: ``no_presolve``'s ``per_axis``); on every other axis, from the systems as run.
    Each entry says which (``protocol``: "sim without presolve" or "as run"), and where the fair
    rows name other systems than sim with its presolve would (``with_presolve``: what those
    rows said)."""
    fair = no_presolve.get("per_axis", {})
    out = {}
    for axis, entry in per_axis.items():
        if axis in fair:
            f = fair[axis]
            out[axis] = {
                "protocol": "sim without presolve",
                "breaks_first": f["breaks_first"],
                "breaks_first_at": f["breaks_first_at"],
                "breaks_together_at": f["breaks_together_at"],
                "with_presolve": {
                    "breaks_first": entry["breaks_first"],
                    "breaks_first_at": entry["breaks_first_at"],
                },
            }
        else:
            out[axis] = {
                "protocol": "as run",
                "breaks_first": entry["breaks_first"],
                "breaks_first_at": entry["breaks_first_at"],
                "breaks_together_at": entry["breaks_together_at"],
            }
    return out


def no_presolve_numbers(table, systems, variants, axes_values):
    """The no-presolve systems, reported apart: their counts, and per placed axis which system
    breaks first when sim runs without its presolve (sim's four default systems swapped for their
    no-presolve twins, against the same peers), and how each sim policy's first break moved."""
    if not variants:
        return {"systems": [], "cells": 0, "counts": {}, "per_axis": {}}
    placed = {
        a: v
        for a, v in axes_values.items()
        if table[(table["axis"] == a) & table["system"].isin(variants)].shape[0]
    }
    fair = [s for s in systems if not s.startswith("sim-")] + variants
    per_axis, counts = headline(table[table["system"].isin(fair)], fair, placed)
    with_presolve, _ = headline(table[table["system"].isin(systems)], systems, placed)
    for axis, entry in per_axis.items():
        entry["with_presolve"] = {
            v: with_presolve.get(axis, {}).get("first_degraded_or_failed", {}).get(runner_system(v))
            for v in variants
        }
    worse, better = freezing_effect(table, variants)
    degraded = table[table["status"] == "degraded"]
    return {
        "systems": variants,
        "suffix": NO_PRESOLVE,
        "axes": list(placed),
        "cells": int(table["system"].isin(variants).sum()),
        "counts": {v: counts[v] for v in variants},
        "per_axis": per_axis,
        "sim_failures": _failures(table, variants),
        # each variant's degraded cells: scene -> the largest drift over the run, in widths
        "degraded_drift": {
            v: {r.scene: float(r.drift_rel) for r in degraded[degraded["system"] == v].itertuples()}
            for v in variants
        },
        "freezing_worse_than_off": worse,
        "freezing_better_than_off": better,
    }


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
