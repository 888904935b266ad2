"""Table "bench_step": the solver's cost per step against pymunk, Box2D 2.3 and Box2D v3 with
nothing frozen (sim-off), for the paper's set-up section, and where sim's step spends its time.

Writes paper/generated/bench_step.csv (ms per step per scene, pymunk/sim, box2d/sim, box2d3/sim,
and the piles in which a peer's body reached its engine's silent motion clamp),
bench_step_profile.csv
(sim's step by stage, ms, one column per scene) and bench_step.json: the ratios per scene, the
issue's target (sim at least 3x pymunk's step rate on pyramid(40), rest_row(5000), drop(200)
while it settles) met or not on each, the substeps and iterations each system used, the
profile of the target scenes, and sim-off without its landing sweeps on the settling scene
(``variants``, reported apart)."""

from analysis import style
from study.metadata import ResultsError

NAME = "bench_step"
PEERS = ("pymunk", "box2d", "box2d3")  # the peers timed (experiments/bench_step.py SYSTEMS)
PROFILE = "bench_step_profile"


def _ratios(table):
    sim = table[table["system"] == "sim-off"].set_index(["scene", "param"])
    out = sim[["label", "bodies", "mode", "substeps", "iterations"]].copy()
    out["sim_off_ms"] = sim["ms_per_step_median"]
    for peer in PEERS:
        rows = table[table["system"] == peer].set_index(["scene", "param"])
        out[f"{peer}_ms"] = rows["ms_per_step_median"]
        out[f"{peer}_iterations"] = rows["iterations"]
        out[f"{peer}_over_sim"] = out[f"{peer}_ms"] / out["sim_off_ms"]
    return out.reset_index()


#: the peers' names in the table's note on clamped piles
PEER_NAMES = {"pymunk": "pymunk", "box2d": "Box2D 2.3", "box2d3": "Box2D v3"}


def clamped(table):
    """{label: {peer: {"piles": n, "of": repeats, "first": text}}} of the settling scenes on
    which a peer's body reached its engine's silent motion clamp (bench_step's ``clamped_piles``
    and ``clamps``; absent from a table written before them)."""
    if "clamped_piles" not in table:
        return {}
    rows = table[(table["system"] != "sim-off") & (table["clamped_piles"].fillna(0) > 0)]
    out = {}
    for r in rows.itertuples():
        out.setdefault(r.label, {})[r.system] = {
            "piles": int(r.clamped_piles),
            "of": int(r.repeats),
            "first": str(r.clamps).split("; ")[0],
        }
    return out


def _clamp_note(label, found):
    """The table's cell on clamped piles: "Box2D 2.3: 1 of 7 piles", or ""."""
    return ", ".join(
        f"{PEER_NAMES.get(p, p)}: {c['piles']} of {c['of']} piles"
        for p, c in found.get(label, {}).items()
    )


def settling_seeds(table):
    """{label: [seed, ...]} of the settling scenes (bench_step's ``seeds`` column: one pile per
    repeat); empty lists for a table written before the column existed."""
    sims = table[(table["system"] == "sim-off") & table["mode"].str.startswith("settling")]
    seeds = sims["seeds"] if "seeds" in sims else [""] * len(sims)
    return {label: str(s).split() for label, s in zip(sims["label"], seeds)}


def variants(table):
    """{label: {variant: {"ms": ms per step, "<peer>_over_variant": ratio}}} of sim's settling
    variants (bench_step's SETTLING_VARIANTS: sim-off without its landing sweeps), timed beside
    the systems and reported apart; empty for a table written before them."""
    rows = table[~table["system"].isin(("sim-off", *PEERS))]
    return {
        label: {
            r["system"]: {
                "ms": float(r["ms_per_step_median"]),
                **{f"{p}_over_variant": float(r[f"speedup_vs_{p}"]) for p in PEERS},
            }
            for _, r in group.iterrows()
        }
        for label, group in rows.groupby("label", sort=False)
    }


def _settings(table, system):
    row = table[table["system"] == system].iloc[0]
    return {
        "substeps": int(row["substeps"]),
        "iterations": int(row["iterations"]),
        "relax_iterations": int(row["relax_iterations"]),
        "contact_sweeps_per_step": int(row["contact_sweeps_per_step"]),
    }


def check_same_run(meta, profile_meta):
    """Refuse a table and a profile from two runs: one run writes both files with the same
    provenance (its date and parameters). Copied over the other's table only, a second run's
    bench_step.csv made a table of one run beside the profile of another, silently."""
    for key in ("date_utc", "parameters"):
        if profile_meta.get(key) != meta.get(key):
            raise ResultsError(
                f"{PROFILE}.csv and {NAME}.csv come from different runs ({key}: "
                f"{profile_meta.get(key)!r} against {meta.get(key)!r}): rerun "
                f"`python -m experiments.{NAME}`"
            )


def draw(table, meta):
    out = _ratios(table)
    found = clamped(table)
    shown = out.assign(
        scene=out["label"],
        when=out["mode"].map(lambda m: "settling" if m.startswith("settling") else "resting"),
        # a peer whose body reached its engine's silent clamp: its pile is not the scene's
        clamped=out["label"].map(lambda lbl: _clamp_note(lbl, found)),
    )
    style.write_table(
        shown[
            [
                "scene",
                "bodies",
                "when",
                "sim_off_ms",
                "pymunk_ms",
                "pymunk_over_sim",
                "box2d_ms",
                "box2d_over_sim",
                "box2d3_ms",
                "box2d3_over_sim",
                "clamped",
            ]
        ].round(
            {
                "sim_off_ms": 4,
                **{f"{p}_ms": 4 for p in PEERS},
                **{f"{p}_over_sim": 2 for p in PEERS},
            }
        ),
        NAME,
    )

    profile, profile_meta = style.load(PROFILE, script=NAME)
    check_same_run(meta, profile_meta)
    wide = profile.pivot_table(index="stage", columns="label", values="ms_per_step", sort=False)
    wide = wide[[c for c in out["label"] if c in wide.columns]]
    style.write_table(wide.round(4).reset_index(), PROFILE)

    target = meta["parameters"].get("target_ratio", 3.0)
    targets = meta["parameters"].get("targets", {})
    largest = out.loc[out.groupby("scene")["bodies"].idxmax()]
    stages = profile[profile["stage"] != "total"]
    return {
        **{f"{p}_over_sim": dict(zip(out["label"], out[f"{p}_over_sim"])) for p in PEERS},
        "ms_per_step": {
            r["label"]: {"sim-off": r["sim_off_ms"], **{p: r[f"{p}_ms"] for p in PEERS}}
            for _, r in out.iterrows()
        },
        "largest": {
            r["scene"]: {
                "scene": r["label"],
                "bodies": int(r["bodies"]),
                "sim_off_ms": r["sim_off_ms"],
                **{k: r[k] for p in PEERS for k in (f"{p}_ms", f"{p}_over_sim")},
            }
            for _, r in largest.iterrows()
        },
        "target_ratio": target,
        "targets": targets,
        # the settling scene's piles: one seed per repeat, the same for every system
        "settling_seeds": settling_seeds(table),
        # piles in which a peer's body reached its engine's silent motion clamp
        "clamped": found,
        # sim-off without its landing sweeps on the settling scene, reported apart
        "variants": variants(table),
        "targets_met": bool(targets) and all(t["met"] for t in targets.values()),
        "sim": _settings(table, "sim-off"),
        **{p: _settings(table, p) for p in PEERS},
        "profile_ms": {
            lbl: {r.stage: r.ms_per_step for r in g.itertuples()}
            for lbl, g in profile.groupby("label", sort=False)
        },
        "profile_largest_stage": {
            lbl: g.loc[g["ms_per_step"].idxmax(), "stage"]
            for lbl, g in stages.groupby("label", sort=False)
        },
        "profiled_over_unprofiled": {
            lbl: float(g["profile_total_ms"].iloc[0] / g["ms_per_step_unprofiled"].iloc[0])
            for lbl, g in profile.groupby("label", sort=False)
        },
        "repeats": int(table["repeats"].iloc[0]),
        "steps_per_repeat": int(meta["parameters"]["steps_per_repeat"]),
        "settle_window_steps": int(meta["parameters"]["settle_window_steps"]),
    }


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
