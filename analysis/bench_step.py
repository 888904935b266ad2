"""Table "bench_step": the solver's cost per step against pymunk with nothing frozen (sim-off),
for the paper's set-up section: paper/generated/bench_step.csv and the headline ratios."""
from analysis import style

NAME = "bench_step"


def draw(table, meta):
    sim = table[table["system"] == "sim-off"].set_index(["scene", "param"])
    pym = table[table["system"] == "pymunk"].set_index(["scene", "param"])
    out = sim[["bodies"]].copy()
    out["sim_off_ms"] = sim["ms_per_step_median"]
    out["pymunk_ms"] = pym["ms_per_step_median"]
    out["pymunk_over_sim"] = out["pymunk_ms"] / out["sim_off_ms"]
    out = out.reset_index()
    shown = out.assign(scene=[f"{s}({p})" for s, p in zip(out["scene"], out["param"])])
    style.write_table(shown[["scene", "bodies", "sim_off_ms", "pymunk_ms", "pymunk_over_sim"]]
                      .round({"sim_off_ms": 4, "pymunk_ms": 4, "pymunk_over_sim": 2}), NAME)
    largest = out.loc[out.groupby("scene")["bodies"].idxmax()]
    return {"pymunk_over_sim": {f"{r.scene}({r.param})": r.pymunk_over_sim
                                for r in out.itertuples()},
            "largest": {r.scene: {"scene": f"{r.scene}({r.param})", "bodies": int(r.bodies),
                                  "sim_off_ms": r.sim_off_ms, "pymunk_ms": r.pymunk_ms,
                                  "pymunk_over_sim": r.pymunk_over_sim}
                        for r in largest.itertuples()},
            "repeats": int(table["repeats"].iloc[0]),
            "steps_per_repeat": int(table["steps_per_repeat"].iloc[0])}


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
