"""Figure 7 "fig_tradeoff": speed-up against error for every freezing / sleeping setting, with the
Pareto front per system.

One row of panels per scene, one column per error measure (the largest distance between a body's
final centre of mass and the fine-dt reference's; the deepest overlap between two bodies or a body
and the floor at the end of the run: what freezing locks in. The deepest overlap *during* the run
is set by the impacts, the same under every setting, and goes to the numbers only). x is
the speed-up of the whole run over the same engine with sleeping off at the same dt (log), y the
error (log; an error at or below the experiment's ``error_floor`` (1e-9: round-off, or exactly 0,
as for bodies frozen before they ever touched) is drawn hollow at the bottom of its panel, a
third of the panel's smallest larger value). The engines' sleeping-off
runs at dt (speed-up 1) are the baselines: their error is the time step's own, and a horizontal
line at it shows what freezing adds on top. A system's Pareto front (no other of its settings is
both faster and more accurate) is a step line; its default setting has a black edge.

Writes paper/figures/fig_tradeoff.svg, paper/generated/fig_tradeoff.csv (the Pareto points) and
returns the headline numbers (paper/generated/fig_tradeoff.json): per scene, each engine's baseline
errors and its reference's resolution; per system, its default setting's speed-up and errors, its
fastest setting, and its fastest setting that froze something and still *matches the baseline* in
both measures: pose error at most the baseline's plus the reference's resolution (the error of the
dt/(fine/2) run against the dt/fine reference: closer than that cannot be told apart), final
overlap at most the baseline's plus a tenth of the slop. ``never_froze_speedups`` are the
speed-ups of settings under which no body ever froze: they do the baseline's work, so their
distance from 1 is the run's timing noise."""
import math

import matplotlib.pyplot as plt
from matplotlib.lines import Line2D
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter
import numpy as np
import pandas as pd

from analysis import style

NAME = "fig_tradeoff"
#: (column, axis label, short name in the numbers) of each error measure drawn
MEASURES = (("pose_error_max_m", "largest pose error (m)", "pose"),
            ("penetration_final_m", "deepest overlap at the end (m)", "penetration"))
FREEZING = ("sim-paper", "sim-extended", "sim-sleep", "pymunk-sleep", "pybullet-sleep")
OFF = {"sim": "sim-off", "pymunk": "pymunk", "pybullet": "pybullet"}
#: a setting "matches the baseline" in penetration when the overlap it leaves at the end exceeds the
#: baseline's by at most this fraction of the slop (0.5 mm at slop 5 mm)
PENETRATION_MARGIN = 0.1
REQUIRED = {"scene", "system", "engine", "role", "parameter", "value", "is_default", "speedup",
            "speedup_min", "awake_fraction", "bodies",
            "pose_error_max_m", "pose_error_mean_m", "penetration_max_m", "penetration_final_m"}


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


def _setting(row):
    if row["parameter"] == "none":
        return "sleeping off"
    return f"{row['parameter']}={row['value']:.3g}"


def draw(table, meta):
    missing = REQUIRED - set(table.columns)
    if missing:
        raise ValueError(f"{NAME}: results lack columns {sorted(missing)}")
    table = table.copy()
    table["is_default"] = table["is_default"].astype(str).str.lower() == "true"
    floor = float(meta.get("parameters", {}).get("error_floor", 1e-9))
    slop = float(meta["parameters"]["slop"])
    scenes = list(dict.fromkeys(table["scene"]))
    timed = table[table["role"].isin(["baseline", "sweep"])]

    fig, axes = plt.subplots(len(scenes), len(MEASURES), squeeze=False,
                             figsize=(style.WIDTH, 2.6 * len(scenes) + 0.6))
    numbers = {"error_floor": floor, "scenes": {}}
    fronts = []
    for r, scene in enumerate(scenes):
        rows = timed[timed["scene"] == scene]
        ref = table[(table["scene"] == scene) & (table["role"] == "resolution")]
        scene_numbers = numbers["scenes"][scene] = {
            "bodies": int(rows["bodies"].iloc[0]), "baseline": {}, "reference_resolution": {},
            "match_limit": {}, "systems": {}}
        for engine, off in OFF.items():
            base = rows[(rows["system"] == off) & (rows["role"] == "baseline")]
            if base.empty:
                continue
            b = base.iloc[0]
            scene_numbers["baseline"][off] = {
                "pose_error_max_m": b["pose_error_max_m"], "pose_error_mean_m":
                    b["pose_error_mean_m"], "angle_error_max_rad": b["angle_error_max_rad"],
                "penetration_max_m": b["penetration_max_m"],
                "penetration_final_m": b["penetration_final_m"], "wall_s": b["wall_s_median"]}
            res = ref[ref["system"] == off]
            resolution = res.iloc[0]["pose_error_max_m"] if not res.empty else math.nan
            if not res.empty:
                scene_numbers["reference_resolution"][off] = {
                    "dt_s": res.iloc[0]["dt_s"], "pose_error_max_m": resolution,
                    "penetration_max_m": res.iloc[0]["penetration_max_m"]}
            scene_numbers["match_limit"][off] = {
                "pose": b["pose_error_max_m"] + resolution,
                "penetration": b["penetration_final_m"] + PENETRATION_MARGIN * slop}
        # settings under which no body ever froze do the baseline's work: their speed-up should
        # be ~1, so its spread is the timing noise of this run (the machine is shared)
        idle = rows[(rows["role"] == "sweep") & (rows["awake_fraction"] >= 1.0)]
        scene_numbers["never_froze_speedups"] = {
            f"{p['system']} {_setting(p)}": {"speedup": p["speedup"],
                                             "speedup_min": p["speedup_min"]}
            for _, p in idle.iterrows()}
        for system in FREEZING:
            pts = rows[rows["system"] == system]
            if pts.empty:
                continue
            engine = pts["engine"].iloc[0]
            base = scene_numbers["baseline"].get(OFF[engine], {})
            entry = scene_numbers["systems"][system] = {}
            default = pts[pts["is_default"]]
            if not default.empty:
                d = default.iloc[0]        # every parameter at its default: the same run
                entry["default"] = {"speedup": d["speedup"], "pose_error_max_m":
                                    d["pose_error_max_m"], "pose_error_mean_m":
                                    d["pose_error_mean_m"], "penetration_max_m":
                                    d["penetration_max_m"], "penetration_final_m":
                                    d["penetration_final_m"], "n_awake_final":
                                    int(d["n_awake_final"]), "awake_fraction":
                                    d["awake_fraction"]}
            fastest = pts.loc[pts["speedup"].idxmax()]
            entry["fastest"] = {"setting": _setting(fastest), "speedup": fastest["speedup"],
                                "pose_error_max_m": fastest["pose_error_max_m"],
                                "penetration_final_m": fastest["penetration_final_m"],
                                "penetration_max_m": fastest["penetration_max_m"]}
            # matching in one measure alone can be degenerate (bodies asleep in mid-air overlap
            # nothing), so a setting matches when it matches in every measure
            limits = scene_numbers["match_limit"][OFF[engine]]
            ok = pts[pts["awake_fraction"] < 1.0]            # settings that froze something
            for column, _, short in MEASURES:
                ok = ok[ok[column] <= limits[short]]
                entry[f"worst_{short}_m"] = float(pts[column].max())
            if ok.empty:
                entry["best_speedup_matching_baseline"] = math.nan
                entry["best_setting_matching_baseline"] = "none"
            else:
                best = ok.loc[ok["speedup"].idxmax()]
                entry["best_speedup_matching_baseline"] = best["speedup"]
                entry["best_setting_matching_baseline"] = _setting(best)
                entry["best_matching_pose_error_max_m"] = best["pose_error_max_m"]
                entry["best_matching_penetration_final_m"] = best["penetration_final_m"]

        for c, (column, ylabel, short) in enumerate(MEASURES):
            ax = axes[r, c]
            values = rows[column][np.isfinite(rows[column])]
            above = values[values > floor]
            bottom = max(floor, float(above.min()) / 3) if len(above) else floor
            for engine, off in OFF.items():
                base = rows[(rows["system"] == off) & (rows["role"] == "baseline")]
                if base.empty:
                    continue
                st = style.system_style(off)
                y = max(float(base[column].iloc[0]), bottom)
                ax.axhline(y, color=st["color"], lw=0.7, ls=(0, (4, 3)), alpha=0.6, zorder=1)
                ax.plot([1.0], [y], marker="*", ms=9, color=st["color"], mec="black", mew=0.5,
                        ls="none", zorder=5)
            for system in FREEZING:
                pts = rows[rows["system"] == system]
                if pts.empty:
                    continue
                st = style.system_style(system)
                zero = pts[column] <= floor
                ax.scatter(pts.loc[~zero, "speedup"], pts.loc[~zero, column], marker=st["marker"],
                           s=14, color=st["color"], alpha=0.75, zorder=3, linewidths=0)
                ax.scatter(pts.loc[zero, "speedup"], np.full(int(zero.sum()), bottom),
                           marker=st["marker"], s=14, facecolor="none", edgecolor=st["color"],
                           linewidths=0.8, zorder=3)
                d = pts[pts["is_default"]]
                ax.scatter(d["speedup"], d[column].clip(lower=bottom), marker=st["marker"], s=30,
                           facecolor=st["color"], edgecolor="black", linewidths=0.8, zorder=4)
                front = pareto(pts, column)
                ax.step(front["speedup"], front[column].clip(lower=bottom), where="pre",
                        color=st["color"], ls=st["linestyle"], lw=1.0, zorder=2)
                for _, p in front.iterrows():
                    fronts.append({"scene": scene, "measure": short, "system": system,
                                   "parameter": p["parameter"], "value": p["value"],
                                   "unit": p["unit"], "is_default": bool(p["is_default"]),
                                   "speedup": p["speedup"], "error_m": p[column]})
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.xaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
            ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _: f"{x:g}"))
            ax.xaxis.set_minor_formatter(NullFormatter())
            lo, hi = ax.get_ylim()
            if hi / lo < 10:           # at least a decade, so that log ticks are labelled
                mid = math.sqrt(lo * hi)
                ax.set_ylim(mid / 10 ** 0.5, mid * 10 ** 0.5)
            ax.set_ylabel(ylabel)
            ax.set_title(f"{scene}, {int(rows['bodies'].iloc[0])} bodies: {short}")
            if r == len(scenes) - 1:
                ax.set_xlabel("speed-up over sleeping off, same engine and dt")

    handles = [Line2D([], [], marker=style.system_style(s)["marker"],
                      color=style.system_style(s)["color"], ls=style.system_style(s)["linestyle"],
                      label=s) for s in FREEZING]
    handles += [Line2D([], [], marker="*", ms=9, color=style.system_style(off)["color"],
                       mec="black", mew=0.5, ls=(0, (4, 3)), label=f"{off} at dt (baseline)")
                for off in OFF.values()]
    handles.append(Line2D([], [], marker="o", color="white", mfc="lightgray", mec="black",
                          label="default setting"))
    handles.append(Line2D([], [], marker="o", color="white", mfc="none", mec="gray",
                          label=f"error <= {floor:g} (at panel floor)"))
    fig.legend(handles=handles, loc="lower center", ncol=4, frameon=False,
               bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=(0, 0.09, 1, 1))
    style.save_figure(fig, NAME)
    style.write_table(pd.DataFrame(fronts, columns=["scene", "measure", "system", "parameter",
                                                    "value", "unit", "is_default", "speedup",
                                                    "error_m"]), NAME)
    return numbers


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
