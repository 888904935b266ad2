"""experiments.fig_tradeoff, its library study.tradeoff and analysis.fig_tradeoff: the one
penetration routine against sim's own separating-axis kernel and known overlaps, the landing scene
and its exact rest pose, the solver sweep's grid, and the experiment end to end on --quick sizes
(into a temporary folder) followed by its analysis.

Wall-clock speed-ups are checked only where a wrong result could not come from machine load (the
ratio of minima, for a setting that freezes the whole scene within a step)."""

import json
import math

import numpy as np
import pandas as pd
import pytest

import sim
from analysis import fig_tradeoff as analysis
from analysis import fronts
from experiments import fig_tradeoff as exp
from study import paths, tradeoff
from study.common import SLOP, build
from sim.geometry import edge_normals, mass_properties, max_separation


# ---- the penetration routine -------------------------------------------------------------------
def _com(body):
    """World centre of mass of a scene body (what every runner reports as its position)."""
    _, centroid, _ = mass_properties(body.vertices, body.density)
    c, s = math.cos(body.angle), math.sin(body.angle)
    return np.array(body.position) + np.array(
        [c * centroid[0] - s * centroid[1], s * centroid[0] + c * centroid[1]]
    )


def _pose(scene):
    return (
        np.array([_com(b) for b in scene.bodies]),
        np.array([b.angle for b in scene.bodies], dtype=float),
    )


def test_overlap_matches_sims_separating_axis_kernel():
    rng = np.random.default_rng(7)
    overlapping = 0
    for _ in range(200):
        bodies = [
            sim.Body(
                vertices=sim.scenes.random_convex(rng, 0.5),
                position=tuple(rng.uniform(-0.6, 0.6, 2) + (0.0, 5.0)),
                angle=float(rng.uniform(-3, 3)),
            )
            for _ in range(2)
        ]
        scene = sim.Scene(bodies=bodies, floor_y=None)
        polygons = tradeoff.Polygons(scene)
        positions, angles = _pose(scene)
        got = tradeoff.deepest_overlap(polygons, positions, angles)
        w = polygons.world(positions, angles)
        a = np.ascontiguousarray(w[0][: len(bodies[0].vertices)])
        b = np.ascontiguousarray(w[1][: len(bodies[1].vertices)])
        sep = max(
            max_separation(a, edge_normals(a), b)[1], max_separation(b, edge_normals(b), a)[1]
        )
        assert got == pytest.approx(max(0.0, -sep), abs=1e-12)
        overlapping += sep < 0
    assert 20 < overlapping < 180  # both cases were exercised


def test_overlap_of_known_poses():
    box = lambda x, y, angle=0.0: sim.Body.box(1.0, 1.0, position=(x, y), angle=angle)
    # two unit boxes 0.9 m apart overlap by 0.1 m; the floor is not touched
    scene = sim.Scene(bodies=[box(0.0, 2.0), box(0.9, 2.0)])
    assert tradeoff.deepest_overlap(tradeoff.Polygons(scene), *_pose(scene)) == pytest.approx(0.1)
    # apart: nothing; a box sunk 3 cm into the floor: 0.03
    scene = sim.Scene(bodies=[box(0.0, 2.0), box(1.2, 0.47)])
    assert tradeoff.deepest_overlap(tradeoff.Polygons(scene), *_pose(scene)) == pytest.approx(0.03)
    # a box rotated 45 degrees whose corner is 2 cm into the floor
    h = math.sqrt(0.5)
    scene = sim.Scene(bodies=[box(0.0, h - 0.02, math.pi / 4)])
    assert tradeoff.deepest_overlap(tradeoff.Polygons(scene), *_pose(scene)) == pytest.approx(0.02)
    # a static ledge (a triangle: padding to the box's 4 vertices is exercised) 5 cm into a box
    ledge = sim.Body(vertices=[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)], position=(0.45, 1.5))
    scene = sim.Scene(bodies=[box(0.0, 2.0)], static_bodies=[ledge])
    assert tradeoff.deepest_overlap(tradeoff.Polygons(scene), *_pose(scene)) == pytest.approx(0.05)


# ---- the landing scene -------------------------------------------------------------------------
def test_landing_starts_apart_and_settles_in_rows():
    scene = tradeoff.landing(base=4, layers=1, loners=2)
    assert len(scene.bodies) == 4 + 3 + 2
    assert tradeoff.deepest_overlap(tradeoff.Polygons(scene), *_pose(scene)) == 0.0
    runner = build("sim-off", scene)
    runner.step(150)
    y = runner.positions[:, 1]
    # rest heights: base row and loners 0.5 m, the dropped row 1.5 m (less a few slops)
    expected = np.array([0.5] * 4 + [1.5] * 3 + [0.5] * 2)
    assert np.abs(y - expected).max() < 0.02
    assert np.hypot(*runner.velocities.T).max() < 0.05
    # the dropped boxes land flat, centred over the gaps: no tilt, no sliding off
    assert np.abs(runner.angles).max() < 0.01
    start_x = [b.position[0] for b in scene.bodies[4:7]]
    assert np.abs(runner.positions[4:7, 0] - start_x).max() < 0.02


def test_rest_pose_is_the_exact_answer():
    """The pyramid's exact final pose is its start; the landing's has every box where it started
    in x, flat, on the row below (rows at 0.5, 1.5 m; loners at 0.5 m)."""
    pyramid = sim.scenes.pyramid(3)
    positions, angles = tradeoff.rest_pose(pyramid)
    start, start_angles = _pose(pyramid)
    assert np.array_equal(positions, start) and np.array_equal(angles, start_angles)
    scene = tradeoff.landing(base=4, layers=1, loners=2)
    positions, angles = tradeoff.rest_pose(scene)
    start, _ = _pose(scene)
    assert np.array_equal(positions[:, 0], start[:, 0]) and not angles.any()
    assert positions[:, 1].tolist() == [0.5] * 4 + [1.5] * 3 + [0.5] * 2
    # at rest nothing overlaps and every box touches what carries it
    assert tradeoff.deepest_overlap(tradeoff.Polygons(scene), positions, angles) == pytest.approx(
        0.0
    )
    with pytest.raises(ValueError, match="no exact rest pose"):
        tradeoff.rest_pose(sim.scenes.drop(3))


def test_solver_grid_and_reference_check():
    assert tradeoff.solver_grid(4, range(-2, 3)) == [1, 2, 4, 8, 16]
    assert tradeoff.solver_grid(1, range(0, 4)) == [1, 2, 4, 8]
    with pytest.raises(ValueError, match="whole number"):
        tradeoff.solver_grid(1, [-1])
    # sim's reference must run more sweeps per substep than any swept setting
    with pytest.raises(ValueError, match="finer than every swept"):
        exp.check_reference(
            {**exp.FULL, "reference_iterations": {**exp.FULL["reference_iterations"], "sim": 8}}
        )
    exp.check_reference(exp.FULL)
    exp.check_reference(exp.QUICK)


def test_bad_scene_input_is_refused():
    with pytest.raises(ValueError, match="layers"):
        tradeoff.landing(base=2, layers=2)
    with pytest.raises(ValueError, match="unknown scene"):
        tradeoff.make_scene("heap", {})


def test_grid_is_log_spaced_around_the_default():
    assert tradeoff.grid(0.5, 0.5, range(-2, 3)) == pytest.approx(
        [0.05, 0.158113883, 0.5, 1.58113883, 5.0]
    )
    assert tradeoff.grid(0.05, 1.0, [0])[0] == 0.05  # the default exactly


def test_pareto_front():
    pts = pd.DataFrame(
        {"speedup": [1.0, 2.0, 3.0, 4.0, 0.5, 5.0], "err": [5.0, 3.0, 4.0, 1.0, 0.5, math.nan]}
    )
    front = fronts.pareto(pts, "err")
    assert list(zip(front["speedup"], front["err"])) == [(0.5, 0.5), (4.0, 1.0)]


#: extended's settings p (its front: 2x at 1 mm, 4x at 10 mm) and other systems' sweep settings
FRONT_ROWS = pd.DataFrame(
    [
        ("sim-extended", "sweep", "p", 1.0, 2.0, 1e-3),
        ("sim-extended", "sweep", "p", 2.0, 4.0, 1e-2),
        ("sim-extended", "sweep", "p", 3.0, 1.0, 5e-2),  # not on its own front
        ("sim-sleep", "sweep", "q", 1.0, 1.5, 2e-3),  # dominated (2.0x at 1e-3)
        ("sim-sleep", "sweep", "q", 2.0, 3.0, 1e-4),  # more accurate at its speed: beats 2x
        ("sim-sleep", "sweep", "q", 3.0, 3.9, 1e-2 - 5e-7),  # a tie with 4.0x: dominated
        ("sim-sleep", "sweep", "q", 4.0, 3.0, 5e-3),  # in the gap: faster than 2x, not better
        ("pymunk-sleep", "sweep", "r", 1.0, 8.0, 0.5),  # faster than any extended setting
        ("pymunk-sleep", "sweep", "r", 2.0, 8.0, 2e-3),  # faster, and better than 4x only
        ("sim-off", "baseline", "none", float("nan"), 1.0, 0.0),
        ("sim-off", "solver", "substeps", 1.0, 1.2, 0.0),
    ],
    columns=["system", "role", "parameter", "value", "speedup", "err"],
)
FREEZING = ("sim-extended", "sim-sleep", "pymunk-sleep")


def test_beyond_front_lists_what_extendeds_front_does_not_dominate():
    """A point is beyond the front when no extended setting is at least as fast and at least as
    accurate (within the tie); a point faster than extended's fastest has nothing to compare
    with; the baseline and the solver rows are not freezing settings."""
    out = fronts.beyond_front(FRONT_ROWS, "err", "sim-extended", FREEZING)
    assert [(p["system"], p["setting"], p["speedup"]) for p in out] == [
        ("pymunk-sleep", "r=1", 8.0),
        ("pymunk-sleep", "r=2", 8.0),
        ("sim-sleep", "q=2", 3.0),
        ("sim-sleep", "q=4", 3.0),
    ]
    assert out[0]["challenger_error_m"] is None
    assert out[2]["challenger_error_m"] == 1e-2 and out[2]["error_m"] == 1e-4
    assert fronts.beyond_front(FRONT_ROWS.iloc[[0, 1, 3, 5]], "err", "sim-extended", FREEZING) == []


def test_beating_front_lists_what_beats_a_point_of_extendeds_front():
    """A point beats the front when it is faster *and* more accurate than one of the front's
    points; beyond the front is not enough (faster than all of it with more error, or in a gap
    of its grid), nor is beating a setting that is off extended's own front."""
    out = fronts.beating_front(FRONT_ROWS, "err", "sim-extended", FREEZING)
    assert [(p["system"], p["setting"]) for p in out] == [
        ("pymunk-sleep", "r=2"),
        ("sim-sleep", "q=2"),
    ]
    assert [b["speedup"] for b in out[0]["beats"]] == [4.0]
    assert [b["speedup"] for b in out[1]["beats"]] == [2.0]
    # errors within the tie are equal: no beating
    tied = FRONT_ROWS.copy()
    tied.loc[(tied["system"] == "sim-sleep") & (tied["value"] == 2.0), "err"] = 1e-3 - 5e-7
    assert ("sim-sleep", "q=2") not in [
        (p["system"], p["setting"])
        for p in fronts.beating_front(tied, "err", "sim-extended", FREEZING)
    ]


# ---- end to end --------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fig_tradeoff")
    exp.main(["--quick"], data_dir=folder)
    table = pd.read_csv(folder / f"{exp.NAME}.csv")
    meta = json.loads((folder / f"{exp.NAME}.json").read_text())
    return table, meta, folder


def test_table_has_every_run(quick_run):
    table, meta, _ = quick_run
    assert list(table.columns) == exp.COLUMNS
    assert meta["parameters"]["quick"] is True
    scenes = list(dict.fromkeys(table["scene"]))
    assert scenes == ["pyramid(4)", "landing(4,1,1)"]
    for scene in scenes:
        t = table[table["scene"] == scene]
        for engine, off in exp.OFF.items():
            for role in ("reference", "resolution", "baseline"):
                rows = t[(t["engine"] == engine) & (t["role"] == role)]
                assert len(rows) == 1 and rows["system"].iloc[0] == off, (scene, engine, role)
        for system, parameter, _, default, _, _ in exp.SWEEPS:
            rows = t[(t["system"] == system) & (t["parameter"] == parameter)]
            # every other grid point: k = -2, 0, 2 (extended's rest_speed: -6..2); Box2D's
            # compiled-in sleep rule: its default alone
            expected = {"rest_speed": 5, "time_to_sleep": 1}.get(parameter, 3)
            assert len(rows) == expected, (scene, system, parameter)
            assert rows.loc[rows["is_default"], "value"].tolist() == pytest.approx([default])
            assert rows["value"].is_monotonic_increasing
        # sim-off's solver knobs, on the same axes: every other grid point in quick
        solver = t[t["role"] == "solver"]
        assert set(solver["system"]) == {"sim-off"}
        for parameter, values, default in (
            ("substeps", [1, 4, 16], exp.SIM_SUBSTEPS),
            ("iterations", [1, 4], exp.SIM_ITERATIONS),
            ("impact_iterations", [2, 8], exp.SIM_IMPACT_ITERATIONS),
        ):
            rows = solver[solver["parameter"] == parameter]
            assert rows["value"].tolist() == values, parameter
            assert rows.loc[rows["is_default"], "value"].tolist() == [default]
    # sim's defaults as the baseline runs them, and every run's settings in the metadata
    assert (exp.SIM_SUBSTEPS, exp.SIM_ITERATIONS) == (4, 1)
    settings = meta["parameters"]["system_settings"]
    assert settings["sim-off"]["substeps"] == 4 and settings["sim-off"]["iterations"] == 1
    assert settings["sim-off substeps=16"]["substeps"] == 16
    assert settings["sim-off iterations=4"]["iterations"] == 4
    assert settings["sim-off impact_iterations=2"]["impact_iterations"] == 2
    assert settings["sim-off"]["impact_iterations"] == exp.SIM_IMPACT_ITERATIONS == 8
    assert settings["sim-off reference"]["iterations"] == exp.QUICK["reference_iterations"]["sim"]
    # sim's friction is solved only in its relax sweeps: its reference converges those too
    relax = exp.QUICK["reference_relax_iterations"]
    assert settings["sim-off reference"]["relax_iterations"] == relax > 1
    assert meta["parameters"]["reference_settings"]["sim"]["relax_iterations"] == relax
    assert settings["pymunk"]["iterations"] == 10 and settings["pybullet"]["iterations"] == 50
    # Box2D: its baseline, its reference and its one sleeping point, with what it ran
    assert set(exp.ENGINES) == {"sim", "pymunk", "pybullet", "box2d"}
    assert settings["box2d"]["iterations"] == 8 and settings["box2d"]["sleeping"] is False
    assert settings["box2d-sleep"]["sleeping"] is True
    assert settings["box2d-sleep"]["b2_timeToSleep"] == 0.5
    assert settings["box2d reference"]["iterations"] == 32


def test_freezings_own_error_is_apart_from_the_solvers(quick_run):
    """``freeze_error_max_m`` is the distance from the same engine's sleeping-off run at dt: 0 for
    that run itself, NaN for the solver rows (no freezing), and bound on both sides by the two
    errors against the reference (triangle inequality: |e_setting - e_off| <= d <= e_setting +
    e_off, per body; checked on the largest, which bounds it from above only)."""
    table, _, _ = quick_run
    timed = table[table["role"].isin(["baseline", "sweep"])]
    assert (table.loc[table["role"] == "baseline", "freeze_error_max_m"] == 0.0).all()
    assert table.loc[table["role"] == "solver", "freeze_error_max_m"].isna().all()
    assert timed["freeze_error_max_m"].notna().all()
    for (scene, engine), t in timed.groupby(["scene", "engine"]):
        off = t[t["role"] == "baseline"].iloc[0]
        for _, row in t[t["role"] == "sweep"].iterrows():
            bound = row["pose_error_max_m"] + off["pose_error_max_m"]
            assert row["freeze_error_max_m"] <= bound * (1 + 1e-9), (scene, row["system"])
            if row["awake_fraction"] == 1.0 and engine == "sim":  # froze nothing: same run
                assert row["freeze_error_max_m"] == 0.0, (scene, row["system"], row["value"])
    # freezing that froze a landing body changes the landing's outcome somewhere
    landing = timed[(timed["scene"] == "landing(4,1,1)") & (timed["awake_fraction"] < 1.0)]
    assert (landing["freeze_error_max_m"] > 0).any()


def test_timings_and_replays(quick_run):
    table, _, _ = quick_run
    timed = table[table["role"].isin(["baseline", "sweep", "solver"])]
    assert (timed["wall_s_median"] > 0).all()
    assert (timed["wall_s_min"] <= timed["wall_s_median"]).all()
    assert (timed["repeats"] >= 3).all()
    assert (table.loc[table["role"] == "baseline", "speedup"] == 1.0).all()
    for _, row in timed.iterrows():
        times = [float(x) for x in row["wall_s_all"].split()]
        assert len(times) == row["repeats"]
        assert min(times) == pytest.approx(row["wall_s_min"], rel=1e-5)  # 6 digits in csv
    # every engine is deterministic: the timed run ended exactly where the measured one did
    assert (timed["replay_difference_m"] == 0.0).all()
    assert (
        table.loc[~table["role"].isin(["baseline", "sweep", "solver"]), "wall_s_median"]
        .isna()
        .all()
    )
    # 16 substeps do sixteen times the solver work of 1. Only the extremes are compared: on the
    # quick scenes a step's fixed cost is most of it, and 4 substeps against 1 came out 1.541
    # against 1.564 ms on a loaded machine (CI, 987d6e0); how the time grows with the substeps
    # is the full run's to show, in fig_tradeoff, not a test's
    for scene, t in timed[timed["role"] == "solver"].groupby("scene"):
        walls = t[t["parameter"] == "substeps"].set_index("value")["wall_s_min"]
        assert walls[16] > walls[1], scene


def test_physics_of_the_results(quick_run):
    table, _, _ = quick_run
    errors = ["pose_error_max_m", "pose_error_mean_m", "angle_error_max_rad"]
    ref = table["role"] == "reference"
    assert table.loc[ref, errors].isna().all().all()
    assert (table.loc[~ref, errors] >= 0).all().all()
    assert (table["pose_error_mean_m"] <= table["pose_error_max_m"]).where(~ref, True).all()
    assert (table["penetration_final_m"] <= table["penetration_max_m"] + 1e-15).all()
    # sleeping off, every step solved: at rest the overlap left is at most the slop
    for role in ("reference", "resolution", "baseline"):
        rows = table[table["role"] == role]
        assert (rows["penetration_final_m"] <= SLOP + 1e-4).all(), role
        assert (rows["awake_fraction"] == 1.0).all() and rows["all_asleep_at_s"].isna().all()
    # a body landing at ~3 m/s sinks about v dt (5 cm) into the floor before pymunk or Bullet sees
    # the contact; sim's speculative contacts reach relative speed x dt ahead (sim.tolerances), so
    # it sees the contact a step before impact and the soft contact stops the approach: it sinks
    # less than the slop
    landing_base = table[(table["scene"] == "landing(4,1,1)") & (table["role"] == "baseline")]
    sinks = landing_base.set_index("system")["penetration_max_m"]
    assert sinks["pymunk"] > 0.01 and sinks["pybullet"] > 0.01
    assert sinks["sim-off"] < SLOP
    # every error is also measured against the exact final pose: the largest centre distance is
    # a metric, so a run's two errors differ by at most its reference's own exact error
    assert (table["exact_error_max_m"] >= 0).all()
    for (scene, engine), t in table.groupby(["scene", "engine"]):
        ref = t.loc[t["role"] == "reference", "exact_error_max_m"].item()
        judged = t[t["role"] != "reference"]
        gap = (judged["exact_error_max_m"] - judged["pose_error_max_m"]).abs()
        assert (gap <= ref + 1e-12).all(), (scene, engine)
    # sleeping that never engages (sleep_time 5 s > the 2.5 s run) leaves sim's trajectory intact
    t = table[table["scene"] == "pyramid(4)"]
    never = t[(t["system"] == "sim-sleep") & (t["parameter"] == "sleep_time") & (t["value"] == 5.0)]
    base = t[(t["system"] == "sim-off") & (t["role"] == "baseline")]
    assert never["awake_fraction"].iloc[0] == 1.0
    assert never["pose_error_max_m"].iloc[0] == pytest.approx(
        base["pose_error_max_m"].iloc[0], abs=1e-12
    )
    # extended freezes the pyramid (placed at rest) at once. How much faster its run is, is a
    # timing and belongs to the results: asserted here as "> 1.5", it failed on a faster machine
    # (1.42 and 1.48 on 6f423e6 and on 94d1a4d alike: 150 steps of 10 bodies, where a frozen
    # step's fixed cost is most of a step)
    ext = t[(t["system"] == "sim-extended") & t["is_default"]]
    assert (ext["n_awake_final"] == 0).all() and (ext["awake_fraction"] < 0.1).all()
    assert (ext["speedup_min"] > 0).all() and ext["speedup_min"].map(math.isfinite).all()


def test_solver_sweep_shares_the_axes(quick_run):
    """sim-off's solver settings are measured as the freezing settings are: the default of each
    knob is the baseline's very run (same error, bit for bit), nothing is frozen, and sim's
    reference is more accurate than every setting judged against it."""
    table, _, _ = quick_run
    for scene, t in table.groupby("scene"):
        base = t[(t["system"] == "sim-off") & (t["role"] == "baseline")].iloc[0]
        solver = t[t["role"] == "solver"]
        assert (solver["awake_fraction"] == 1.0).all() and (
            solver["n_awake_final"] == base["n_awake_final"]
        ).all()
        for _, row in solver[solver["is_default"]].iterrows():
            assert row["pose_error_max_m"] == base["pose_error_max_m"], (scene, row["parameter"])
            assert row["penetration_final_m"] == base["penetration_final_m"]
    # on the landing (the scene where sim's settings differ) the reference is closer to the exact
    # final pose than every swept setting
    t = table[table["scene"] == "landing(4,1,1)"]
    ref = t[(t["system"] == "sim-off") & (t["role"] == "reference")]["exact_error_max_m"].item()
    assert (t.loc[t["role"] == "solver", "exact_error_max_m"] > ref).all()


def test_analysis_draws_and_quotes(quick_run, monkeypatch, tmp_path):
    _, _, folder = quick_run
    monkeypatch.setattr(paths, "DATA", folder)
    monkeypatch.setattr(paths, "FIGURES", tmp_path / "figures")
    monkeypatch.setattr(paths, "GENERATED", tmp_path / "generated")
    numbers = analysis.main([])
    svg = tmp_path / "figures" / f"{analysis.NAME}.svg"
    assert svg.exists() and svg.stat().st_size > 20_000
    fronts = pd.read_csv(tmp_path / "generated" / f"{analysis.NAME}.csv")
    assert set(fronts["measure"]) == {"freezing", "pose", "penetration"}
    table = pd.read_csv(folder / f"{exp.NAME}.csv")
    swept = {s for s in analysis.FREEZING if s in set(table["system"])}
    assert swept == {s for s in analysis.FREEZING if s.split("-")[0] in exp.ENGINES}
    assert set(fronts["series"]) == swept | set(analysis.SOLVER_SERIES)
    assert set(fronts.loc[fronts["series"].isin(analysis.SOLVER_SERIES), "system"]) == {"sim-off"}
    # freezing's own panel has no solver series: the solver knobs freeze nothing
    assert (
        not fronts.loc[fronts["measure"] == "freezing", "series"].isin(analysis.SOLVER_SERIES).any()
    )
    for _, front in fronts.groupby(["scene", "measure", "series"]):
        # on a front, more speed costs strictly more error
        assert front["speedup"].is_monotonic_increasing
        assert front["error_m"].diff().dropna().gt(0).all()
    written = json.loads((tmp_path / "generated" / f"{analysis.NAME}.json").read_text())
    assert written["quick"] is True
    pyramid = numbers["scenes"]["pyramid(4)"]
    assert set(pyramid["baseline"]) == set(exp.OFF.values())
    assert set(pyramid["systems"]) == swept
    for entry in pyramid["systems"].values():
        assert entry["default"]["speedup"] > 0
        assert "best_speedup_matching_baseline" in entry
    # what extended's front does not dominate, per measure, with the counts the paper quotes
    for scene, sn in numbers["scenes"].items():
        for short, points in sn["beyond_extended_front"].items():
            counts = sn["beyond_extended_front_counts"][short]
            # each other system's settings once, its defaults once however many sweeps hold them
            rows = table[(table["scene"] == scene) & (table["role"] == "sweep")]
            rows = rows[rows["system"].isin(swept - {analysis.CHALLENGER})]
            defaults = rows["is_default"].astype(str).str.lower() == "true"
            distinct = (~defaults).sum() + rows.loc[defaults, "system"].nunique()
            assert counts["settings"] == distinct < len(rows)
            assert counts["beyond"] == len(points)
            assert counts["faster_than_extended"] + counts["more_accurate_at_its_speed"] == len(
                points
            )
            assert all(p["system"] != analysis.CHALLENGER for p in points)
            # a point that beats a point of the front is beyond it too
            beating = sn["beating_extended_front"][short]
            assert counts["beating"] == len(beating)
            beyond = {(p["system"], p["setting"]) for p in points}
            assert all((p["system"], p["setting"]) in beyond and p["beats"] for p in beating)
    # the two errors apart, per freezing system: its engine's solver's and freezing's own
    t = pd.read_csv(folder / f"{exp.NAME}.csv")
    for scene, sn in numbers["scenes"].items():
        assert set(sn["solver_and_freezing"]) == swept
        for system, split in sn["solver_and_freezing"].items():
            rows = t[(t["scene"] == scene) & (t["system"] == system)]
            engine = rows["engine"].iloc[0]
            base = t[(t["scene"] == scene) & (t["engine"] == engine) & (t["role"] == "baseline")]
            assert split["solver_error_max_m"] == pytest.approx(base["pose_error_max_m"].item())
            default = rows[rows["is_default"].astype(str).str.lower() == "true"].iloc[0]
            assert split["freeze_error_max_m"] == pytest.approx(default["freeze_error_max_m"])
            assert split["worst_freeze_error_max_m"] == pytest.approx(
                rows["freeze_error_max_m"].max()
            )
    # extended freezes a pyramid placed at rest where it stands: no body ends a micron off its
    # placed pose (the exact answer), and it is as close to the reference as the reference is to
    # that pose (the reference, converged in 64 relax sweeps, moves tens of microns)
    ext = pyramid["systems"]["sim-extended"]
    rows = t[(t["scene"] == "pyramid(4)") & (t["system"] == "sim-extended")]
    default = rows[rows["is_default"].astype(str).str.lower() == "true"].iloc[0]
    assert default["exact_error_max_m"] < 1e-6
    reference_moved = pyramid["reference_exact_error_max_m"]["sim-off"]
    assert ext["default"]["pose_error_max_m"] < reference_moved + 1e-6
    assert ext["default"]["awake_fraction"] < 0.1
    # the comparison the paper quotes: every engine at its defaults, sleeping off, on the landing
    table, _, _ = quick_run
    landing = numbers["scenes"]["landing(4,1,1)"]
    comparison = landing["defaults_comparison"]
    base = table[(table["scene"] == "landing(4,1,1)") & (table["role"] == "baseline")]
    for _, row in base.iterrows():
        assert comparison["pose_error_max_m"][row["system"]] == pytest.approx(
            row["pose_error_max_m"]
        )
        assert comparison["exact_error_max_m"][row["system"]] == pytest.approx(
            row["exact_error_max_m"]
        )
    peers = {p: comparison["pose_error_max_m"][p] for p in analysis.PEERS if p in exp.ENGINES}
    assert comparison["best_peer"] == min(peers, key=peers.get)
    assert comparison["sim_off_within_best_peer"] == (
        comparison["pose_error_max_m"]["sim-off"] <= min(peers.values())
    )
    assert [x["value"] for x in landing["solver"]["substeps"]] == [1, 4, 16]
    assert set(comparison["reference_resolution_m"]) == set(exp.OFF.values())


@pytest.mark.xfail(
    strict=True,
    reason=(
        "the issue's done-when on the quick landing only: sim-off's error at its defaults is "
        "0.082 mm against its reference (0.10 mm before the carried split at once), pybullet's "
        "0.022 mm (with the impact sweeps; 2.6 mm without). At full size it holds (sim-off "
        "0.57 mm from the exact pose on 2026-12-06, 0.66 mm in fig_tradeoff of 2026-12-07, "
        "pybullet 1.05 mm: "
        "tests/adapters/test_peers.py::test_sim_lands_a_pile_no_further_from_its_rest_pose_than_"
        "any_peer); see experiments/fig_tradeoff.py"
    ),
)
def test_sim_off_at_defaults_is_as_accurate_as_the_best_peer(quick_run):
    table, _, _ = quick_run
    base = table[(table["scene"] == "landing(4,1,1)") & (table["role"] == "baseline")]
    errors = base.set_index("system")["pose_error_max_m"]
    assert errors["sim-off"] <= min(errors["pymunk"], errors["pybullet"])
