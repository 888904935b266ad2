"""Table "peer_agreement": do sim, pymunk and pybullet agree on the known answers (free fall, rest,
sliding distance, bounce, tipping, a stack)? paper/generated/peer_agreement.csv lists every check
against an analytic answer or sim-off with its tolerance; the numbers count the agreements and say
how much solving each system did per step (each at its own defaults: sim's substeps and sweeps,
the peers' iterations)."""

from analysis import style

NAME = "peer_agreement"


def draw(table, meta):
    checked = table[table["agree"].notna()].copy()
    checked["agree"] = checked["agree"].astype(str).str.lower() == "true"
    shown = checked[
        ["scene", "system", "metric", "value", "reference", "reference_kind", "tolerance", "agree"]
    ].copy()
    for col in ("value", "reference", "tolerance"):
        shown[col] = shown[col].map(lambda x: f"{x:.4g}")
    shown["agree"] = shown["agree"].map({True: "yes", False: "NO"})
    style.write_table(shown, NAME)
    per_system = checked.groupby("system")["agree"].agg(["sum", "count"])
    slide = table[table["metric"] == "slide_distance_m"].set_index("system")
    disagreements = [
        f"{r.system}: {r.scene} {r.metric} {r.value:.4g} vs {r.reference:.4g}"
        for r in checked[~checked["agree"]].itertuples()
    ]
    return {
        "checks": int(len(checked)),
        "agreed": int(checked["agree"].sum()),
        "per_system": {
            s: {"agreed": int(r["sum"]), "checks": int(r["count"])}
            for s, r in per_system.iterrows()
        },
        "slide_distance_m": {s: float(v) for s, v in slide["value"].items()},
        "slide_distance_analytic_m": float(slide["reference"].iloc[0]),
        "disagreements": disagreements,
        "solver": meta["parameters"].get("solver_summary", {}),
    }


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
