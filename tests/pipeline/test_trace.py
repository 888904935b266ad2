"""Recordings of any run, read back with rerun's own API (rerun.chunk.RrdReader): every system's
entities on one step timeline, the divergence against the reference, the colours of frozen
bodies, the blueprint; and the names a run can be traced by (study.targets)."""

import hashlib
import inspect
import math
import os
import re
import subprocess
import sys
from importlib.metadata import version
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from rerun.chunk import RrdReader

import sim
from analysis import trace
from study import common, scenarios, targets
from study.extremes.axes import AXES
from study.peers import make_runner

RERUN = Path(sys.executable).with_name("rerun")
ENV = {**os.environ, "RERUN_ANALYTICS": "0"}


def read(path):
    """entity path -> DataFrame of its rows on the step timeline, sorted by step (static rows,
    which have no step, under the key "<entity>#static")."""
    parts = {}
    for chunk in RrdReader(path).stream().to_chunks():
        df = chunk.to_record_batch().to_pandas()
        key = str(chunk.entity_path) + ("" if "step" in df.columns else "#static")
        parts.setdefault(key, []).append(df)
    out = {}
    for key, dfs in parts.items():
        df = pd.concat(dfs, ignore_index=True)
        if "step" in df.columns:
            df = df.dropna(subset=["step"]).sort_values("step", kind="stable")
        out[key] = df.reset_index(drop=True)
    return out


def scalars(entities, path):
    """(steps, values) of a Scalars entity."""
    df = entities[path]
    return df["step"].to_numpy(int), np.array([v[0] for v in df["Scalars:scalars"]])


def rgba(packed):
    """rerun's packed 0xRRGGBBAA colour -> (r, g, b)."""
    packed = int(packed)
    return (packed >> 24) & 255, (packed >> 16) & 255, (packed >> 8) & 255


@pytest.fixture(scope="module")
def box_recording(tmp_path_factory):
    """single_box (placed at rest) under sim-off twice, sim-extended and pymunk-sleep, 60 steps."""
    path = tmp_path_factory.mktemp("trace") / "box.rrd"
    target = targets.resolve(
        "single_box", systems=["sim-off", "sim-off", "sim-extended", "pymunk-sleep"]
    )
    tracks = trace.record(target, path, steps=60)
    return path, read(path), tracks


def test_every_system_is_recorded_on_one_step_timeline(box_recording):
    path, entities, tracks = box_recording
    check = subprocess.run(
        [str(RERUN), "rrd", "verify", str(path)], capture_output=True, text=True, env=ENV
    )
    assert check.returncode == 0, check.stderr
    assert [t.path for t in tracks] == ["sim-off", "sim-off_2", "sim-extended", "pymunk-sleep"]
    assert not any(t.stopped for t in tracks)
    for s in ("sim-off", "sim-off_2", "sim-extended", "pymunk-sleep"):
        for entity in (
            f"/systems/{s}/bodies",
            f"/systems/{s}/contacts",
            f"/systems/{s}/impulses",
            f"/timeline/awake/{s}",
            f"/timeline/kinetic_energy/{s}",
            f"/timeline/divergence_m/{s}",
            f"/timeline/divergence_rad/{s}",
        ):
            steps = entities[entity]["step"].to_numpy(int)
            assert steps.tolist() == list(range(61)), entity  # step 0 and every step
        assert entities[f"/timeline/step_ms/{s}"]["step"].tolist() == list(range(1, 61))
        assert f"/systems/{s}/static#static" in entities  # the floor, once
        time_s = entities[f"/systems/{s}/bodies"]["time"]
        assert time_s.iloc[-1] == pd.Timedelta(seconds=1.0)  # 60 steps of 1/60 s
    assert "/about#static" in entities


def test_divergence_is_zero_against_itself_and_not_against_a_peer(box_recording):
    _, entities, _ = box_recording
    for s in ("sim-off", "sim-off_2"):  # the reference, and sim-off run again
        _, d = scalars(entities, f"/timeline/divergence_m/{s}")
        _, a = scalars(entities, f"/timeline/divergence_rad/{s}")
        assert np.all(d == 0.0) and np.all(a == 0.0), s
    _, d = scalars(entities, "/timeline/divergence_m/pymunk-sleep")
    assert d[0] == 0.0 and d.max() > 0.0  # same start; Chipmunk settles its own way


def test_frozen_and_asleep_bodies_take_the_frozen_colour(box_recording):
    _, entities, _ = box_recording
    frozen = tuple(trace.body_colors([sim.State.ROTATION_STABLE], [True])[0])
    asleep = tuple(trace.body_colors([sim.State.SLEEPING], [True])[0])
    free = tuple(trace.body_colors([sim.State.FREE], [False])[0])
    assert frozen == tuple(int(c * trace.FROZEN_SHADE) for c in trace.STATE_COLORS[2])
    ext = entities["/systems/sim-extended/bodies"]["LineStrips2D:colors"]
    assert rgba(ext.iloc[0][0]) == free  # the start state: FREE
    assert rgba(ext.iloc[-1][0]) == frozen  # certified at rest: frozen
    pm = entities["/systems/pymunk-sleep/bodies"]["LineStrips2D:colors"]
    assert rgba(pm.iloc[0][0]) == free
    assert rgba(pm.iloc[-1][0]) == asleep  # Chipmunk's 0.5 s of idling passed
    off = entities["/systems/sim-off/bodies"]["LineStrips2D:colors"]
    assert {rgba(c[0]) for c in off} == {free}  # never frozen
    # extended says why a body is awake: not yet tested at step 0, frozen (no label) after
    why = entities["/systems/sim-extended/bodies"]["LineStrips2D:labels"]
    assert list(why.iloc[0]) == ["untested"] and list(why.iloc[-1]) == [""]
    assert "LineStrips2D:labels" not in entities["/systems/sim-off/bodies"]
    _, awake = scalars(entities, "/timeline/awake/sim-extended")
    assert awake[0] == 1 and awake[-1] == 0


def test_events_and_outlines_follow_the_runs(box_recording):
    _, entities, _ = box_recording
    texts = [t[0] for t in entities["/events/sim-extended"]["TextLog:text"]]
    assert any("FREE -> ROTATION_STABLE" in t for t in texts), texts
    texts = [t[0] for t in entities["/events/pymunk-sleep"]["TextLog:text"]]
    assert texts == ["pymunk-sleep step 31: body 0 fell asleep"]
    strips = entities["/systems/sim-off/bodies"]["LineStrips2D:strips"].iloc[-1]
    outline = np.array([tuple(p) for p in strips[0]])
    assert np.allclose(outline[0], outline[-1])  # closed
    assert outline[:, 1].min() == pytest.approx(0.0, abs=0.01)  # on the floor
    impulses = entities["/systems/sim-off/impulses"]["Arrows2D:vectors"].iloc[-1]
    total = sum(tuple(v)[1] for v in impulses) / 0.5  # arrow-scale 0.5 m per N s
    assert total == pytest.approx(1.0 * 9.81 / 60, rel=1e-3)  # m g dt


def blueprint_views(path):
    """The views of the recording's blueprint: [(kind, display name, origin)]."""
    reader = RrdReader(path)
    (blueprint,) = reader.blueprints()
    views = []
    for chunk in reader.stream(store=blueprint).to_chunks():
        df = chunk.to_record_batch().to_pandas()
        if "ViewBlueprint:space_origin" in df.columns:
            row = df.iloc[-1]
            views.append(
                (
                    row["ViewBlueprint:class_identifier"][0],
                    row["ViewBlueprint:display_name"][0],
                    row["ViewBlueprint:space_origin"][0],
                )
            )
    return views


def test_the_blueprint_lays_out_every_system(box_recording):
    path, _, _ = box_recording
    views = blueprint_views(path)
    scenes = {(name, origin) for kind, name, origin in views if kind == "2D"}
    assert scenes == {
        ("sim-off", "systems/sim-off"),
        ("sim-off_2", "systems/sim-off_2"),
        ("sim-extended", "systems/sim-extended"),
        ("pymunk-sleep", "systems/pymunk-sleep"),
    }
    series = {origin for kind, _, origin in views if kind == "TimeSeries"}
    assert series == {
        "timeline/divergence_m",
        "timeline/awake",
        "timeline/kinetic_energy",
        "timeline/step_ms",
    }
    assert ("TextLog", "events", "events") in views


def test_every_engine_reports_its_contact_impulses():
    """runner.contacts(): on a resting 2-box stack the floor carries m g dt per step in every
    engine (pymunk gives a pair's total, split evenly; pybullet a force, times dt; Box2D its
    manifold points' impulses)."""
    scene = sim.scenes.stack(2)
    weight_impulse = 2 * 1.0 * 9.81 / 60  # 2 unit boxes of density 1, N s
    for system in ("sim-off", "pymunk", "pybullet", "box2d"):
        with make_runner(system, scene) as runner:
            runner.step(60)
            c = runner.contacts()
            on_floor = np.abs(c["point"][:, 1]) < 0.05
            assert c["point"].shape == c["normal"].shape == (len(c["normal_impulse"]), 2)
            assert c["normal_impulse"][on_floor].sum() == pytest.approx(weight_impulse, rel=1e-3), (
                system
            )


def test_impulse_arrows_follow_one_convention_in_every_engine(tmp_path):
    """stack(2): each arrow is the impulse on the pair's upper body (the floor lowest), so every
    arrow points up and they add up to 3 m g dt (two boxes on the floor, one on box 0), in every
    engine. Before, pymunk's and Box2D's arrows pointed down, into the floor and box 0."""
    systems = ["sim-off", "pymunk", "pybullet", "box2d"]
    target = targets.resolve("stack", systems=systems, size=2)
    trace.record(target, tmp_path / "stack.rrd", steps=30, arrow_scale=0.5)
    entities = read(tmp_path / "stack.rrd")
    for s in systems:
        arrows = np.array(
            [tuple(v) for v in entities[f"/systems/{s}/impulses"]["Arrows2D:vectors"].iloc[-1]]
        )
        assert np.all(arrows[:, 1] >= -1e-9), (s, arrows)
        assert arrows[:, 1].sum() / 0.5 == pytest.approx(3 * 9.81 / 60, rel=2e-3), s


# ---- names -------------------------------------------------------------------------------------
def test_a_scene_file_traces_by_its_path(tmp_path):
    scene = sim.scenes.stack(3)
    scene.to_file(tmp_path / "three.toml")
    target = targets.resolve(str(tmp_path / "three.toml"), systems=["sim-sleep"])
    assert target.kind == "file" and len(target.scene.bodies) == 3
    out = trace.main(
        [
            str(tmp_path / "three.toml"),
            "--systems",
            "sim-sleep",
            "--steps",
            "5",
            "--out",
            str(tmp_path / "three.rrd"),
        ]
    )
    entities = read(out)
    assert len(entities["/systems/sim-sleep/bodies"]) == 6


def test_an_unknown_name_lists_what_is_available(capsys):
    with pytest.raises(SystemExit) as exc:
        trace.main(["no_such_scene"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    for word in (
        "scene builders:",
        "pyramid",
        "scenarios:",
        "slope_creep",
        ".toml",
        "table_failures/<scenario>",
        "table_extremes/<axis>/<value>",
        "knife_edge",
    ):
        assert word in err, word
    for bad, words in (
        ("table_extremes/dt/0.5", "the rows are"),
        ("table_extremes/no_axis/1", "axes:"),
        ("table_failures/nothing", "scenarios:"),
        ("table_failures/slope_creep/3", "scenarios:"),
    ):
        with pytest.raises(ValueError, match=words):
            targets.resolve(bad)
    with pytest.raises(ValueError, match="no system 'box9'"):
        targets.resolve("table_failures/slope_creep", systems=["box9"])
    with pytest.raises(ValueError, match="unknown system"):
        targets.resolve("pyramid", systems=["sim-warp"])


def test_a_failure_row_runs_as_its_table_does():
    target = targets.resolve("table_failures/slope_creep")
    scenario = scenarios.get("slope_creep")
    assert [s.name for s in target.systems] == list(common.SYSTEMS)
    assert target.dt == common.DT
    assert target.steps == round(scenario.duration(scenario.build()) / common.DT)
    assert target.scene.to_dict() == scenario.build().to_dict()


def test_every_extremes_cell_runs_as_its_table_does():
    """The cell's systems, scene, dt, steps and settings are the table's own sweep tasks."""
    from experiments import table_extremes as table  # the script: tests may import it
    from study.extremes.scenes import scene_of

    config = table.FULL
    assert targets.THRESHOLD_BISECTIONS == config["bisection_steps"]
    assert targets.PYBULLET_MAX_BODIES == config["pybullet_max_bodies"]
    thresholds = {p: {"v_star": targets.threshold(p), "note": ""} for p in ("paper", "extended")}
    tasks, not_run = table.sweep_tasks(config, thresholds)
    cells = {}
    for task in tasks:
        cells.setdefault((task["axis"], task["value"]), []).append(task)
    skipped = {(a, v, s): why for a, v, s, why in not_run}
    for (axis, value), runs in cells.items():
        target = targets.resolve(f"table_extremes/{axis}/{value}")
        by_name = {s.name: s for s in target.systems}
        assert target.dt == runs[0]["dt"] and target.steps == runs[0]["steps"]
        for task in runs:
            system = by_name[task["system"]]
            assert system.runner == task["runner"] and not system.not_run
            expected = dict(task["settings"])
            if task["iterations"] is not None:
                expected["iterations"] = task["iterations"]
            assert system.settings == expected, (axis, value, task["system"])
            scene = system.scene or target.scene
            assert scene.to_dict() == scene_of(task["scene"]).to_dict()
        for name, system in by_name.items():
            if (axis, value, name) in skipped:
                assert system.not_run, (axis, value, name)
        assert len(by_name) == len(runs) + sum(1 for a, v, _ in skipped if (a, v) == (axis, value))


def test_a_rounded_value_names_its_row():
    assert targets.match_value("dt", "0.03333") == 1 / 30
    assert targets.match_value("knife_edge", "0") == 0.0
    assert targets.match_value("impact_threshold", "-1e-6") == -1e-6
    assert targets.resolve("table_extremes/dt/0.0333").label == "table_extremes/dt/0.03333"
    for axis, record in AXES.items():  # every label names its own row again
        for value in record.values:
            label = targets.cell_label(axis, value)
            assert targets.match_value(axis, label.rsplit("/", 1)[1]) == value


def test_a_system_that_cannot_run_is_logged_not_dropped(tmp_path):
    target = targets.resolve("single_box", systems=["sim-off", "pymunk"])
    target.systems[1].not_run = "a reason"
    tracks = trace.record(target, tmp_path / "x.rrd", steps=3)
    assert tracks[1].stopped == "not run: a reason"
    entities = read(tmp_path / "x.rrd")
    assert "/systems/pymunk/bodies" not in entities
    assert [t[0] for t in entities["/events/pymunk"]["TextLog:text"]] == [
        "pymunk not run: a reason"
    ]
    assert len(entities["/systems/sim-off/bodies"]) == 4


def test_a_long_run_is_recorded_every_k_steps_and_at_its_last(tmp_path):
    """10 steps every 4: frames at 0, 4, 8 and 10 (the last step was dropped: steps // every
    frames), the step time of the last frame per step of its 2."""
    target = targets.resolve("single_box", systems=["sim-off"])
    trace.record(target, tmp_path / "x.rrd", steps=10, every=4)
    entities = read(tmp_path / "x.rrd")
    assert entities["/systems/sim-off/bodies"]["step"].tolist() == [0, 4, 8, 10]
    assert entities["/timeline/step_ms/sim-off"]["step"].tolist() == [4, 8, 10]
    assert "(recorded every 4 and at the last)" in about(entities)
    with pytest.raises(ValueError, match="every"):
        trace.record(target, tmp_path / "y.rrd", steps=10, every=0)
    assert math.ceil(100000 / trace.MAX_FRAMES) == 50  # long_run's default: every 50 steps


def about(entities):
    """The text of a recording's about page."""
    return entities["/about#static"]["TextDocument:text"].iloc[-1][0]


def test_the_about_page_states_the_steps_run_and_the_provenance(tmp_path):
    """--steps 60 on a 6 s row: the page said the row's 360 steps. It records what a results
    file records (study.metadata.collect): the commit and whether the tree is dirty, package
    versions, machine; it had the commit alone."""
    target = targets.resolve("table_failures/slope_creep", systems=["pymunk-sleep"])
    assert target.steps == 360
    trace.record(target, tmp_path / "x.rrd", steps=60)
    text = about(read(tmp_path / "x.rrd"))
    assert "; 60 steps (recorded every 1); reference pymunk-sleep" in text
    # the row's step count as a count of steps (a bare "360" also turns up in the commit hash
    # the page records: 0f2372464c360cf1... failed this test on 730b07e)
    assert "360 steps" not in text
    assert '"dirty": ' in text and '"code_changed_during_run": false' in text
    assert f'"rerun-sdk": "{version("rerun-sdk")}"' in text and '"cpu": ' in text
    assert '"steps": 60' in text  # the run's parameters


def test_an_interrupted_recording_leaves_the_old_file(tmp_path, monkeypatch, capsys):
    """Ctrl-C at frame 3 of a rerun: the good recording stays whole (the partial one overwrote
    it); what the interrupted run recorded is in the partial file beside it, which the
    error names, and the command line says so in one line with status 130."""
    target = targets.resolve("single_box", systems=["pymunk"])
    out = tmp_path / "box.rrd"
    trace.record(target, out, steps=5)
    good = out.read_bytes()

    def interrupt(k, frames):
        if k == 3:
            raise KeyboardInterrupt

    try:
        trace.record(targets.resolve("single_box", systems=["pymunk"]), out, 50, progress=interrupt)
    except BaseException as exc:  # old code: the KeyboardInterrupt itself
        raised = exc
    assert out.read_bytes() == good
    assert isinstance(raised, trace.Interrupted) and isinstance(raised.__cause__, KeyboardInterrupt)
    assert re.search(r"interrupted at step 3 of 50: .*box.rrd left as it was", str(raised))
    partial = tmp_path / "box.partial.rrd"
    assert read(partial)["/systems/pymunk/bodies"]["step"].tolist() == [0, 1, 2, 3]
    trace.record(target, out, steps=7)  # a run to its end replaces the file, partial gone
    assert read(out)["/systems/pymunk/bodies"]["step"].tolist() == list(range(8))
    assert not partial.exists()

    monkeypatch.setattr(trace, "_progress", lambda label: interrupt)
    with pytest.raises(SystemExit) as exc:
        trace.main(["single_box", "--systems", "pymunk", "--steps", "9", "--out", str(out)])
    assert exc.value.code == 130
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith("python -m analysis.trace: single_box interrupted at step 3 of 9")
    assert str(partial) in err


def test_different_runs_get_different_default_names(tmp_path, monkeypatch):
    """pyramid at sizes 3 and 4, at another dt, under other systems, and two scene.toml files
    in different folders all went to pyramid.rrd or scene.rrd, each overwriting the last."""
    monkeypatch.setattr(trace, "RECORDINGS", tmp_path / "recordings")
    for folder, scene in (("a", sim.scenes.pyramid(2)), ("b", sim.scenes.stack(2))):
        (tmp_path / folder).mkdir()
        scene.to_file(tmp_path / folder / "scene.toml")
    runs = [
        ["pyramid", "--size", "3"],
        ["pyramid", "--size", "4"],
        ["pyramid", "--size", "3", "--dt", str(1 / 240)],
        ["pyramid", "--size", "3", "--systems", "pybullet,pymunk"],
        ["pyramid", "--size", "3", "--every", "2"],
        [str(tmp_path / "a" / "scene.toml")],
        [str(tmp_path / "b" / "scene.toml")],
    ]
    paths = [
        trace.main([*run, "--steps", "4"] + (["--systems", "pymunk"] * ("--systems" not in run)))
        for run in runs
    ]
    assert len(set(paths)) == len(runs), paths
    assert paths[0].name == "pyramid__size3__pymunk__steps4.rrd"
    assert paths[3].name == "pyramid__size3__pybullet+pymunk__steps4.rrd"
    # every digit of a dt that six do not give exactly (0.004 and 0.0040000001 shared "dt0.004")
    assert paths[2].name == "pyramid__size3__dt0.004166666666666667__pymunk__steps4.rrd"
    near = [targets.resolve("pyramid", size=2, dt=dt).file_stem() for dt in (0.004, 0.0040000001)]
    assert near == ["pyramid__size2__dt0.004", "pyramid__size2__dt0.0040000001"]
    assert paths[5].name.startswith("scene-") and paths[6].name.startswith("scene-")
    assert (
        targets.resolve("table_failures/slope_creep").file_stem() == "table_failures__slope_creep"
    )


def test_a_refused_reference_is_replaced_by_the_next_system_and_said(tmp_path, capsys):
    """Box2D refuses dt 0.5 s: with it named first, no divergence was logged for any system and
    nothing said why. The first system that runs is the reference, and the events, the about
    page and stderr say so."""
    target = targets.resolve("pyramid", systems=["box2d", "pymunk", "pybullet"], size=3, dt=0.5)
    tracks = trace.record(target, tmp_path / "x.rrd", steps=5)
    assert tracks[0].stopped.startswith("not run: refused (box2d: dt 0.5 s is too long")
    entities = read(tmp_path / "x.rrd")
    for s, zero in (("pymunk", True), ("pybullet", False)):
        steps, d = scalars(entities, f"/timeline/divergence_m/{s}")
        assert steps.tolist() == list(range(6))
        assert np.all(d == 0.0) if zero else d.max() > 0.0
    (note,) = [t[0] for t in entities["/events/recording"]["TextLog:text"]]
    assert "divergence is measured against pymunk, the first system that runs" in note
    assert note in about(entities) and note in capsys.readouterr().err


@pytest.mark.parametrize(
    "argv, refused",
    [
        (["seed_fig1", "--arrow-scale", "nan"], "--arrow-scale: must be a finite number > 0"),
        (["seed_fig1", "--arrow-scale", "-0.5"], "--arrow-scale: must be a finite number > 0"),
        (["seed_fig1", "--arrow-scale", "inf"], "--arrow-scale: must be a finite number > 0"),
        # --out was ignored with --table (one file per row, into --out-dir)
        (["--table", "table_failures", "--out", "x.rrd"], "--table [--out-dir DIR]"),
    ],
)
def test_a_meaningless_option_is_refused_in_one_line(argv, refused, tmp_path, capsys):
    # an arrow scale of nan drew no arrows, a negative one reversed them, silently
    with pytest.raises(SystemExit) as exc:
        trace.main([*argv, "--out-dir", str(tmp_path)] if "--table" in argv else argv)
    assert exc.value.code == 2
    assert refused in capsys.readouterr().err.strip().splitlines()[-1]
    assert not list(tmp_path.iterdir())  # nothing recorded


def test_size_is_only_a_size_and_systems_must_name_one(capsys):
    """--size went to the builder's first argument, whatever it was: seed_fig1 (none) raised a
    TypeError, seed_fig3 took it as the speed, single_box as its width in m. "--systems ,"
    fell back to the default systems."""
    for builder in ("seed_fig1", "seed_fig3", "single_box"):
        with pytest.raises(ValueError, match=f"^{builder} has no size argument .--size sets"):
            targets.resolve(builder, size=3)
    for builder, parameter in targets.SIZE_PARAMETERS.items():
        assert next(iter(inspect.signature(sim.scenes.BUILDERS[builder]).parameters)) == parameter
        assert targets.resolve(builder, size=3).scene.params[parameter] == 3
    with pytest.raises(ValueError, match="the list of systems is empty"):
        targets.resolve("pyramid", systems=[])
    with pytest.raises(ValueError, match="the list of systems is empty"):
        targets.resolve("table_failures/slope_creep", systems=[])
    for argv in (["pyramid", "--systems", ","], ["seed_fig3", "--size", "5"]):
        with pytest.raises(SystemExit) as exc:
            trace.main(argv)
        assert exc.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()[-1]
        assert err in (
            "python -m analysis.trace: error: --systems ',' names no system",
            "python -m analysis.trace: error: seed_fig3 has no size argument (--size sets the "
            "body count of rest_row, stack, pyramid, drop, arch)",
        ), err


@pytest.mark.parametrize(
    "case", ["a name too long", "a folder", "under a file", "in /proc", "table under a file"]
)
def test_an_output_that_cannot_be_written_is_one_line_before_anything_runs(
    tmp_path, case, capsys, monkeypatch
):
    """A folder given as --out failed only at the final rename, after the whole run, and left its
    partial file; a file where a folder must be, or a place nothing can be written, came out as a
    traceback (a reviewer, 2026-12-07)."""
    monkeypatch.setattr(trace, "RECORDINGS", tmp_path / "recordings")
    (tmp_path / "afile").write_text("")
    (tmp_path / "adir").mkdir()
    argv = {
        "a name too long": ["single_box", "--out", str(tmp_path / ("n" * 250 + ".rrd"))],
        "a folder": ["single_box", "--out", str(tmp_path / "adir")],
        "under a file": ["single_box", "--out", str(tmp_path / "afile" / "x.rrd")],
        "in /proc": ["single_box", "--out", "/proc/freeze2d-test.rrd"],
        "table under a file": ["--table", "table_failures", "--out-dir", str(tmp_path / "afile")],
    }[case]
    ran = []
    monkeypatch.setattr(trace.Recorder, "run", lambda self, progress: ran.append(1))
    with pytest.raises(SystemExit) as stop:
        trace.main([*argv, "--systems", "sim-off"] if case != "table under a file" else argv)
    assert stop.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("python -m analysis.trace: error: cannot "), err
    assert not ran
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["adir", "afile"]


def test_a_peer_refusing_a_non_finite_velocity_stops_its_own_track_only(tmp_path, monkeypatch):
    """A peer refuses to hand out a non-finite observable (study.peers.guards); the recording
    reads velocities too (kinetic energy): a pymunk run whose velocities went NaN while its
    poses were still finite killed the whole recording, the other systems' tracks with it."""
    from study.peers.pymunk_runner import PymunkRunner

    def refuse(self):
        if self.step_count >= 2:
            raise sim.SimulationError(f"pymunk: body 0 is non-finite after step {self.step_count}")
        return np.zeros((self.scene.n_bodies, 2))

    monkeypatch.setattr(PymunkRunner, "velocities", property(refuse))
    target = targets.resolve("single_box", systems=["sim-off", "pymunk"])
    tracks = trace.record(target, tmp_path / "a.rrd", steps=4, every=1)
    stopped = {t.system.name: t.stopped for t in tracks}
    assert stopped["sim-off"] == "" and "non-finite state" in stopped["pymunk"]
    assert (tmp_path / "a.rrd").exists()


@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
def test_a_cell_value_that_is_not_a_finite_number_is_refused_not_read_as_the_first_row(value):
    """nan and inf compare false with every row, so the "no row there" test never fired and
    table_extremes/knife_edge/nan recorded the 1e-3 row (a reviewer, 2026-12-07)."""
    for axis in ("knife_edge", "dt"):
        with pytest.raises(ValueError, match="the value must be a finite number; the rows are"):
            targets.resolve(f"table_extremes/{axis}/{value}")


@pytest.mark.parametrize(
    "argv, refused",
    [
        # --out-dir without --table was ignored: the recording went to results/recordings/
        (["single_box", "--out-dir", "{tmp}"], "give a NAME [--out FILE] or --table"),
        # a one-system or shortened table run overwrote the whole rows `make reproduce` keeps
        (["--table", "table_failures", "--systems", "pymunk"], "give --out-dir DIR"),
        (["--table", "table_failures", "--steps", "3"], "give --out-dir DIR"),
        # "steps must be an integer >= 1, got 0", of a --steps never given
        (["slope_creep", "--dt", "100"], "slope_creep: dt 100 s is longer than the scenario's"),
    ],
)
def test_an_option_that_would_be_ignored_or_misread_is_refused_in_one_line(
    argv, refused, tmp_path, capsys, monkeypatch
):
    monkeypatch.setattr(trace, "RECORDINGS", tmp_path / "recordings")
    with pytest.raises(SystemExit) as exc:
        trace.main([a.replace("{tmp}", str(tmp_path / "od")) for a in argv])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()  # argparse's usage, then one line
    assert refused in err[-1] and err[-1].startswith("python -m analysis.trace: error: "), err
    assert not list(tmp_path.rglob("*"))  # nothing recorded


def test_a_scene_file_that_cannot_be_read_is_one_line(tmp_path, capsys):
    """Scene.from_file raises OSError for a file that exists but cannot be read; the trace
    caught ValueError only: a traceback (a reviewer read /proc/self/mem through a link)."""
    link = tmp_path / "mem.toml"
    link.symlink_to("/proc/self/mem")
    with pytest.raises(SystemExit) as exc:
        trace.main([str(link), "--systems", "sim-off", "--out", str(tmp_path / "x.rrd")])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"cannot read scene file {link}" in err[0], err


def test_the_provenance_names_each_scene_that_ran_and_a_scene_files_path_and_hash(tmp_path):
    """The impact threshold axis throws at each policy's own threshold, and the about page gave
    only the target's scene (sim-paper's 11.86 m/s for sim-extended's run at 2.58); a scene
    file's hash was only in the default file name, so with --out a hand-edited file looked like
    its builder's."""
    target = targets.resolve(
        "table_extremes/impact_threshold/1e-6", systems=["sim-paper", "sim-extended"]
    )
    own = {s.name: s.scene for s in target.systems if s.scene is not None}
    assert list(own) == ["sim-extended"]  # sim-paper runs the target's scene
    assert json_text(own["sim-extended"].params) != json_text(target.scene.params)
    trace.record(target, tmp_path / "x.rrd", steps=2)
    text = about(read(tmp_path / "x.rrd"))
    for name, scene in own.items():
        section = text.split(f"## {name}\n", 1)[1]
        assert section.startswith(f"\nits own scene `{scene.name}` {json_text(scene.params)}")
    path = tmp_path / "mine.toml"
    sim.scenes.stack(2).to_file(path)
    target = targets.resolve(str(path), systems=["sim-off"])
    trace.record(target, tmp_path / "y.rrd", steps=2)
    text = about(read(tmp_path / "y.rrd"))
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    assert f'"path": "{path.resolve()}"' in text and f'"sha256": "{digest}"' in text


def json_text(params):
    import json

    from study.metadata import jsonable

    return json.dumps(jsonable(params))


def test_with_every_k_sims_events_sit_at_their_own_steps_and_a_peers_say_between_frames(tmp_path):
    """With --every 100 a box freezing at step 1 was logged at step 100 saying "step 1", and a
    pymunk body falling asleep at step 31 was said to at "step 100"."""
    target = targets.resolve("stack", systems=["sim-extended", "pymunk-sleep"], size=3)
    trace.record(target, tmp_path / "x.rrd", steps=200, every=100)
    entities = read(tmp_path / "x.rrd")
    events = entities["/events/sim-extended"]
    for step, (text,) in zip(events["step"], events["TextLog:text"]):
        assert text.startswith(f"sim-extended step {int(step)}: "), (step, text)
    (asleep,) = [t[0] for t in entities["/events/pymunk-sleep"]["TextLog:text"]][:1]
    assert asleep.startswith("pymunk-sleep by step 100 (since step 0): "), asleep
