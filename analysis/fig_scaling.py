"""Figure 5 "fig_scaling": how step cost grows with awake and frozen bodies.

One row per system: left, ms/step against N_awake at each fixed N_frozen; right, ms/step against
N_frozen at each fixed N_awake. Dots are measured medians, solid lines the fit ms = a N_awake +
b N_frozen + c, dashed grey lines the ideal b = 0 (a frozen body costs nothing: flat in N_frozen).
Under sim-off nothing is frozen: N_frozen counts the resting row's bodies, which are solved.

paper/generated/fig_scaling.csv: per system, fitted to the median and to the fastest repeat of
each mix, a, b (ns per body-step, with standard errors), c (ms), b/a (with its standard error),
b/b_off (a frozen body against a solved resting one), R^2 and RMS residual. The numbers: the
same, in ms and ns (the fastest-repeat fit under "fastest_repeat").
"""

import math

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.lines import Line2D

from analysis import style

NAME = "fig_scaling"
NS_PER_MS = 1e6
ROW_NOTE = {
    "sim-off": "nothing frozen: the row is solved",
    "sim-extended": "row frozen",
    "sim-sleep": "row asleep",
    "pymunk-sleep": "row asleep",
    "box2d-sleep": "row asleep",
}


def fits_of(table, scene="fit"):
    """system -> {key: value} from the fit rows (scene "fit": medians, "fit_min": fastest
    repeats; metric "fit_<key>")."""
    rows = table[table["scene"] == scene]
    if rows.empty:
        raise ValueError(f"{NAME}: no {scene!r} rows in the results table")
    out = {}
    for r in rows.itertuples():
        out.setdefault(r.system, {})[r.metric[len("fit_") :]] = float(r.value)
    return out


def medians_of(table):
    t = table[~table["scene"].str.startswith("fit") & (table["metric"] == "ms_per_step_median")]
    if t.empty:
        raise ValueError(f"{NAME}: no ms_per_step_median rows in the results table")
    return t[["system", "n_awake", "n_frozen", "value", "flag"]].astype(
        {"n_awake": int, "n_frozen": int}
    )


def _fastest_flyer(table, prefix):
    """m/s: the largest ``fastest_flyer_speed`` of any mix of the systems named ``prefix``...
    (NaN in results from before the row existed)."""
    rows = (table["metric"] == "fastest_flyer_speed") & table["system"].str.startswith(prefix)
    speeds = table.loc[rows, "value"]
    return float(speeds.max()) if not speeds.empty else math.nan


def _shades(n, cmap="viridis"):
    return [plt.get_cmap(cmap)(x) for x in np.linspace(0.1, 0.8, n)]


def _ns(ms, digits=3):
    """A per-body cost given in ms, printed in ns: whole numbers from 100 ns up (1030, not
    1.03e+03)."""
    ns = ms * NS_PER_MS
    return f"{ns:.0f}" if math.isfinite(ns) and abs(ns) >= 100 else style.fmt(ns, digits)


def _pm(fit, key):
    """ "value ± standard error" of a per-body cost, in ns."""
    return f"{_ns(fit[key])} ± {_ns(fit[key + '_stderr'], 2)}"


def _label(fit):
    return (
        f"a = {_pm(fit, 'a')} ns, b = {_pm(fit, 'b')} ns, b/a = "
        f"{style.fmt(fit['b_over_a'])} ± {style.fmt(fit.get('b_over_a_stderr', math.nan), 2)}"
    )


def draw(table, meta):
    table = table.copy()
    table["flag"] = table["flag"].astype(object).fillna("")
    fits, fits_min, med = fits_of(table), fits_of(table, "fit_min"), medians_of(table)
    systems = [s for s in style.SYSTEM_STYLE if s in fits]
    awake_counts = sorted(med["n_awake"].unique())
    frozen_counts = sorted(med["n_frozen"].unique())
    fig, axes = plt.subplots(
        len(systems), 2, figsize=(style.WIDTH, 1.75 * len(systems) + 0.5), squeeze=False
    )
    for i, system in enumerate(systems):
        fit, m = fits[system], med[med["system"] == system]
        marker = style.system_style(system)["marker"]
        ax_aw, ax_fr = axes[i]
        x_aw = np.linspace(0, max(awake_counts), 50)
        for nf, color in zip(frozen_counts, _shades(len(frozen_counts))):
            p = m[m["n_frozen"] == nf].sort_values("n_awake")
            ax_aw.plot(p["n_awake"], p["value"], linestyle="none", marker=marker, color=color)
            ax_aw.plot(x_aw, fit["a"] * x_aw + fit["b"] * nf + fit["c"], color=color, linewidth=0.9)
        x_fr = np.linspace(0, max(frozen_counts), 50)
        for na, color in zip(awake_counts, _shades(len(awake_counts), "plasma")):
            p = m[m["n_awake"] == na].sort_values("n_frozen")
            ax_fr.plot(p["n_frozen"], p["value"], linestyle="none", marker=marker, color=color)
            ax_fr.plot(x_fr, fit["a"] * na + fit["b"] * x_fr + fit["c"], color=color, linewidth=0.9)
            ideal = fit["a"] * na + fit["c"]
            ax_fr.plot(x_fr, np.full_like(x_fr, ideal), color="0.55", linestyle="--", linewidth=0.8)
        bad = m[m["flag"] != ""]
        if len(bad):
            ax_fr.text(
                0.98,
                0.05,
                f"{len(bad)} mixes failed the awake/flight check",
                transform=ax_fr.transAxes,
                ha="right",
                fontsize=6,
                color="red",
            )
        ax_aw.set_title(f"{system}: {ROW_NOTE.get(system, '')}", loc="left", fontsize=7.5)
        ax_fr.set_title(_label(fit), loc="left", fontsize=7)
        ax_aw.set_ylabel("ms per step")
        ax_aw.set_xlim(0, 1.05 * max(awake_counts))
        ax_fr.set_xlim(0, 1.05 * max(frozen_counts))
        for ax in (ax_aw, ax_fr):
            ax.set_ylim(bottom=0)
    axes[-1, 0].set_xlabel("N_awake: bodies in flight (solved)")
    axes[-1, 1].set_xlabel("N_frozen: bodies in the resting row")
    fig.text(
        0.5,
        1.0,
        "fit: ms/step = a N_awake + b N_frozen + c  (a, b per body-step)",
        ha="center",
        va="bottom",
        fontsize=7.5,
    )
    frozen_handles = [
        Line2D([], [], color=c, marker="o", label=f"{nf}")
        for nf, c in zip(frozen_counts, _shades(len(frozen_counts)))
    ]
    awake_handles = [
        Line2D([], [], color=c, marker="o", label=f"{na}")
        for na, c in zip(awake_counts, _shades(len(awake_counts), "plasma"))
    ]
    ideal = Line2D([], [], color="0.55", linestyle="--", label="ideal b = 0")
    # legends under the columns they belong to, clear of the data
    axes[-1, 0].legend(
        handles=frozen_handles,
        title="lines at fixed N_frozen",
        loc="upper center",
        bbox_to_anchor=(0.5, -0.32),
        ncol=len(frozen_counts),
        fontsize=6,
        title_fontsize=6,
        frameon=False,
    )
    axes[-1, 1].legend(
        handles=awake_handles + [ideal],
        title="lines at fixed N_awake",
        loc="upper center",
        bbox_to_anchor=(0.5, -0.32),
        ncol=len(awake_counts) + 1,
        fontsize=6,
        title_fontsize=6,
        frameon=False,
    )
    fig.tight_layout(h_pad=2.0)  # clear of the x tick labels of the row above
    style.save_figure(fig, NAME)

    style.write_table(_paper_table(fits, fits_min, systems), NAME)
    numbers = {
        "model": "ms/step = a N_awake + b N_frozen + c",
        "systems": systems,
        "n_awake": [int(x) for x in awake_counts],
        "n_frozen": [int(x) for x in frozen_counts],
        "mixes_failing_checks": int((med["flag"] != "").sum()),
        # m/s: sim's fastest flyer in any mix at the end of its timing (they peak mid-timing;
        # the peers' worlds settle for longer before it, so theirs end a little faster)
        "fastest_flyer_speed_sim": _fastest_flyer(table, "sim-"),
    }
    for system in systems:
        numbers[system] = {
            **_fit_numbers(fits[system]),
            "fastest_repeat": _fit_numbers(fits_min[system]),
        }
    return numbers


def _fit_numbers(f):
    keys = (
        "a",
        "a_stderr",
        "b",
        "b_stderr",
        "c",
        "c_stderr",
        "b_over_a",
        "b_over_a_stderr",
        "r2",
        "rms_residual",
        "max_abs_residual",
        "b_over_b_off",
        "a_over_a_off",
        "points",
    )
    return {
        **{k: f[k] for k in keys if k in f},
        "a_ns": f["a"] * NS_PER_MS,
        "b_ns": f["b"] * NS_PER_MS,
        "a_stderr_ns": f["a_stderr"] * NS_PER_MS,
        "b_stderr_ns": f["b_stderr"] * NS_PER_MS,
    }


def _paper_table(fits, fits_min, systems):
    """One row per system and estimator (median of repeats: the figure's; fastest repeat)."""
    rows = []
    for system in systems:
        for estimator, f in (("median", fits[system]), ("fastest repeat", fits_min[system])):
            rows.append(
                {
                    "system": system,
                    "ms/step from": estimator,
                    "a (ns/body-step)": _pm(f, "a"),
                    "b (ns/body-step)": _pm(f, "b"),
                    "c (ms/step)": f"{style.fmt(f['c'])} ± {style.fmt(f['c_stderr'], 2)}",
                    "b/a": f"{style.fmt(f['b_over_a'])} ± {style.fmt(f.get('b_over_a_stderr'), 2)}",
                    "b/b(off)": style.fmt(f.get("b_over_b_off")),
                    "R^2": style.fmt(f["r2"], 4),
                    "RMS residual (ms)": style.fmt(f["rms_residual"], 2),
                }
            )
    return pd.DataFrame(rows)


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
