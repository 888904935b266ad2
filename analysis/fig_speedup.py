"""Figure 4 "fig_speedup": ms/step against body count on resting scenes (rest_row, pyramid), every
system, log-log (top), and the speed-up over the same engine with sleeping off (bottom).

A hollow marker is a system timed while some bodies were still solved (not all frozen/asleep: the
count is in the table). paper/generated/fig_speedup.csv: per scene and system, ms/step (median)
and the speed-up. The numbers: per family, at its largest size, every system's ms/step, speed-up
and awake count; pybullet's at the largest size it was run at.
"""

import math

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.lines import Line2D
from matplotlib.ticker import FuncFormatter, NullFormatter

from analysis import style
from study import systems

NAME = "fig_speedup"
FAMILY_TITLE = {"rest_row": "resting row: rest_row(n)", "pyramid": "pyramid(base)"}
FREEZING = systems.FREEZING


def _check(table):
    need = {
        "family",
        "size",
        "scene",
        "bodies",
        "system",
        "ms_per_step_median",
        "speedup",
        "n_awake_before",
        "n_awake_after",
        "flag",
    }
    missing = need - set(table.columns)
    if missing:
        raise ValueError(f"{NAME}: results table lacks columns {sorted(missing)}")
    table = table.copy()
    table["flag"] = table["flag"].astype(object).fillna("")
    return table


def _plot_family(ax_ms, ax_sp, t, systems):
    for system in systems:
        s = t[(t["system"] == system) & t["ms_per_step_median"].notna()].sort_values("bodies")
        if s.empty:
            continue
        st = style.system_style(system)
        x, y = s["bodies"].to_numpy(float), s["ms_per_step_median"].to_numpy(float)
        whole = (s["flag"] != "NOT all frozen").to_numpy()
        ax_ms.plot(x, y, color=st["color"], linestyle=st["linestyle"], label=system)
        ax_ms.plot(x[whole], y[whole], linestyle="none", marker=st["marker"], color=st["color"])
        ax_ms.plot(
            x[~whole],
            y[~whole],
            linestyle="none",
            marker=st["marker"],
            markerfacecolor="white",
            color=st["color"],
        )
        if system in FREEZING:
            sp = s["speedup"].to_numpy(float)
            ax_sp.plot(x, sp, color=st["color"], linestyle=st["linestyle"])
            ax_sp.plot(
                x[whole], sp[whole], linestyle="none", marker=st["marker"], color=st["color"]
            )
            ax_sp.plot(
                x[~whole],
                sp[~whole],
                linestyle="none",
                marker=st["marker"],
                markerfacecolor="white",
                color=st["color"],
            )
    ax_sp.axhline(1.0, color="0.4", linewidth=0.8, linestyle="-")
    for ax in (ax_ms, ax_sp):
        ax.set_xscale("log")
        ax.set_yscale("log")
        # ticks at the measured sizes, as plain numbers: the sizes are read off the axis
        ax.set_xticks(sorted(t["bodies"].unique()))
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.xaxis.set_minor_formatter(NullFormatter())
    ax_sp.set_xlabel("bodies")


def draw(table, meta):
    table = _check(table)
    systems = [s for s in style.SYSTEM_STYLE if s in set(table["system"])]
    families = [f for f in FAMILY_TITLE if f in set(table["family"])]
    if not families:
        raise ValueError(f"{NAME}: no rest_row or pyramid rows in the table")
    fig, axes = plt.subplots(
        2, len(families), figsize=(style.WIDTH, 5.0), squeeze=False, sharex="col"
    )
    for j, family in enumerate(families):
        t = table[table["family"] == family]
        _plot_family(axes[0, j], axes[1, j], t, systems)
        axes[0, j].set_title(FAMILY_TITLE[family])
    axes[0, 0].set_ylabel("ms per step (median)")
    axes[1, 0].set_ylabel("speed-up over sleeping off\n(same engine)")
    cap = meta.get("parameters", {}).get("pybullet_max_bodies")
    handles = []
    for s in systems:
        st = style.system_style(s)
        text = f"{s} (<= {cap} bodies)" if cap and s.startswith("pybullet") else s
        handles.append(
            Line2D(
                [],
                [],
                color=st["color"],
                marker=st["marker"],
                linestyle=st["linestyle"],
                label=text,
            )
        )
    handles.append(
        Line2D(
            [],
            [],
            color="0.3",
            marker="o",
            markerfacecolor="white",
            linestyle="none",
            label="not all frozen while timed",
        )
    )
    fig.legend(
        handles=handles, loc="lower center", ncol=4, frameon=False, bbox_to_anchor=(0.5, 0.0)
    )
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    style.save_figure(fig, NAME)

    style.write_table(_paper_table(table, systems), NAME)
    return _numbers(table, families, systems, cap)


def _ratio(x):
    """A speed-up as printed: 3 significant figures, whole numbers from 100 up (2602, not
    2.6e+03)."""
    return f"{x:.0f}" if math.isfinite(x) and x >= 100 else style.fmt(x)


def _paper_table(table, systems):
    """One row per scene; per system "ms (xspeed-up)", "-" where not run; "*k awake" = not all
    frozen while timed (before -> after the timing when it changed)."""
    rows = []
    for scene, t in table.groupby("scene", sort=False):
        row = {"scene": scene, "bodies": int(t["bodies"].iloc[0])}
        for system in systems:
            r = t[t["system"] == system]
            if r.empty or not math.isfinite(r["ms_per_step_median"].iloc[0]):
                row[system] = "-"
                continue
            r = r.iloc[0]
            cell = f"{style.fmt(r['ms_per_step_median'])}"
            if system in FREEZING:
                cell += f" (x{_ratio(r['speedup'])})"
            if r["flag"] == "NOT all frozen":
                before, after = int(r["n_awake_before"]), int(r["n_awake_after"])
                cell += f" *{before} awake" if before == after else f" *{before}->{after} awake"
            row[system] = cell
        rows.append(row)
    return pd.DataFrame(rows)


def _numbers(table, families, systems, cap):
    out = {"pybullet_max_bodies": cap, "units": "ms per step; speed-up = ratio"}
    for family in families:
        t = table[table["family"] == family]
        largest = int(t["bodies"].max())
        at = t[t["bodies"] == largest]
        fam = {
            "largest_scene": at["scene"].iloc[0],
            "largest_bodies": largest,
            "sizes": sorted(int(b) for b in t["bodies"].unique()),
            "ms": {},
            "speedup": {},
            "speedup_paired": {},
            "ms_per_call": {},
            "speedup_single": {},
            "n_awake": {},
            "n_awake_after": {},
        }
        for r in at.itertuples():
            if math.isfinite(r.ms_per_step_median):
                fam["ms"][r.system] = r.ms_per_step_median
                fam["speedup"][r.system] = r.speedup
                fam["speedup_paired"][r.system] = getattr(r, "speedup_paired", math.nan)
                fam["ms_per_call"][r.system] = r.ms_per_call_median
                fam["speedup_single"][r.system] = r.speedup_single
                fam["n_awake"][r.system] = int(r.n_awake_before)
                fam["n_awake_after"][r.system] = int(r.n_awake_after)
        # each system at the largest size it was run at (pybullet is capped)
        fam["largest_run"] = {}
        for system in systems:
            s = t[(t["system"] == system) & t["ms_per_step_median"].notna()]
            if s.empty:
                continue
            r = s.loc[s["bodies"].idxmax()]
            fam["largest_run"][system] = {
                "scene": r["scene"],
                "bodies": int(r["bodies"]),
                "ms": r["ms_per_step_median"],
                "speedup": r["speedup"],
                "n_awake": int(r["n_awake_before"]),
            }
        # the largest speed-up anywhere in the family, per system
        fam["max_speedup"] = {
            s: float(np.nanmax(t.loc[t["system"] == s, "speedup"]))
            for s in FREEZING
            if (t["system"] == s).any() and t.loc[t["system"] == s, "speedup"].notna().any()
        }
        out[family] = fam
    partial = table[table["flag"] == "NOT all frozen"]
    out["not_all_frozen"] = [
        f"{r.scene} {r.system}: {int(r.n_awake_before)} of {int(r.bodies)} awake"
        for r in partial.itertuples()
    ]
    paper = table[
        (table["family"] == "pyramid")
        & (table["system"] == "sim-paper")
        & table["n_awake_before"].notna()
    ]
    out["paper_pyramid_awake_fraction"] = {
        r.scene: r.n_awake_before / r.bodies for r in paper.itertuples()
    }
    return out


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
