"""Table "bench_fast_paths": which work the solver skips when a scene does not need it, and what
each candidate saves, or could save at most (paper/generated/bench_fast_paths.csv: the
verdicts). The bounds of the candidates not built (box SAT, rotation) are whole profile stages of
the public ``World.profile`` (narrowphase, broadphase): looser than the bounds measured before
with sim's internals (see the experiment's docstring)."""

import pandas as pd

from analysis import style

NAME = "bench_fast_paths"


def draw(table, meta):
    p = meta["parameters"]
    verdicts = pd.DataFrame(p["verdicts"])
    shown = verdicts.assign(saving=verdicts["saving"].map(lambda x: f"{100 * x:.1f} %"))
    style.write_table(shown[["candidate", "saving", "verdict", "detail"]], NAME)
    return {
        "pays": p["pays"],
        "saving": {r.candidate: r.saving for r in verdicts.itertuples()},
        "verdict": {r.candidate: r.verdict for r in verdicts.itertuples()},
        "friction_ms": {
            r.variant: r.ms_per_step_median
            for r in table[
                (table["part"] == "friction") & table["scene"].str.contains("mu=0.0", regex=False)
            ].itertuples()
        },
        "bounds_from": {"box_sat": "narrowphase stage", "rotation": "broadphase stage"},
        "substeps": p.get("substeps"),
        "iterations": p.get("iterations"),
    }


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
