"""The README's results bullets say what the numbers say, in the study's protocol."""

from analysis.glance import (
    extremes_line,
    frozen_cost_line,
    provenance_text,
    slow_cases_line,
    presolve_failures_line,
    solver_line,
    time_to_rest_line,
)
from analysis.fig_time_to_rest import median_beyond_cap
from analysis.paper import provenance


def _extremes(per_axis, fair):
    return {
        "cells": 4,
        "counts": {"sim-off": {"failed": 0}, "pymunk": {"failed": 1}},
        "per_axis": per_axis,
        "breaks_first": fair,
        "no_presolve": {
            "suffix": " (no presolve)",
            "axes": ["stack_height"],
            "cells": 2,
            "counts": {"sim-off (no presolve)": {"failed": 1, "degraded": 0}},
        },
    }


def test_the_extremes_bullet_quotes_the_fair_headline():
    """Where sim's presolve decides who breaks first on a placed axis, the README must quote the
    fair rows (sim without it), not the rows sim wins with it."""
    with_presolve = {
        "stack_height": {"breaks_first": ["pymunk"], "breaks_first_at": "50"},
        "dt": {"breaks_first": ["pymunk"], "breaks_first_at": "1/15 s"},
    }
    fair = {
        "stack_height": {"breaks_first": ["sim-off (no presolve)"], "breaks_first_at": "10"},
        "dt": {"breaks_first": ["pymunk"], "breaks_first_at": "1/15 s"},
    }
    line = extremes_line(_extremes(with_presolve, fair))
    assert "stack height: sim-off (no presolve) (at 10)" in line
    assert "stack height: pymunk" not in line
    assert "dt: pymunk (at 1/15 s)" in line
    assert "failed per system: sim-off 0, pymunk 1" in line
    assert "On the 1 axes that start placed at rest" in line
    assert "sim-off 1 failed / 0 degraded" in line
    assert "sim's failed cells" not in line  # none listed: nothing said


def test_the_extremes_bullet_says_why_each_sim_cell_failed():
    ex = _extremes({}, {})
    ex["sim_failures"] = [
        "sim-extended time step (10-box stack) 1/480 s: chattering (a body woken 3 times)",
        "sim-sleep knife edge tilt 1e-06 rad: outcome stays (reference falls left)",
    ]
    line = extremes_line(ex)
    assert (
        "sim's failed cells: sim-extended time step (10-box stack) 1/480 s: chattering (a body "
        "woken 3 times); sim-sleep knife edge tilt 1e-06 rad: outcome stays (reference falls "
        "left)." in line
    )


def _system(steps, never=()):
    drops = [k for k in steps if k.startswith("drop")]
    return {
        "steps": steps,
        "never": list(never),
        "family_median_steps": {
            "drop": median_beyond_cap([steps[k] for k in drops], [k in never for k in drops]),
        },
    }


def test_a_median_counts_a_run_that_never_froze_as_beyond_the_cap():
    """The piles' median is an order statistic: a run that never froze is longer than any that
    did, and the median is exact unless it falls on such a run."""
    assert median_beyond_cap([376, None, 196, 190, 225], [0, 1, 0, 0, 0]) == 225
    assert median_beyond_cap([376, None, None, 190, None], [0, 1, 1, 0, 1]) is None
    assert median_beyond_cap([100, 200, 300, 400], [0, 0, 0, 0]) == 250
    assert median_beyond_cap([100, None], [0, 1]) is None  # the mean of 100 and "never"
    assert median_beyond_cap([], []) is None


def test_the_time_to_rest_bullet_quotes_the_piles_and_the_certificate_cost():
    """Placed at rest every certificate is one step and every timer its length: the bullet must
    also say how the systems do on piles that fall and settle (median over the seeds, or how many
    never froze) and what the certificate costs."""
    scenes = ["rest_row(50)", "drop(30,seed=0)", "drop(30,seed=1)", "drop(30,seed=2)"]
    ttr = {
        "dt": 1 / 60,
        "scenes": scenes,
        "sim-extended": _system(dict(zip(scenes, [1, 120, 140, 400]))),
        "sim-sleep": _system(dict(zip(scenes, [31, 190, None, 150])), never=["drop(30,seed=1)"]),
        "certificate": {"median_us_per_certificate": 3.51, "max_us_per_certificate": 9.46},
    }
    line = time_to_rest_line(ttr)
    assert "Placed at rest (rest_row(50)): sim-extended 1, sim-sleep 31." in line
    assert (
        "(drop(30)), median over 3 seeds: sim-extended 140, sim-sleep 190 (1 of 3 never froze: "
        "beyond the cap in the median)" in line
    )
    assert "3.5 µs per certificate" in line and "at most 9.5 µs" in line
    assert "freezing off" not in line  # no reference runs in these results: nothing said


def test_the_time_to_rest_bullet_says_how_long_the_reference_piles_move():
    scenes = ["rest_row(50)", "drop(30,seed=0)"]
    ttr = {
        "dt": 1 / 60,
        "scenes": scenes,
        "sim-extended": _system(dict(zip(scenes, [1, 120]))),
        "certificate": {"median_us_per_certificate": 3.51, "max_us_per_certificate": 9.46},
        "reference": {
            "sim-off": {"pile_median_steps": {"0.05": 90.0, "0.02": 101.0, "0.001": None}},
            "pymunk": {"pile_median_steps": {"0.05": 300.0, "0.02": 421.0, "0.001": 436.0}},
            "box2d": {"pile_median_steps": {"0.05": 200.0, "0.02": None, "0.001": None}},
        },
    }
    line = time_to_rest_line(ttr)
    assert (
        "with freezing off the same piles move at 2 cm/s or faster until step 101 (median) and "
        "creep at 1 mm/s or faster until step past the cap (each peer with its sleeping off: "
        "2 cm/s or faster until pymunk 421, box2d past the cap)" in line
    )


def test_the_time_to_rest_bullet_quotes_the_larger_seed_sample():
    scenes = ["rest_row(50)", "drop(30,seed=0)"]
    sample = {
        "seeds": 100,
        "scene": "drop(30)",
        "systems": {
            "sim-sleep": {"median_steps": 170.0, "never": 0},
            "sim-extended": {"median_steps": 215.5, "never": 3},
        },
        "extended_over_sleep": 215.5 / 170.0,
    }
    ttr = {
        "dt": 1 / 60,
        "scenes": scenes,
        "sim-extended": _system(dict(zip(scenes, [1, 120]))),
        "certificate": {"median_us_per_certificate": 3.51, "max_us_per_certificate": 9.46},
        "seed_sample": sample,
    }
    line = time_to_rest_line(ttr)
    assert (
        "over 100 seeds of drop(30) (medians, a pile that never froze counted as beyond the "
        "cap): sim-extended 215.5 (3 never froze), sim-sleep 170, extended / sleep 1.3×" in line
    )
    sample["systems"]["sim-extended"]["median_steps"] = None
    sample["extended_over_sleep"] = None
    line = time_to_rest_line(ttr)
    assert "sim-extended beyond the cap (3 never froze), sim-sleep 170." in line


def test_the_failures_bullet_names_what_freezing_changes_among_the_slow_cases():
    tf = {
        "slow_cases": ["unstable_equilibrium", "slow_sliding"],
        "slow_broken_by": {
            "sim-sleep": ["unstable_equilibrium", "slow_sliding"],
            "pybullet-sleep": ["slow_sliding"],
            "sim-extended": [],
        },
    }
    line = slow_cases_line(tf)
    assert line == (
        "Of the 2 slow cases (tipping from an unstable balance, slow sliding, creep), freezing "
        "changes: sim-sleep 2 (unstable_equilibrium, slow_sliding); pybullet-sleep 1 "
        "(slow_sliding); none under sim-extended."
    )


def _fit(b_over_a, stderr):
    fit = {"b_over_a": b_over_a, "b_over_a_stderr": stderr, "a": 1e-4, "b": b_over_a * 1e-4}
    off = {"b_over_a": 1e3, "b_over_a_stderr": 1e5, "a": 1e-7, "b": 3.3e-5}  # a unresolved
    return {"sim-extended": fit, "sim-off": off, "pymunk-sleep": fit}


def test_the_frozen_cost_bullet_says_what_the_fit_can_tell():
    """A cost is quoted only when the fit tells it from zero; within two standard errors of zero
    the bullet gives the upper bound; a fit below zero even at two standard errors is not a saving
    (a frozen body can only add work) and must not be quoted as a bound."""
    line = frozen_cost_line(_fit(0.05, 0.01))
    assert "A frozen body costs 0.05 of an awake one" in line
    # the solved body against extended's a (off's own is not resolved beside the solved row)
    assert "the same resting body costs 0.33 times an awake body in flight under `extended`" in line
    assert "at most 0.07 at two standard errors" in line
    line = frozen_cost_line(_fit(0.001, 0.003))
    assert "too little to measure" in line and "at most 0.007 at two standard errors" in line
    line = frozen_cost_line(_fit(-0.011, 0.005))
    assert "too little to measure" in line
    assert "below zero even at two standard errors" in line and "drift in the timings" in line
    assert "at most" not in line


def test_provenance_names_every_commit_that_made_a_result():
    """A results set remade in part (one experiment rerun at a later commit, or from a tree with
    uncommitted changes) names each commit with the results it made; one commit, one name."""
    clean = {"commit": "a" * 40, "dirty": False}
    later = {"commit": "0" * 40, "dirty": True}  # sorts first by name, not by count
    meta = {"x": {"git": clean}, "y": {"git": clean}, "z": {"git": later}, "w": {}}
    got = provenance(meta)
    assert got == [
        {"commit": "aaaaaaaaaa", "results": ["x", "y"]},
        {"commit": "0000000000+dirty", "results": ["z"]},
        {"commit": "unknown", "results": ["w"]},
    ]
    assert provenance_text(got) == (
        "commit `aaaaaaaaaa` (`z` from commit `0000000000+dirty`; `w` from commit `unknown`)"
    )
    assert provenance_text(provenance({"x": {"git": clean}})) == "commit `aaaaaaaaaa`"


def test_the_time_to_rest_bullet_sets_sims_presolve_apart():
    """sim's presolve puts a placed scene in equilibrium before step 1, which no peer has: the
    bullet gives each sim system's steps on the largest pyramid with and without it, beside the
    peers' (which have only the one)."""
    scenes = ["rest_row(50)", "pyramid(10)", "pyramid(20)", "drop(30,seed=0)"]
    ttr = {
        "dt": 1 / 60,
        "scenes": scenes,
        "sim-extended": _system(dict(zip(scenes, [1, 1, 1, 120]))),
        "sim-sleep": _system(dict(zip(scenes, [30, 30, 30, 150]))),
        "pymunk-sleep": _system(dict(zip(scenes, [31, 40, 90, 200]))),
        "certificate": {"median_us_per_certificate": 3.51, "max_us_per_certificate": 9.46},
        "without_presolve": {
            "sim-extended (no presolve)": _system(
                {"rest_row(50)": 1, "pyramid(10)": 47, "pyramid(20)": 469}
            ),
            "sim-sleep (no presolve)": _system(
                {"rest_row(50)": 30, "pyramid(10)": 42, "pyramid(20)": None}
            ),
        },
    }
    line = time_to_rest_line(ttr)
    assert (
        "; on pyramid(20), with / without sim's presolve of the start pose (no peer has one): "
        "sim-extended 1 / 469, sim-sleep 30 / never, against pymunk-sleep 90." in line
    )
    del ttr["without_presolve"]
    assert "presolve" not in time_to_rest_line(ttr)  # older results: nothing said


def test_the_failures_bullet_sets_sims_presolve_apart():
    tf = {
        "without_presolve": {
            "failures_by_freezing": {"sim-sleep": 5, "sim-paper": 5, "sim-extended": 0},
            "broken_by": {},
            "outcome_changes": [
                {
                    "scenario": "unstable_equilibrium",
                    "system": "sim-sleep",
                    "with": "balanced",
                    "without": "tipped off",
                }
            ],
        }
    }
    assert presolve_failures_line(tf) == (
        " Without sim's presolve of the start pose (no peer has one), freezing changes: "
        "sim-sleep 5, sim-paper 5, sim-extended 0; the presolve changes the outcome of "
        "unstable_equilibrium under sim-sleep (balanced with it, tipped off without)."
    )
    tf["without_presolve"]["outcome_changes"] = []
    assert presolve_failures_line(tf).endswith("; the presolve changes no outcome.")
    assert presolve_failures_line({}) == ""  # older results: nothing said


def _bench(drop_pymunk=1.11, drop_v3=0.77, met=False):
    def scene(name, pymunk, v3, b2):
        return {
            "scene": name,
            "pymunk_over_sim": pymunk,
            "box2d3_over_sim": v3,
            "box2d_over_sim": b2,
        }

    return {
        "largest": {
            "rest_row": scene("rest_row(5000)", 3.4, 1.77, 4.67),
            "pyramid": scene("pyramid(40)", 3.14, 1.44, 3.91),
            "drop": scene("drop(200)", drop_pymunk, drop_v3, 1.6),
        },
        "target_ratio": 3.0,
        "targets": {
            "pyramid(40)": {"speedup_vs_pymunk": 3.14, "met": True},
            "drop(200)": {"speedup_vs_pymunk": drop_pymunk, "met": met},
        },
        "box2d3": {"substeps": 4},
    }


def test_the_solver_bullet_quotes_every_peer_and_the_missed_target():
    line = solver_line(_bench())
    assert "pymunk 3.40× on rest_row(5000), 3.14× on pyramid(40), 1.11× on drop(200)" in line
    assert "Box2D v3 1.77× on rest_row(5000), 1.44× on pyramid(40), 0.77× on drop(200)" in line
    assert "Box2D 2.3 4.67× on rest_row(5000)" in line
    assert "not met on drop(200) (1.11×)" in line
    # what the state of the art does on the scene where the target is missed: 1.11 / 0.77
    assert "Box2D v3 itself runs drop(200) at 1.44× pymunk's rate" in line


def test_the_solver_bullet_says_when_the_target_is_met():
    line = solver_line(_bench(drop_pymunk=3.2, drop_v3=1.5, met=True))
    assert "met on every target scene" in line and "not met" not in line
    assert "itself runs" not in line


def test_the_solver_bullet_names_a_peer_whose_pile_reached_its_engine_clamp():
    bench = _bench()
    assert "clamp" not in solver_line(bench)
    bench["clamped"] = {"drop(200)": {"box2d": {"piles": 1, "of": 7, "first": "seed 4, ..."}}}
    line = solver_line(bench)
    assert (
        "per-step motion clamp, which slows it silently, under Box2D 2.3 in 1 of 7 piles of "
        "drop(200)" in line
    )


def test_the_solver_bullet_quotes_sim_without_its_landing_sweeps_apart():
    """bench_step's settling variant (sim-off with impact_iterations=0) is reported in its own
    sentence, with its own ratios, and only when the results have it."""
    bench = _bench()
    assert "landing sweeps" not in solver_line(bench)  # results written before the variant
    bench["variants"] = {
        "drop(200)": {
            "sim-off (no landing sweeps)": {
                "ms": 0.2,
                "pymunk_over_variant": 1.24,
                "box2d3_over_variant": 0.85,
                "box2d_over_variant": 1.6,
            }
        }
    }
    line = solver_line(bench)
    assert (
        'Without its landing sweeps (`impact_iterations=0`, the row "sim-off (no landing '
        "sweeps)\": accuracy work no peer does) sim-off runs drop(200) at 1.24× pymunk's rate "
        "and 0.85× Box2D v3's." in line
    )
    assert "1.11× on drop(200)" in line  # sim-off's own ratios are unchanged
