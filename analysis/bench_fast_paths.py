"""Table "bench_fast_paths": which work the solver skips when a scene does not need it, and what
each candidate saves (paper/generated/bench_fast_paths.csv: the verdicts)."""
import pandas as pd

from analysis import style

NAME = "bench_fast_paths"


def draw(table, meta):
    verdicts = pd.DataFrame(meta["parameters"]["verdicts"])
    shown = verdicts.assign(saving=verdicts["saving"].map(lambda x: f"{100 * x:.1f} %"))
    style.write_table(shown[["candidate", "saving", "verdict", "detail"]], NAME)
    return {"pays": meta["parameters"]["pays"],
            "saving": {r.candidate: r.saving for r in verdicts.itertuples()},
            "verdict": {r.candidate: r.verdict for r in verdicts.itertuples()},
            "friction_ms": {r.variant: r.ms_per_step_median for r in table[
                (table["part"] == "friction")
                & table["scene"].str.contains("mu=0.0", regex=False)].itertuples()}}


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
