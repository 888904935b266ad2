"""Table "bench_freeze": the freezing targets (fully frozen step cost, cost per frozen body,
steps to freeze, overhead where nothing rests): paper/generated/bench_freeze.csv is the verdict
table; the numbers are what the paper quotes."""

import pandas as pd

from analysis import style

NAME = "bench_freeze"


def _value(table, part, metric, scene, system):
    v = table[
        (table["part"] == part)
        & (table["metric"] == metric)
        & (table["scene"] == scene)
        & (table["system"] == system)
    ]["value"]
    return float(v.iloc[0]) if len(v) else float("nan")


def draw(table, meta):
    targets = pd.DataFrame(meta["targets"])
    style.write_table(targets[["target", "measured", "goal", "verdict"]], NAME)
    frozen = table[(table["part"] == "frozen_cost") & (table["metric"] == "ms_per_step_median")]
    biggest = frozen.loc[frozen["bodies"] == frozen["bodies"].max()]
    scene = biggest["scene"].iloc[0]
    # each in-flight scene's worst phase (study/in_flight.py): the target is judged on it
    flight = table[
        (table["part"] == "in_flight_overhead") & (table["metric"] == "ratio_to_off_worst")
    ]
    fits = meta["fits"]
    return {
        "frozen_scene": scene,
        "frozen_ms": {r.system: r.value for r in biggest.itertuples()},
        "b_over_a": fits["sim-extended"]["b_over_a"],
        "a_ms": fits["sim-extended"]["a"],
        "b_ms": fits["sim-extended"]["b"],
        "b_over_b_off": fits["sim-extended"].get("b_over_b_off"),
        "in_flight_ratio": {r.scene: r.value for r in flight.itertuples()},
        "targets_passed": int((targets["verdict"] == "PASS").sum()),
        "targets": int(len(targets)),
    }


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
