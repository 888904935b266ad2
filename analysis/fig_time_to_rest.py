"""Figure 6 "fig_time_to_rest": steps until every body of a scene is frozen/asleep, per system.

Horizontal bars, one group per scene, one bar per freezing system, log scale in steps (top axis in
seconds at dt 1/60 s). A run that did not freeze the whole scene within the cap is drawn hatched up
to the cap and labelled "never" with the number of bodies still awake; a run whose freeze did not
hold (bodies awake again 1 s later) is marked with a red cross.

paper/generated/fig_time_to_rest.csv: scene x system, steps (or "never (k awake)"). The numbers:
per system, the steps for every scene, how many scenes it never froze (and which), the median
steps over the scenes it did freeze; the cap; the piles' larger seed sample (``_seed_sample``).
paper/generated/fig_time_to_rest_presolve.csv: the scenes placed at rest, each sim system with
and without its presolve (an advantage no peer has, reported apart) beside the peers;
``without_presolve`` in the numbers.
paper/generated/fig_time_to_rest_reference.csv: over the piles, each freezing system's median
steps until all froze beside how long its own reference (the same engine with nothing frozen)
still moved them at each reference speed (``_reference_table``); ``reference`` in the numbers.
"""

import math

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.ticker import FuncFormatter

from analysis import style
from study import systems

NAME = "fig_time_to_rest"
#: the table of the placed scenes with and without sim's presolve (``_presolve_table``)
PRESOLVE_TABLE = NAME + "_presolve"
#: the table of the piles' time to rest against each engine's own reference (``_reference_table``)
REFERENCE_TABLE = NAME + "_reference"
FREEZING = systems.FREEZING


def runs_of(table, part="time_to_freeze"):
    """One row per (scene, system) of ``part``: steps (NaN = never), never, awake at the end,
    awake 1 s after, cap, bodies; scenes in the order of the table."""
    t = table[table["part"] == part] if "part" in table else table
    if t.empty:
        raise ValueError(f"{NAME}: no {part} rows in the results table")
    wide = t.pivot_table(
        index=["scene", "system"], columns="metric", values="value", aggfunc="first", dropna=False
    )
    need = {"steps_to_all_frozen", "n_awake_at_end", "n_awake_1s_after", "cap_steps"}
    if need - set(wide.columns):
        raise ValueError(f"{NAME}: results table lacks metrics {sorted(need - set(wide.columns))}")
    flags = t.drop_duplicates(["scene", "system"]).set_index(["scene", "system"])
    wide["never"] = flags["flag"].astype(object).fillna("").eq("never").reindex(wide.index)
    wide["bodies"] = flags["bodies"].reindex(wide.index)
    wide = wide.reset_index()
    order = {s: i for i, s in enumerate(dict.fromkeys(t["scene"]))}
    wide["scene_order"] = wide["scene"].map(order)
    return wide.sort_values("scene_order")


def draw(table, meta):
    runs = runs_of(table)
    scenes = list(dict.fromkeys(runs["scene"]))
    systems = [s for s in FREEZING if s in set(runs["system"])]
    cap = float(runs["cap_steps"].max())
    dt = float(meta.get("parameters", {}).get("dt", 1 / 60))
    bar_h = 0.8 / len(systems)
    fig, ax = plt.subplots(figsize=(style.WIDTH, 0.42 * len(scenes) + 1.2))
    # "never" labels already drawn per scene: adjacent bars are closer than the text is tall, so
    # every other label goes inside the plot, left of the cap line, on a white ground
    labelled = dict.fromkeys(scenes, 0)
    for k, system in enumerate(systems):
        st = style.system_style(system)
        for i, scene in enumerate(scenes):
            r = runs[(runs["scene"] == scene) & (runs["system"] == system)]
            if r.empty:
                continue
            r = r.iloc[0]
            y = i + (k - (len(systems) - 1) / 2) * bar_h
            if r["never"]:
                ax.barh(
                    y,
                    cap,
                    height=bar_h,
                    color="white",
                    edgecolor=st["color"],
                    hatch="////",
                    linewidth=0.6,
                )
                inside = labelled[scene] % 2 == 1
                labelled[scene] += 1
                ground = {"facecolor": "white", "edgecolor": "none", "pad": 0.3}
                ax.text(
                    cap / 1.05 if inside else cap * 1.05,
                    y,
                    f"never ({int(r['n_awake_at_end'])} awake)",
                    va="center",
                    ha="right" if inside else "left",
                    fontsize=5,
                    color=st["color"],
                    bbox=ground if inside else None,
                )
                continue
            steps = float(r["steps_to_all_frozen"])
            ax.barh(y, steps, height=bar_h, color=st["color"], edgecolor="none")
            # above the bars, on a white patch: the next system's bar (a hatched "never" one
            # spans the axis) would otherwise cross the number
            ax.text(
                steps * 1.05,
                y,
                f"{steps:.0f}",
                va="center",
                fontsize=5,
                color="0.25",
                zorder=4,
                bbox={"facecolor": "white", "edgecolor": "none", "pad": 0.2, "alpha": 0.85},
            )
            if r["n_awake_1s_after"] > 0:
                ax.plot(steps, y, marker="x", color="red", markersize=4, linestyle="none")
    ax.set_xscale("log")
    ax.set_xlim(0.8, cap * 4)
    ax.axvline(cap, color="0.4", linewidth=0.8, linestyle=":")
    ax.text(cap * 1.05, -0.45, f"cap: {cap * dt:g} s", ha="left", va="top", fontsize=6, color="0.3")
    ax.set_yticks(range(len(scenes)), scenes)
    ax.set_ylim(len(scenes) - 0.5, -0.5)  # first scene on top
    ax.grid(axis="y", visible=False)
    step = f"1/{round(1 / dt)}" if abs(1 / dt - round(1 / dt)) < 1e-9 else f"{dt:.4g}"
    ax.set_xlabel(f"steps until every body is frozen/asleep (dt = {step} s)")
    top = ax.secondary_xaxis("top", functions=(lambda s: s * dt, lambda t: t / dt))
    top.set_xlabel("simulated time (s)")
    plain = FuncFormatter(lambda v, _: f"{v:g}")
    ax.xaxis.set_major_formatter(plain)
    top.xaxis.set_major_formatter(plain)
    handles = [Patch(color=style.system_style(s)["color"], label=s) for s in systems]
    handles += [
        Patch(facecolor="white", edgecolor="0.3", hatch="////", label="never within the cap"),
        Line2D([], [], marker="x", color="red", linestyle="none", label="awake again 1 s later"),
    ]
    ax.legend(
        handles=handles, loc="lower center", bbox_to_anchor=(0.5, 1.12), ncol=4, frameon=False
    )
    fig.tight_layout()
    style.save_figure(fig, NAME)

    style.write_table(_paper_table(runs, scenes, systems), NAME)
    without = _without_presolve(table)
    if without is not None:
        style.write_table(_presolve_table(runs, without, systems), PRESOLVE_TABLE)
    numbers = _numbers(runs, scenes, systems, cap, dt)
    reference = _reference(table)
    if reference is not None:
        style.write_table(_reference_table(numbers, reference, systems), REFERENCE_TABLE)
    return {
        **numbers,
        "certificate": _certificate(table),
        "reference": reference,
        "seed_sample": _seed_sample(table),
        "without_presolve": None if without is None else _presolve_numbers(without),
    }


def _without_presolve(table):
    """The runs of part "without_presolve" (``runs_of``), or None when the table has none."""
    if "part" not in table or not (table["part"] == "without_presolve").any():
        return None
    return runs_of(table, "without_presolve")


def _presolve_table(runs, without, shown):
    """Scenes placed at rest x systems: each sim system with its presolve (as in the figure) and
    then without it, then the peers; cells as the figure's table's."""
    both = pd.concat([runs[runs["scene"].isin(set(without["scene"]))], without])
    columns = []
    for system in shown:
        columns.append(system)
        variant = system + systems.NO_PRESOLVE
        if variant in set(without["system"]):
            columns.append(variant)
    return _paper_table(both, list(dict.fromkeys(without["scene"])), columns)


def _presolve_numbers(without):
    """Per no-presolve system: steps per scene, the scenes never frozen, per scene family the
    median steps (``_per_system``)."""
    return {system: _per_system(s) for system, s in without.groupby("system", sort=False)}


def _per_system(s):
    """One system's runs (rows of ``runs_of``): steps per scene (None: never), the scenes it never
    froze, and per scene family (drop seeds, stacks...) the median steps, a run that never froze
    counting as beyond the cap (an order statistic: exact unless it is one of them, then None),
    and how many never froze."""
    families = s.groupby(s["scene"].str.split("(").str[0], sort=False)
    return {
        "steps": {
            r.scene: (None if r.never else int(r.steps_to_all_frozen)) for r in s.itertuples()
        },
        "never": [r.scene for r in s.itertuples() if r.never],
        "family_median_steps": {
            family: median_beyond_cap(g["steps_to_all_frozen"], g["never"])
            for family, g in families
        },
        "family_never": {family: int(g["never"].sum()) for family, g in families},
    }


def _seed_sample(table, first=5):
    """The piles' larger seed sample (experiments.fig_time_to_rest, part "seed_sample"): per
    system the median steps to all frozen over every seed and over the ``first`` seeds (the
    figure's piles), each with a pile that never froze counted as beyond the cap
    (``median_beyond_cap``: None when the median is such a pile), and how many never froze; and
    the ratio of sim-extended's median to sim-sleep's over the whole sample (None if either is).
    None when the table has no such rows."""
    if "part" not in table or not (table["part"] == "seed_sample").any():
        return None
    runs = runs_of(table, "seed_sample")
    runs = runs.assign(seed=runs["scene"].str.extract(r"seed=(\d+)", expand=False).astype(int))
    out = {"seeds": int(runs["seed"].nunique()), "first": first, "scene": None, "systems": {}}
    out["scene"] = str(runs["scene"].iloc[0]).split(",")[0] + ")"
    for system, s in runs.groupby("system", sort=False):
        head = s[s["seed"] < first]
        out["systems"][system] = {
            "median_steps": median_beyond_cap(s["steps_to_all_frozen"], s["never"]),
            "median_steps_first": median_beyond_cap(head["steps_to_all_frozen"], head["never"]),
            "never": int(s["never"].sum()),
        }
    medians = {k: v["median_steps"] for k, v in out["systems"].items()}
    ext, slp = medians.get("sim-extended"), medians.get("sim-sleep")
    out["extended_over_sleep"] = ext / slp if ext is not None and slp else None
    return out


def _reference(table):
    """How long each scene moves with freezing off (experiments.fig_time_to_rest,
    reference_motion), per reference system (sim-off, each peer with its sleeping off):
    ``reference_of`` each. None when the table has no such rows."""
    if "part" not in table or not (table["part"] == "reference").any():
        return None
    t = table[table["part"] == "reference"]
    return {system: reference_of(s) for system, s in t.groupby("system", sort=False)}


def _reference_table(numbers, reference, shown):
    """Over the piles (drop seeds): per freezing system, the median steps until all froze
    (``family_median_steps``; "never" when that median is a pile that never froze), its
    reference, and how long that reference still moved a body at each speed (median steps; "at
    cap" when a pile still moved then at the cap). Empty when the runs have no piles."""
    rows = []
    for system in shown:
        ref = reference.get(systems.REFERENCE[system])
        if (
            ref is None
            or ref["pile_median_steps"] is None
            or "drop" not in numbers[system].get("family_median_steps", {})
        ):
            continue
        frozen = numbers[system]["family_median_steps"]["drop"]
        row = {
            "system": system,
            "all frozen (median step)": "never" if frozen is None else f"{frozen:g}",
            "reference": systems.REFERENCE[system],
        }
        for speed, step in ref["pile_median_steps"].items():
            label = (
                f"{float(speed) * 100:g} cm/s"
                if float(speed) >= 0.01
                else f"{float(speed) * 1000:g} mm/s"
            )
            row[f"moving at {label} until"] = "at cap" if step is None else f"{step:g}"
        rows.append(row)
    return pd.DataFrame(rows)


def reference_of(t):
    """One reference system's rows: per scene and speed (m/s, as a string key) the last step at
    which a body moved at least that fast (0 never), the speeds at which it still moved at the
    cap, and over the piles (drop seeds) the median of those steps per speed, a pile still moving
    at the cap counted as beyond it (``median_beyond_cap``: None only when the median is such a
    pile; until 2026-12-07 any one such pile made it None, and pybullet's piles, one of five at
    the cap, were said to move "past the cap" where their median was step 1799)."""
    speed_of = {m: m[len("moving_until_") :] for m in t["metric"].unique()}
    steps = {}
    at_cap = {}
    for r in t.itertuples():
        steps.setdefault(r.scene, {})[speed_of[r.metric]] = int(r.value)
        if r.flag == "at cap":
            at_cap.setdefault(r.scene, []).append(speed_of[r.metric])
    piles = [scene for scene in steps if str(scene).startswith("drop")]
    pile_median = (
        {
            speed: median_beyond_cap(
                [steps[scene][speed] for scene in piles],
                [speed in at_cap.get(scene, []) for scene in piles],
            )
            for speed in dict.fromkeys(speed_of.values())
        }
        if piles
        else None
    )
    return {"steps": steps, "at_cap": at_cap, "pile_median_steps": pile_median}


def _certificate(table):
    """extended's rest certificate per scene (experiments.fig_time_to_rest.certificate_cost):
    certificates tried, steps that tried any, steps run, and us of the rest-test stage per
    certificate (an upper bound on one certificate's cost); plus the median of that over scenes."""
    if "part" not in table or not (table["part"] == "certificate").any():
        return None
    t = table[table["part"] == "certificate"]
    wide = t.pivot_table(index="scene", columns="metric", values="value", aggfunc="first")
    per_scene = {
        scene: {
            "certificates": int(r.certificates),
            "steps_certifying": int(r.steps_certifying),
            "steps_run": int(r.steps_run),
            "us_per_certificate": (
                None
                if math.isnan(r.freeze_after_per_certificate)
                else float(r.freeze_after_per_certificate)
            ),
        }
        for scene, r in wide.iterrows()
    }
    costs = [
        v["us_per_certificate"] for v in per_scene.values() if v["us_per_certificate"] is not None
    ]
    return {
        "scenes": per_scene,
        "median_us_per_certificate": float(np.median(costs)) if costs else None,
        "max_us_per_certificate": float(np.max(costs)) if costs else None,
        "piles_waiting": _piles_waiting(wide),
    }


def _piles_waiting(wide):
    """What extended's dropped piles wait for once still (experiments.fig_time_to_rest,
    waiting_<reason>): per pile the step from which no body was moving and the awake body-steps
    after it by reason; over all piles each reason's body-steps and share of them."""
    reasons = [m[len("waiting_") :] for m in wide.columns if m.startswith("waiting_")]
    piles = wide[[str(scene).startswith("drop") for scene in wide.index]]
    if not reasons or piles.empty:
        return None
    per_pile = {
        scene: {
            "still_from_step": None if math.isnan(r.still_from_step) else int(r.still_from_step),
            "body_steps": {reason: int(r[f"waiting_{reason}"]) for reason in reasons},
        }
        for scene, r in piles.iterrows()
    }
    totals = {reason: int(piles[f"waiting_{reason}"].sum()) for reason in reasons}
    everything = sum(totals.values())
    return {
        "piles": per_pile,
        "body_steps": totals,
        "share": {r: (n / everything if everything else None) for r, n in totals.items()},
    }


def median_beyond_cap(steps, never):
    """The median of ``steps`` with every run flagged in ``never`` taken as longer than any
    that froze (it did not freeze within the cap); None when the median is such a run, or when
    two middle values are averaged and one is. Order statistics need no value for them."""
    values = sorted(float(v) for v, n in zip(steps, never) if not n)
    n = len(values) + int(sum(bool(x) for x in never))
    if n == 0:
        return None
    lo, hi = (n - 1) // 2, n // 2  # the middle position(s), 0-based, in order
    if hi >= len(values):
        return None
    return 0.5 * (values[lo] + values[hi])


def _cell(r):
    if r["never"]:
        return f"never ({int(r['n_awake_at_end'])} awake)"
    cell = f"{r['steps_to_all_frozen']:.0f}"
    if r["n_awake_1s_after"] > 0:
        cell += f" (+{int(r['n_awake_1s_after'])} woke)"
    return cell


def _paper_table(runs, scenes, systems):
    rows = []
    for scene in scenes:
        s = runs[runs["scene"] == scene]
        row = {"scene": scene, "bodies": int(s["bodies"].iloc[0])}
        for system in systems:
            r = s[s["system"] == system]
            row[system] = _cell(r.iloc[0]) if len(r) else "-"
        rows.append(row)
    return pd.DataFrame(rows)


def _numbers(runs, scenes, shown, cap, dt):
    out = {"cap_steps": int(cap), "cap_s": cap * dt, "dt": dt, "scenes": scenes}
    for system in shown:
        s = runs[runs["system"] == system]
        froze = s[~s["never"]]
        out[system] = {
            **_per_system(s),
            "reference": systems.REFERENCE[system],  # the same engine with nothing frozen
            "n_never": int(s["never"].sum()),
            "awake_at_cap": {r.scene: int(r.n_awake_at_end) for r in s.itertuples() if r.never},
            "median_steps_when_frozen": (
                float(np.median(froze["steps_to_all_frozen"])) if len(froze) else math.nan
            ),
            "did_not_hold": [r.scene for r in s.itertuples() if r.n_awake_1s_after > 0],
        }
    fastest = {}
    for scene in scenes:
        s = runs[(runs["scene"] == scene) & ~runs["never"]]
        if len(s):
            best = s["steps_to_all_frozen"].min()
            fastest[scene] = sorted(s.loc[s["steps_to_all_frozen"] == best, "system"])
    out["fastest"] = fastest
    return out


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
