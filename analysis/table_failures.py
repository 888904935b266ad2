"""Table 8 "table_failures": the failure catalogue, as the paper shows it.

Writes
- paper/generated/table_failures.csv: one row per scenario, the truth's outcome, then one cell
  per system: "ok" (with the pose error against the same engine with sleeping off, m, for the
  freezing systems), "WRONG (<outcome>), <error> m" when the outcome is wrong and freezing changed
  it, "wrong as off (<outcome>)" when the engine gets it wrong with sleeping off too (the
  engine's failure, not freezing's);
- paper/generated/table_failures_speedup.csv: the speed-up of every system on every scenario
  (wall time of the same engine with sleeping off / the system's, whole run);
- paper/figures/table_failures.svg: the same catalogue as a grid (green right, red wrong by
  freezing, grey wrong as the engine itself), each cell labelled with its outcome and speed-up;
- the numbers the text quotes (failure counts per system, which scenarios break which system,
  speed-ups, whether each danger met frozen bodies; and sim's without its presolve of the start
  pose, which no peer has: ``without_presolve``).
"""

import matplotlib.pyplot as plt
from matplotlib.colors import ListedColormap
import numpy as np

from analysis import style
from study import systems

NAME = "table_failures"
OK, WRONG_FREEZING, WRONG_ENGINE = 0, 1, 2
CELL_COLORS = ("#cfe8c9", "#e9a3a0", "#d4d4d4")  # right, wrong by freezing, wrong as the engine
REFERENCES = tuple(systems.OFF.values())  # each engine with nothing frozen
#: the dangers of motion too slow to see (a body tipping from an unstable balance, sliding or
#: creeping slowly), where a rest rule of velocities alone freezes what still moves; each of the
#: first three with its twin of other geometry (study.scenarios)
SLOW_CASES = (
    "unstable_equilibrium",
    "unstable_ledge",
    "slow_sliding",
    "slow_glide",
    "slope_creep",
    "slope_creep_plank",
)


def _bool(series):
    """CSV booleans read back as bool (or as the strings "True"/"False" after a NaN)."""
    return series.map(lambda v: v if isinstance(v, (bool, np.bool_)) else str(v) == "True")


def _check(table):
    needed = {
        "scenario",
        "system",
        "reference",
        "truth",
        "expected",
        "truth_is_expected",
        "outcome",
        "right",
        "changed",
        "engine_right",
        "pose_error_m",
        "pose_error_rad",
        "speedup",
        "asleep_at_event",
        "key_ever_frozen",
        "frozen_fraction",
    }
    missing = needed - set(table.columns)
    if missing:
        raise ValueError(
            f"{NAME}: results table lacks column(s) {', '.join(sorted(missing))}: "
            f"rerun `python -m experiments.{NAME}`"
        )
    table = table.copy()
    for col in ("truth_is_expected", "right", "changed", "engine_right"):
        table[col] = _bool(table[col])
    return table


def kind(row):
    """OK, WRONG_FREEZING (wrong, and freezing changed the outcome) or WRONG_ENGINE."""
    if row.right:
        return OK
    return WRONG_FREEZING if row.changed else WRONG_ENGINE


def error(metres):
    """A pose error as the table prints it: 2 significant figures in m, "<0.1 mm" below that
    (errors of 1e-17 m are round-off, and printing them would suggest a precision there is not)."""
    return "<0.1 mm" if metres < 1e-4 else f"{style.fmt(metres, 2)} m"


def cell(row):
    """The paper's cell for one scenario x system."""
    k = kind(row)
    reference = row.system == row.reference
    if k == OK:
        return "ok" if reference else f"ok, {error(row.pose_error_m)}"
    if k == WRONG_ENGINE:
        return f"wrong as off ({row.outcome})" if not reference else f"WRONG ({row.outcome})"
    return f"WRONG ({row.outcome}), {error(row.pose_error_m)}"


def _grid(table, scenarios, systems, value):
    return (
        table.assign(_v=table.apply(value, axis=1))
        .pivot(index="scenario", columns="system", values="_v")
        .reindex(index=scenarios, columns=systems)
    )


def figure(table, scenarios, systems):
    kinds = _grid(table, scenarios, systems, kind).to_numpy(dtype=float)
    outcomes = _grid(table, scenarios, systems, lambda r: r.outcome)
    speedups = _grid(table, scenarios, systems, lambda r: r.speedup)
    truths = table.groupby("scenario")["truth"].first().reindex(scenarios)
    fig, ax = plt.subplots(figsize=(style.WIDTH, 0.36 * len(scenarios) + 1.3))
    ax.imshow(kinds, cmap=ListedColormap(CELL_COLORS), vmin=0, vmax=2, aspect="auto")
    for i, sc in enumerate(scenarios):
        for j, system in enumerate(systems):
            label = outcomes.loc[sc, system]
            text = "ok" if kinds[i, j] == OK else label
            if system not in REFERENCES:
                text += f"\n×{speedups.loc[sc, system]:.2g}"
            ax.text(j, i, text, ha="center", va="center", fontsize=5.2, linespacing=1.0)
    ax.set_xticks(range(len(systems)), systems, rotation=30, ha="right")
    ax.set_yticks(
        range(len(scenarios)),
        [f"{sc.replace('_', ' ')}\n(truth: {truths[sc]})" for sc in scenarios],
        fontsize=6,
    )
    ax.tick_params(length=0)
    ax.grid(False)
    ax.set_xticks(np.arange(len(systems) + 1) - 0.5, minor=True)
    ax.set_yticks(np.arange(len(scenarios) + 1) - 0.5, minor=True)
    ax.grid(which="minor", color="white", linewidth=1.5)
    ax.tick_params(which="minor", length=0)
    for spine in ax.spines.values():
        spine.set_visible(False)
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in CELL_COLORS]
    ax.legend(
        handles,
        ("right", "wrong: freezing changed the outcome", "wrong as the engine with sleeping off"),
        loc="lower center",
        bbox_to_anchor=(0.5, 1.0),
        ncol=3,
        frameon=False,
        fontsize=6,
    )
    ax.set_title(
        "outcome per scenario and system (×: speed-up over the same engine, sleeping off)",
        fontsize=7,
        pad=16,
    )
    style.save_figure(fig, NAME)


def draw(table, meta):
    table = _check(table)
    scenarios = list(dict.fromkeys(table["scenario"]))
    systems = list(dict.fromkeys(table["system"]))
    freezing = [s for s in systems if s not in REFERENCES]

    paper_table = _grid(table, scenarios, systems, cell)
    paper_table.insert(0, "truth", table.groupby("scenario")["truth"].first().reindex(scenarios))
    style.write_table(paper_table.reset_index(), NAME)
    speed = _grid(table, scenarios, freezing, lambda r: round(float(r.speedup), 2))
    style.write_table(speed.reset_index(), f"{NAME}_speedup")
    figure(table, scenarios, systems)

    wrong = table[~table["right"]]
    by_freezing = wrong[wrong["changed"]]
    engine_wrong = table[(table["system"] == table["reference"]) & ~table["right"]]
    events = table[table["asleep_at_event"].notna()]
    numbers = {
        "scenarios": scenarios,
        "n_scenarios": len(scenarios),
        "systems": systems,
        "truth_all_expected": bool(table["truth_is_expected"].all()),
        "truth_mismatches": sorted(set(table.loc[~table["truth_is_expected"], "scenario"])),
        "failures": {s: int((wrong["system"] == s).sum()) for s in systems},
        "failures_by_freezing": {s: int((by_freezing["system"] == s).sum()) for s in freezing},
        "broken_by": {
            s: list(by_freezing.loc[by_freezing["system"] == s, "scenario"]) for s in freezing
        },
        "slow_cases": [sc for sc in SLOW_CASES if sc in scenarios],
        "slow_broken_by": {
            s: [
                sc
                for sc in by_freezing.loc[by_freezing["system"] == s, "scenario"]
                if sc in SLOW_CASES
            ]
            for s in freezing
        },
        "breaks": {
            sc: list(by_freezing.loc[by_freezing["scenario"] == sc, "system"]) for sc in scenarios
        },
        "wrong_outcome": {f"{r.scenario}/{r.system}": r.outcome for r in wrong.itertuples()},
        "engine_failures": {
            f"{r.scenario}/{r.system}": r.outcome for r in engine_wrong.itertuples()
        },
        "scenarios_all_right": [
            sc for sc in scenarios if table.loc[table["scenario"] == sc, "right"].all()
        ],
        "max_pose_error_m": {
            s: float(table.loc[table["system"] == s, "pose_error_m"].max()) for s in freezing
        },
        "max_failure_pose_error_m": {
            s: (
                float(by_freezing.loc[by_freezing["system"] == s, "pose_error_m"].max())
                if (by_freezing["system"] == s).any()
                else 0.0
            )
            for s in freezing
        },
        "speedup_median": {
            s: float(table.loc[table["system"] == s, "speedup"].median()) for s in freezing
        },
        "speedup_min": {
            s: float(table.loc[table["system"] == s, "speedup"].min()) for s in freezing
        },
        "speedup_max": {
            s: float(table.loc[table["system"] == s, "speedup"].max()) for s in freezing
        },
        # the same from the fastest repeats (ratio of minima): the check against a busy machine
        "speedup_of_minima_median": {
            s: float(table.loc[table["system"] == s, "speedup_min"].median()) for s in freezing
        }
        if "speedup_min" in table
        else {},
        # did every scheduled danger meet frozen bodies? (fraction of key bodies frozen just
        # before the projectile arrived; the smallest over the event scenarios)
        "asleep_at_event_min": {
            s: float(events.loc[events["system"] == s, "asleep_at_event"].min()) for s in freezing
        }
        if len(events)
        else {},
        "never_froze_key": {
            s: list(table.loc[(table["system"] == s) & (table["key_ever_frozen"] == 0), "scenario"])
            for s in freezing
        },
        "repeats": int(table["repeats"].iloc[0]) if "repeats" in table else None,
        "without_presolve": _without_presolve(table, freezing),
    }
    return numbers


def _without_presolve(table, freezing):
    """sim's systems run again without the presolve (experiments.table_failures' no-presolve
    columns): per sim freezing system the outcomes freezing changed, wrongly, and which; and
    every (scenario, sim system) whose outcome the presolve changes. None for results without
    the columns."""
    if "outcome_no_presolve" not in table:
        return None
    sim = table[table["outcome_no_presolve"].notna()].copy()
    for col in ("changed_no_presolve", "right_no_presolve"):
        sim[col] = _bool(sim[col])
    broken = sim[sim["changed_no_presolve"] & ~sim["right_no_presolve"]]
    sim_freezing = [s for s in freezing if s in set(sim["system"])]
    return {
        "failures_by_freezing": {s: int((broken["system"] == s).sum()) for s in sim_freezing},
        "broken_by": {s: list(broken.loc[broken["system"] == s, "scenario"]) for s in sim_freezing},
        "outcome_changes": [
            {
                "scenario": r.scenario,
                "system": r.system,
                "with": r.outcome,
                "without": r.outcome_no_presolve,
            }
            for r in sim.itertuples()
            if r.outcome != r.outcome_no_presolve
        ],
    }


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
