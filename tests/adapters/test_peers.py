"""One interface for every system, and the four engines with freezing and sleeping off (sim
freeze off, pymunk, pybullet, box2d) against the same known answers and against each other.

Where a peer cannot reach sim's answer the test says so with the measured figure or the exact
discrete answer: sim integrates over 4 substeps per step (Bullet, Chipmunk and Box2D over one),
pymunk moves positions before velocities (free fall trails by g dt t, a launched body runs v0 dt
further), Bullet's bounce overshoots e^2 h by ~10 % (tests/adapters/test_pybullet_runner.py), and
Box2D
computes in float32 and its bounce falls ~6 % short (tests/adapters/test_box2d_runner.py).
"""

import ast
import json
import math
import pathlib

import numpy as np
import pandas as pd
import pytest

import sim
from conftest import tilted_box
from experiments import peer_agreement
from sim.validation import INITIAL_ITERATIONS
from study.common import build
from study.metadata import jsonable
from study.peers import (
    DEFAULT_ITERATIONS,
    SIM_DEFAULT_SUBSTEPS,
    SYSTEMS,
    Runner,
    SimRunner,
    engine_of,
    make_runner,
    solver_summary,
)

DT = 1 / 60
G = 9.81
#: Every engine with freezing and sleeping off.
SYSTEMS_OFF = ("sim-off", "pymunk", "pybullet", "box2d")
#: Relative round-off of positions and velocities: Box2D computes in float32 (measured in 1 s of
#: free fall from 10 m: position 1.7e-7, velocity 4.4e-7), the others in float64.
ROUND_OFF = {"box2d": 2e-6}
ROOT = pathlib.Path(__file__).resolve().parents[2]


def _build(system, scene, **kwargs):
    """make_runner, skipping nothing: a sim policy that has not landed raises
    NotImplementedError inside sim.World, and the caller decides what that means."""
    return make_runner(system, scene, dt=DT, **kwargs)


# ---- the interface ---------------------------------------------------------------------------
@pytest.mark.parametrize("system", SYSTEMS)
def test_every_system_satisfies_the_runner_interface(system):
    scene = sim.scenes.stack(2)
    try:
        runner = _build(system, scene)
    except NotImplementedError:
        assert system.startswith("sim-") and system != "sim-off"  # policies still to land
        return
    with runner:
        assert isinstance(runner, Runner)
        assert runner.name == system
        assert runner.settings["system"] == system
        assert runner.settings["dt"] == DT and runner.dt == DT
        assert runner.settings["iterations"] == DEFAULT_ITERATIONS[engine_of(system)]
        json.dumps(jsonable(runner.settings))  # storable as metadata
        assert runner.step_count == 0 and runner.time == 0.0
        runner.step(3)
        assert runner.step_count == 3 and runner.time == pytest.approx(3 * DT)
        n = len(scene.bodies)
        for name, shape in (
            ("positions", (n, 2)),
            ("angles", (n,)),
            ("velocities", (n, 2)),
            ("angular_velocities", (n,)),
            ("asleep", (n,)),
        ):
            value = getattr(runner, name)
            assert isinstance(value, np.ndarray) and value.shape == shape, name
        assert runner.asleep.dtype == bool
        if system in SYSTEMS_OFF:
            assert not runner.asleep.any()  # sleeping off: nobody sleeps


@pytest.mark.parametrize("system", SYSTEMS_OFF)
def test_iterations_can_be_set_and_are_recorded(system):
    with _build(system, sim.scenes.single_box(), iterations=7) as runner:
        assert runner.settings["iterations"] == 7


def test_sim_runner_passes_the_policy_and_settings_through():
    runner = _build("sim-off", sim.scenes.stack(2), slop=0.002)
    assert isinstance(runner, SimRunner) and runner.world.freeze == "off"
    assert runner.world.slop == 0.002 and runner.settings["slop"] == 0.002
    for policy in ("sleep", "paper", "extended"):
        try:
            other = _build(f"sim-{policy}", sim.scenes.stack(2))
        except NotImplementedError:
            continue
        assert other.world.freeze == policy
        np.testing.assert_array_equal(other.asleep, other.world.states != sim.State.FREE)


def test_sim_runs_at_the_worlds_own_defaults_and_records_every_setting():
    """No iterations given: sim.World's own defaults (1 biased sweep per substep, 4 substeps),
    and ``settings`` holds the soft step's knobs as the World has them."""
    import inspect

    defaults = inspect.signature(sim.World).parameters
    runner = _build("sim-off", sim.scenes.stack(2))
    w, s = runner.world, runner.settings
    assert DEFAULT_ITERATIONS["sim"] == defaults["iterations"].default == w.iterations
    assert SIM_DEFAULT_SUBSTEPS == defaults["substeps"].default == w.substeps
    for key in (
        "substeps",
        "relax_iterations",
        "impact_iterations",
        "contact_hertz",
        "damping_ratio",
        "push_speed",
        "load_time",
        "slop",
        "speculative_distance",
        "restitution_threshold",
        "warm_starting",
        "continuous",
        "overlap_tolerance",
    ):
        assert s[key] == getattr(w, key) == defaults[key].default, key
    # None: the World's choice, recorded as the count it made (warm starting is on)
    assert defaults["initial_iterations"].default is None
    assert s["initial_iterations"] == w.initial_iterations == INITIAL_ITERATIONS
    assert s["fast_paths"] == w.fast_paths
    for removed in ("position_iterations", "baumgarte", "max_correction"):
        assert removed not in s
    assert s["contact_hertz_base"] > 0
    assert solver_summary(s) == {
        "substeps": w.substeps,
        "iterations": w.iterations,
        "relax_iterations": w.relax_iterations,
        "contact_sweeps_per_step": w.substeps * (w.iterations + w.relax_iterations),
    }
    other = _build("sim-off", sim.scenes.stack(2), substeps=2, damping_ratio=10.0)
    assert other.settings["substeps"] == 2 and other.settings["damping_ratio"] == 10.0
    assert other.settings["contact_hertz_base"] == s["contact_hertz_base"] / 2  # substep rate
    with _build("pymunk", sim.scenes.stack(2)) as peer:
        assert (
            solver_summary(peer.settings)["contact_sweeps_per_step"]
            == peer.settings["iterations"]
            == DEFAULT_ITERATIONS["pymunk"]
        )
    with _build("box2d", sim.scenes.stack(2)) as peer:  # 8 velocity + 3 position
        assert solver_summary(peer.settings)["contact_sweeps_per_step"] == 11
        assert peer.settings["iterations"] == DEFAULT_ITERATIONS["box2d"] == 8


def test_factory_rejects_unknown_systems_and_sleeping_by_setting():
    with pytest.raises(ValueError):
        make_runner("box2d-v3", sim.scenes.single_box())
    with pytest.raises(ValueError):
        make_runner("pymunk", sim.scenes.single_box(), sleeping=True)
    with pytest.raises(ValueError):
        make_runner("sim-off", sim.scenes.single_box(), freeze="sleep")


@pytest.mark.parametrize("system", ["pymunk-sleep", "pybullet-sleep", "box2d-sleep"])
def test_sleeping_peers_put_a_resting_row_to_sleep(system):
    with _build(system, sim.scenes.rest_row(3)) as runner:
        runner.step(150)  # 2.5 s: past both engines' timers
        assert runner.asleep.all()
        assert runner.settings["sleeping"]


def test_peers_never_leak_into_sim():
    """ARCHITECTURE §1: sim imports nothing from study or experiments (or pymunk, pybullet,
    Box2D)."""
    for path in (ROOT / "sim").rglob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            names = (
                [a.name for a in node.names]
                if isinstance(node, ast.Import)
                else [node.module or ""]
                if isinstance(node, ast.ImportFrom)
                else []
            )
            for name in names:
                assert name.split(".")[0] not in (
                    "study",
                    "experiments",
                    "pymunk",
                    "pybullet",
                    "Box2D",
                ), path


# ---- the same known answers in every engine -------------------------------------------------
def fall_height(y0, n, dt, substeps=1, explicit=False):
    """Height after ``n`` steps of free fall from rest, m, as each integrator computes it exactly.

    Semi-implicit Euler (velocity first, then position with the new velocity) over k = n substeps
    substeps of h = dt / substeps: y0 - g h^2 k (k+1)/2 (sim: 4 substeps; Bullet and Box2D: one
    per step).
    Chipmunk moves positions with the old velocity first (explicit): y0 - g dt^2 n (n-1)/2."""
    if explicit:
        return y0 - G * dt * dt * n * (n - 1) / 2
    k, h = n * substeps, dt / substeps
    return y0 - G * h * h * k * (k + 1) / 2


def substeps_of(runner):
    """Integration substeps per step: sim's setting; one for Bullet, Chipmunk and Box2D (each
    runner records num_sub_steps 0, sub_stepping False or none)."""
    return runner.settings.get("substeps", 1)


@pytest.mark.parametrize("system", SYSTEMS_OFF)
def test_free_fall(system):
    """v = -g t exactly everywhere (gravity adds g h per substep whatever the substeps);
    positions: each integrator's exact discrete answer (``fall_height``): sim semi-implicit over
    its substeps, Bullet and Box2D semi-implicit per step, Chipmunk explicit (g dt t behind
    Bullet). Box2D to float32 round-off (``ROUND_OFF``)."""
    scene = sim.Scene([sim.Body.box(1.0, 1.0, position=(0.0, 10.0))], floor_y=None)
    n = 60
    with _build(system, scene) as runner:
        runner.step(n)
        assert runner.velocities[0, 1] == pytest.approx(
            -G * n * DT, rel=ROUND_OFF.get(system, 1e-9)
        )
        expected = fall_height(10.0, n, DT, substeps_of(runner), explicit=system == "pymunk")
        assert runner.positions[0, 1] == pytest.approx(expected, rel=ROUND_OFF.get(system, 1e-12))


def test_free_fall_formula_can_tell_the_integrators_apart():
    """The three exact answers differ by far more than the test's 1e-12 (so a runner with the
    wrong integrator, or sim with other substeps, would fail test_free_fall): after 1 s at dt
    1/60, Bullet's semi-implicit step is g dt t (1 - 1/4)/2 = 0.061 m below sim's 4 substeps,
    Chipmunk's explicit one g dt t (1 + 1/4)/2 = 0.102 m above."""
    sim4, bullet, chipmunk = (
        fall_height(10.0, 60, DT, 4),
        fall_height(10.0, 60, DT),
        fall_height(10.0, 60, DT, explicit=True),
    )
    assert sim4 - bullet == pytest.approx(G * DT * 1.0 * (1 - 1 / 4) / 2, rel=1e-9)
    assert chipmunk - sim4 == pytest.approx(G * DT * 1.0 * (1 + 1 / 4) / 2, rel=1e-9)
    assert fall_height(10.0, 60, DT, 1) == bullet


@pytest.mark.parametrize("system", SYSTEMS_OFF)
def test_resting_box_stays_within_the_slop(system):
    with _build(system, sim.scenes.single_box()) as runner:
        start = runner.positions
        runner.step(300)
        assert np.hypot(*(runner.positions - start).T).max() < 0.005
        assert abs(runner.angles[0]) < 1e-3


SIM_STOP_TRANSIENT = (
    "measured: sim-off stops 1.6e-4 m short of its integrator's discrete answer (1.14039 vs "
    "1.14055 m). In the substep where the box stops, the warm start applies the last substep's "
    "full sliding friction, which reverses the box; the biased sweep has no friction rows, and "
    "the relax sweep's friction row stops only 2/5 of the slip (the normal rows after it take "
    "back the turn it gives the box), so the step ends with the box moving back at 5 mm/s (3e-5 "
    "m short) and the next step's warm start carries that on (2.1e-4 m short, then 1.6e-4 once "
    "it stands). With friction rows in the biased sweep too (Box2D v3's choice) it is 5.3e-5 m "
    "short, but pyramid(40), the tipping box, the landing and seed_fig1 under paper got worse "
    "(not adopted). With each two-point lane's friction solved in one block with its normal "
    "rows in the relax sweep, 6.8e-5 m short, but the landing, the step's cost and extended's "
    "piles got worse (not adopted; docs/ARCHITECTURE.md section 2.3)"
)


@pytest.mark.parametrize("system", SYSTEMS_OFF)
def test_slide_distance(system):
    # sim-off crept forward at 2.4e-6 m/s two seconds after it stopped until a two-point
    # manifold on an immovable body carried its load's split between the points at once (the
    # soft step's store): 2.3e-9 m/s
    speed, mu = 3.0, 0.4
    with _build(system, sim.scenes.sliding_box(speed=speed, friction=mu)) as runner:
        x0 = runner.positions[0, 0]
        runner.step(120)
        assert abs(runner.velocities[0, 0]) < 1e-6
        assert runner.positions[0, 0] - x0 == pytest.approx(speed**2 / (2 * mu * G), rel=0.03)


def slide_distance(v0, mu, dt, substeps=1, explicit=False):
    """Distance a box launched at ``v0`` m/s slides on friction ``mu`` before it stops, m, as a
    discrete integrator computes it exactly: friction takes mu g h off the speed every substep of
    h = dt / substeps until less than that is left, which it takes to 0. Semi-implicit Euler moves
    with the new speed (sim over its substeps, Bullet per step): h * sum_j (v0 - j mu g h), j =
    1.. floor(v0 / (mu g h)); Chipmunk moves with the old one first, which adds v0 dt."""
    h = dt / substeps
    a = mu * G * h
    v = v0 - a * np.arange(1, int(v0 / a) + 1)
    return h * v.sum() + (v0 * dt if explicit else 0.0)


@pytest.mark.xfail(strict=True, reason=SIM_STOP_TRANSIENT)
def test_slide_final_positions_agree_across_systems():
    """Each system stops where its own integrator's discrete answer says (``slide_distance``),
    so the final positions differ by the differences of those answers: sim (4 substeps) slides
    v0 (dt - h)/2 ~ 0.019 m further than Bullet (one step), and Chipmunk's explicit order runs
    it v0 dt further than Bullet. Within Bullet's 1e-5 m penetration and the contact's stop
    transient (tolerance 1e-4 m; Chipmunk's 1e-3 m as before)."""
    slide = sim.scenes.sliding_box()
    v0, mu = slide.params["speed"], slide.params["friction"]
    final, expected = {}, {}
    for system in ("sim-off", "pymunk", "pybullet"):
        with _build(system, slide) as runner:
            x0 = runner.positions[0, 0]
            runner.step(120)
            final[system] = runner.positions[0] - (x0, 0.0)
            expected[system] = slide_distance(
                v0, mu, DT, substeps_of(runner), explicit=system == "pymunk"
            )
    assert final["pybullet"][0] - final["sim-off"][0] == pytest.approx(
        expected["pybullet"] - expected["sim-off"], abs=1e-4
    )
    assert abs(final["pybullet"][1] - final["sim-off"][1]) < 1e-4
    assert final["pymunk"][0] - final["sim-off"][0] == pytest.approx(
        expected["pymunk"] - expected["sim-off"], abs=1e-3
    )
    # the expectation itself: v0 (dt - h)/2 apart to within one substep's travel
    assert expected["sim-off"] - expected["pybullet"] == pytest.approx(
        v0 * (DT - DT / 4) / 2, abs=v0 * DT / 4
    )


def test_box2d_slides_where_bullet_does():
    """Box2D and Bullet both integrate semi-implicitly once per step, so both stop at the same
    discrete answer (``slide_distance``, 1.12185 m): measured box2d 1.1218497 (float32),
    pybullet 1.121854 (its 1e-5 m penetration leaves y at 0.49999). Unlike sim-off, not
    expected to fail."""
    slide = sim.scenes.sliding_box()
    v0, mu = slide.params["speed"], slide.params["friction"]
    final = {}
    for system in ("box2d", "pybullet"):
        with _build(system, slide) as runner:
            x0 = runner.positions[0, 0]
            runner.step(120)
            final[system] = runner.positions[0] - (x0, 0.0)
    assert final["box2d"][0] == pytest.approx(slide_distance(v0, mu, DT), abs=1e-5)
    np.testing.assert_allclose(final["box2d"], final["pybullet"], rtol=0, atol=2e-5)


@pytest.mark.parametrize("system", SYSTEMS_OFF)
def test_bounce_height(system):
    """Apex e^2 h within 10 % for sim, pymunk and box2d (measured -5.6 % for e = 0.7: its
    continuous collision loses the rest of the impact step); pybullet overshoots by ~10 %
    (measured +10 % for e = 0.7), so its bound is the documented 3-16 %."""
    e, h, half = 0.7, 2.0, 0.25
    scene = sim.Scene([sim.Body.box(2 * half, 2 * half, position=(0.0, h + half), restitution=e)])
    with _build(system, scene) as runner:
        heights = []
        for _ in range(180):
            runner.step()
            heights.append(runner.positions[0, 1] - half)
    first = int(np.argmin(heights[:60]))
    ratio = max(heights[first : first + 90]) / (e * e * h)
    if system == "pybullet":
        assert 1.03 < ratio < 1.16
    else:
        assert ratio == pytest.approx(1.0, abs=0.10)


@pytest.mark.parametrize("system", SYSTEMS_OFF)
@pytest.mark.parametrize("offset_deg,falls", [(-2.0, False), (2.0, True)])
def test_tipping(system, offset_deg, falls):
    """The box that falls back rocks on its base for a while: 5 s settles it in sim, pymunk and
    pybullet; Box2D rocks until 6 s (measured 0.012 rad at 5 s, 2e-4 rad from 6 s on)."""
    w, h = 0.5, 2.0
    angle = math.atan(w / h) + math.radians(offset_deg)
    with _build(system, sim.Scene(bodies=[tilted_box(w, h, angle)])) as runner:
        runner.step(360 if system == "box2d" else 300)
        expected = math.pi / 2 if falls else 0.0
        assert runner.angles[0] == pytest.approx(expected, abs=0.01)


@pytest.mark.parametrize("system", SYSTEMS_OFF)
def test_five_box_column_holds_10_s(system):
    with _build(system, sim.scenes.stack(5)) as runner:
        start = runner.positions
        runner.step(600)
        assert np.hypot(*(runner.positions[-1] - start[-1])) < 0.01
        assert np.abs(runner.angles).max() < 0.01


def test_seed_fig3_outcome_agrees():
    """A slides off B and lands on the floor in every system."""
    for system in SYSTEMS_OFF:
        with _build(system, sim.scenes.seed_fig3()) as runner:
            runner.step(240)
            assert runner.positions[0, 1] < 0.5, system  # on the floor, not on B (1 m)
            assert runner.positions[0, 0] > 1.0, system  # off B's right edge


# ---- the table ------------------------------------------------------------------------------
def test_peer_agreement_quick_writes_the_table(tmp_path):
    peer_agreement.main(["--quick"], data_dir=tmp_path)
    table = pd.read_csv(tmp_path / "peer_agreement.csv")
    labels = [label for label, *_ in peer_agreement.cases(peer_agreement.QUICK)]
    assert set(table["scene"]) == set(labels) | {f"pyramid{peer_agreement.QUICK['cost_pyramid']}"}
    assert set(table["system"]) == set(peer_agreement.SYSTEMS)
    for label in labels:
        rows = table[table["scene"] == label]
        assert set(rows["system"]) == set(peer_agreement.SYSTEMS), label
        peers = rows[rows["system"] != "sim-off"]
        assert set(peers.loc[peers["metric"] == "final_pose_diff_m", "system"]) == set(
            peer_agreement.SYSTEMS
        ) - {peer_agreement.REFERENCE}
    # every known answer that every system must reach
    for scene, metric in (
        ("single_box", "rest_drift_m"),
        ("sliding_box", "slide_distance_m"),
        ("tipping_past", "tipped"),
        ("tipping_short", "tipped"),
        ("stack5", "top_box_drift_m"),
        ("seed_fig3", "fell_off"),
    ):
        rows = table[(table["scene"] == scene) & (table["metric"] == metric)]
        assert len(rows) == len(peer_agreement.SYSTEMS) and rows["agree"].all(), (scene, metric)
    drift = table[table["metric"] == "out_of_plane_drift"]
    assert len(drift) == len(labels) and (drift["value"] == 0.0).all()
    cost = table[table["metric"] == "ms_per_step_median"]
    assert len(cost) == len(peer_agreement.SYSTEMS) and (cost["value"] > 0).all()
    ratio = table[(table["metric"] == "cost_vs_sim_off") & (table["system"] == "sim-off")]
    assert ratio["value"].tolist() == [1.0]
    meta = json.loads((tmp_path / "peer_agreement.json").read_text())
    assert meta["script"] == "peer_agreement"
    assert set(meta["parameters"]["system_settings"]) == set(peer_agreement.SYSTEMS)
    assert meta["parameters"]["system_settings"]["pybullet"]["iterations"] == 50
    assert meta["packages"]["pybullet"] == "3.2.7"


def test_sim_lands_a_pile_no_further_from_its_rest_pose_than_any_peer():
    """Issue 11's landing criterion, on fig_tradeoff's landing scene (24 unit boxes falling flat
    onto each other and the floor; the exact answer moves no box sideways): after 5 s at each
    system's default settings (study.common.build, as fig_tradeoff runs them), sim-off's largest
    distance from the rest pose is no larger than the best peer's. Measured (2026-12-06;
    fig_tradeoff of 2026-12-07: 0.66 mm): sim-off 0.57 mm (0.69 mm before a two-point manifold on an
    immovable body carried its load's split at once, 32.6 mm before the impact sweeps,
    sim.soft_step.IMPACT_SWEEP_SPEED), pybullet 1.05 mm, pymunk 12.9 mm, Box2D 16.3 mm."""
    from study.common import build
    from study.tradeoff import landing, rest_pose

    scene = landing()
    exact, _ = rest_pose(scene)
    error = {}
    for system in SYSTEMS_OFF:
        with build(system, scene) as runner:
            runner.step(300)
            error[system] = float(np.linalg.norm(runner.positions - exact, axis=1).max())
    best_peer = min(v for k, v in error.items() if k != "sim-off")
    assert error["sim-off"] <= best_peer, error


def test_sim_keeps_a_pile_of_random_polygons_apart_better_than_every_peer():
    """A pile of 30 random convex polygons dropped into the bin (drop(30), seed 0), 4 s at each
    engine's defaults: the deepest overlap between any two bodies or a body and the floor at
    any step, measured by one geometric routine for every engine (study.tradeoff). Impacts
    compress soft contacts, and bodies kicked in the middle of a step swing corners the step's
    manifold did not see, so every engine lets some overlap through; no analytic answer, so
    against the peers. Measured (seed 0): sim-off 21 mm (20 mm at dt/2, 11 mm at dt/4; 33 mm
    before the corner contacts, geometry._closest_points), pymunk 154 mm, Box2D 123 mm,
    pybullet 187 mm; seeds 1-4 alike (sim 23-54 mm, the peers 122-294 mm)."""
    from study.tradeoff import Polygons, deepest_overlap

    scene = sim.scenes.drop(30, seed=0)
    polygons = Polygons(scene)
    deepest = {}
    for system in SYSTEMS_OFF:
        with _build(system, scene) as runner:
            worst = 0.0
            for _ in range(240):
                runner.step(1)
                worst = max(worst, deepest_overlap(polygons, runner.positions, runner.angles))
        deepest[system] = worst
    best_peer = min(v for k, v in deepest.items() if k != "sim-off")
    assert deepest["sim-off"] < 0.5 * best_peer, deepest


@pytest.mark.parametrize("size", [1.0, 0.1, 0.01])
def test_pymunk_slop_is_sims_for_the_scenes_smallest_body(size):
    # sim's slop is a cap, scaled to 0.5% of the smaller body of a pair (sim.tolerances);
    # pymunk's is one length for the space. Under the flat 5 mm a 1 cm box placed on the floor
    # sank 2.7 mm (27% of its size) where sim's sank nothing. With the smallest body's slop it
    # sinks at most that slop, 0.5% of its size, at every size.
    box = sim.Body.box(size, size, position=(0.0, size / 2))
    runner = build("pymunk", sim.Scene(bodies=[box]))
    assert runner.settings["collision_slop"] == pytest.approx(min(0.005, 0.005 * size))
    runner.step(120)
    sink = size / 2 - runner.positions[0, 1]
    runner.close()
    assert sink <= 0.005 * size * (1 + 1e-3)


def test_results_metadata_records_the_slop_pymunk_ran_with_on_each_scene():
    # a script records its runners' settings from one probe scene; pymunk's slop follows each
    # scene (build, comparable_slop), so the metadata's scenes carry it, scene by scene
    from study.metadata import collect

    scenes = [sim.scenes.stack(2), sim.scenes.drop(20, seed=0)]
    described = collect(scenes, {}, script="test")["scenes"]
    for scene, entry in zip(scenes, described):
        with build("pymunk", scene) as runner:
            assert entry["pymunk_collision_slop_m"] == runner.settings["collision_slop"]
    assert described[1]["pymunk_collision_slop_m"] < described[0]["pymunk_collision_slop_m"]
