"""Table "peer_agreement": do sim (freeze off), pymunk, pybullet and Box2D 2.3 agree on the same
scenes, and what does a step cost in each?

Question: every later comparison runs one sim.Scene in three systems. Before reading anything into
those comparisons we need to know where the three already agree with each other and with known
answers, and where a peer cannot (pybullet's restitution, Chipmunk's integration order), and by
how much; and the per-step cost of each peer next to sim's.

Settings: each system runs the same scene from the same start state at dt 1/60 s, no sleeping,
at its own defaults (study.peers.DEFAULT_ITERATIONS), which are not the same thing in each:
sim the soft step with 4 substeps per step, 1 biased solve sweep and 1 relax sweep per substep;
pymunk 10 iterations per step; pybullet 50 iterations per step (one Bullet step per step); box2d
8 velocity + 3 position iterations per step, float32, its polygons inset by their 1 cm skin. Every
setting of each system is in the metadata (``system_settings``, from the runners). Where the
integrators differ (sim's substeps, Chipmunk's order), the known answers are the continuous ones
and the tolerances say how far a discrete integrator may sit from them.

Cases:
- known answers: single_box at rest (drift 0), sliding_box (slide distance v0^2 / (2 mu g)), a box
  bouncing from 2 m with restitution e against a floor of 0 (apex e^2 h, max mixing), a tall
  0.5 x 2 box tilted 2 degrees past / short of its tipping angle atan(w/h) (falls / stands),
  stack(5) for 10 s and pyramid(10) (stay standing);
- against sim(off): the final pose difference (largest centre distance and angle difference over
  bodies) on every scene, and outcome agreement on the chaotic ones: seed_fig3 ("A fell off B onto
  the floor") and drop(20, seed) (bodies inside the bin, pile height);
- pybullet's out-of-plane drift (largest |y| of a centre plus tilt of a body's y axis) per scene;
- cost: ms per step on pyramid(20) (median and min over repeats, build and 10 warm-up steps
  excluded, systems interleaved repeat by repeat, garbage collector paused), and the ratio to
  sim-off's median.

Columns: scene, bodies, seconds, system, metric, value, reference, reference_kind ("analytic",
"sim-off", "zero"), tolerance, agree (value within tolerance of the reference; empty for
measurements that have no tolerance).

    python -m experiments.peer_agreement [--quick] [--repeats R] [--steps K]
writes results/data/peer_agreement.csv and peer_agreement.json.
"""

import argparse
import math
import statistics

import numpy as np
import pandas as pd
from tqdm import tqdm

import sim
from study.cli import first_paragraph, or_default, positive_int
from study.common import interrupted, build, data_folder
from study.timing import interleaved
from study.metadata import code_state, collect, write_results
from study.peers import PybulletRunner, make_runner, solver_summary
from study.scenarios import world_vertices

NAME = "peer_agreement"
DT = 1 / 60
G = 9.81
SYSTEMS = ("sim-off", "pymunk", "pybullet", "box2d")
REFERENCE = "sim-off"
WARMUP_STEPS = 10
TIP_OFFSET_DEG = 2.0

FULL = {
    "stack_seconds": 10.0,
    "pyramid": 10,
    "drop": (20, (0, 1, 2)),
    "drop_seconds": 8.0,
    "cost_pyramid": 20,
    "repeats": 7,
    "steps": 20,
}
QUICK = {
    "stack_seconds": 10.0,
    "pyramid": 5,
    "drop": (8, (0,)),
    "drop_seconds": 4.0,
    "cost_pyramid": 6,
    "repeats": 3,
    "steps": 5,
}


# ---- scenes ------------------------------------------------------------------------------------
def bounce_scene(e, height=2.0, size=0.5):
    """A box of restitution ``e`` whose bottom face starts ``height`` m above a floor of
    restitution 0 (max mixing makes the pair bounce with e)."""
    body = sim.Body.box(size, size, position=(0.0, height + size / 2), restitution=e)
    return sim.Scene(
        bodies=[body],
        name=f"bounce_e{e:g}",
        params={"restitution": e, "height": height, "size": size},
    )


def tipping_scene(offset_deg, width=0.5, height=2.0, friction=0.6):
    """A width x height box standing on its lowest corner, tilted ``offset_deg`` past (> 0) or
    short of (< 0) its tipping angle atan(width / height), starting exactly touching the floor."""
    angle = math.atan(width / height) + math.radians(offset_deg)
    lowest = -0.5 * width * math.sin(angle) - 0.5 * height * math.cos(angle)
    body = sim.Body.box(width, height, position=(0.0, -lowest), angle=angle, friction=friction)
    label = "past" if offset_deg > 0 else "short"
    return sim.Scene(
        bodies=[body],
        name=f"tipping_{label}",
        params={"offset_deg": offset_deg, "width": width, "height": height},
    )


# ---- cases: (label, scene, seconds, metrics) -----------------------------------------------------
# A metric is (name, function(trajectory) -> value, analytic reference or None, tolerance or
# None). Without an analytic reference, the value is compared with sim-off's. ``trajectory`` holds
# the scene, the start and end observables and, for the bounce, the height after every step.
def _max_drift(t):
    return float(np.hypot(*(t["end_pos"] - t["start_pos"]).T).max())


def _top_drift(t):
    return float(np.hypot(*(t["end_pos"][-1] - t["start_pos"][-1])))


def _slide(t):
    return float(t["end_pos"][0, 0] - t["start_pos"][0, 0])


def _apex(t):
    bottom = np.asarray(t["heights"])
    first = int(np.argmin(bottom[: int(round(1.0 / DT))]))  # falls 2 m in 0.64 s
    return float(bottom[first : first + int(round(1.5 / DT))].max())


def _tipped(t):
    return float(abs(t["end_angle"][0]) > math.pi / 4)


def _fell_off(t):
    """seed_fig3: A's centre ended below B's top face (1 m): A left B and lies on the floor."""
    return float(t["end_pos"][0, 1] < 1.0)


def _inside_bin(t):
    scene = t["scene"]
    left, right = scene.static_bodies[0], scene.static_bodies[1]
    x_lo = left.position[0] + 0.25
    x_hi = right.position[0] - 0.25
    x = t["end_pos"][:, 0]
    return float(np.count_nonzero((x > x_lo) & (x < x_hi)))


def _pile_height(t):
    scene = t["scene"]
    return float(
        max(
            world_vertices(scene, i, t["end_pos"][i], t["end_angle"][i])[:, 1].max()
            for i in range(len(scene.bodies))
        )
    )


def cases(sizes):
    """Every case of the table for the given sizes (FULL or QUICK)."""
    slide = sim.scenes.sliding_box()
    v0, mu = slide.params["speed"], slide.params["friction"]
    out = [
        ("single_box", sim.scenes.single_box(), 5.0, [("rest_drift_m", _max_drift, 0.0, 0.005)]),
        (
            "sliding_box",
            slide,
            2.0,
            [("slide_distance_m", _slide, v0**2 / (2 * mu * G), 0.03 * v0**2 / (2 * mu * G))],
        ),
    ]
    for e in (0.5, 0.7, 0.9):
        h = 2.0
        out.append(
            (
                f"bounce_e{e:g}",
                bounce_scene(e, h),
                3.0,
                [("bounce_apex_m", _apex, e * e * h, 0.10 * e * e * h)],
            )
        )
    out += [
        ("tipping_past", tipping_scene(TIP_OFFSET_DEG), 5.0, [("tipped", _tipped, 1.0, 0.0)]),
        ("tipping_short", tipping_scene(-TIP_OFFSET_DEG), 5.0, [("tipped", _tipped, 0.0, 0.0)]),
        (
            "stack5",
            sim.scenes.stack(5),
            sizes["stack_seconds"],
            [("top_box_drift_m", _top_drift, 0.0, 0.01)],
        ),
        (
            f"pyramid{sizes['pyramid']}",
            sim.scenes.pyramid(sizes["pyramid"]),
            5.0,
            [("max_drift_m", _max_drift, 0.0, 0.02)],
        ),
        ("seed_fig3", sim.scenes.seed_fig3(), 4.0, [("fell_off", _fell_off, 1.0, 0.0)]),
    ]
    n, seeds = sizes["drop"]
    for seed in seeds:
        out.append(
            (
                f"drop{n}_seed{seed}",
                sim.scenes.drop(n, seed=seed),
                sizes["drop_seconds"],
                [
                    ("bodies_in_bin", _inside_bin, float(n), 0.0),
                    ("pile_height_m", _pile_height, None, 0.25),
                ],
            )
        )  # relative to sim-off's
    return out


#: Final pose difference to sim-off that counts as agreement, per case (absent: chaotic or
#: phase-sensitive, reported without a tolerance). sliding_box allows for the integrators: a
#: discrete slide stops about v0 h / 2 short of v0^2 / (2 mu g) for a step h, so Bullet (h = dt)
#: stops v0 (dt - dt/4) / 2 = 0.019 m before sim (4 substeps), and Chipmunk, which moves
#: positions before velocities, runs v0 dt further than Bullet: 0.031 m past sim.
POSE_TOLERANCE = {"single_box": 0.005, "sliding_box": 0.06, "stack5": 0.01, "tipping_short": 0.01}


def run_case(system, scene, seconds, record_heights=False):
    """Run one system on one scene; returns the trajectory dict the metrics read."""
    runner = build(system, scene, dt=DT)
    try:
        steps = int(round(seconds / DT))
        t = {"scene": scene, "start_pos": runner.positions, "start_angle": runner.angles}
        if record_heights:
            half = 0.5 * float(np.ptp(scene.bodies[0].vertices[:, 1]))
            heights = []
            for _ in range(steps):
                runner.step()
                heights.append(float(runner.positions[0, 1]) - half)
            t["heights"] = heights
        else:
            runner.step(steps)
        t["end_pos"], t["end_angle"] = runner.positions, runner.angles
        t["settings"] = runner.settings
        if isinstance(runner, PybulletRunner):
            t["out_of_plane"] = runner.out_of_plane()
        return t
    finally:
        runner.close()


def agreement_rows(sizes, progress=None):
    """Run every case in every system; the table's agreement rows."""
    rows = []
    for label, scene, seconds, metrics in cases(sizes):
        bouncing = any(name == "bounce_apex_m" for name, *_ in metrics)
        runs = {}
        for system in SYSTEMS:
            runs[system] = run_case(system, scene, seconds, record_heights=bouncing)
            if progress is not None:
                progress.update()
        ref = runs[REFERENCE]
        base = {"scene": label, "bodies": len(scene.bodies), "seconds": seconds}
        for system, t in runs.items():
            for name, fn, analytic, tol in metrics:
                value = fn(t)
                if analytic is None:
                    reference, kind = fn(ref), REFERENCE
                    tol_abs = tol * abs(reference)
                else:
                    reference, kind, tol_abs = analytic, "analytic", tol
                rows.append(
                    {
                        **base,
                        "system": system,
                        "metric": name,
                        "value": value,
                        "reference": reference,
                        "reference_kind": kind,
                        "tolerance": tol_abs,
                        "agree": bool(abs(value - reference) <= tol_abs + 1e-12),
                    }
                )
            if system != REFERENCE:
                d_pos = float(np.hypot(*(t["end_pos"] - ref["end_pos"]).T).max())
                d_ang = float(np.abs(t["end_angle"] - ref["end_angle"]).max())
                tol = POSE_TOLERANCE.get(label)
                for name, value in (("final_pose_diff_m", d_pos), ("final_angle_diff_rad", d_ang)):
                    rows.append(
                        {
                            **base,
                            "system": system,
                            "metric": name,
                            "value": value,
                            "reference": 0.0,
                            "reference_kind": REFERENCE,
                            "tolerance": tol if name.endswith("_m") else None,
                            "agree": (
                                bool(value <= tol)
                                if tol is not None and name.endswith("_m")
                                else None
                            ),
                        }
                    )
            if "out_of_plane" in t:
                o = t["out_of_plane"]
                value = max(o["max_abs_y_m"], o["max_tilt_rad"], o["max_base_drift_m"])
                rows.append(
                    {
                        **base,
                        "system": system,
                        "metric": "out_of_plane_drift",
                        "value": value,
                        "reference": 0.0,
                        "reference_kind": "zero",
                        "tolerance": 0.0,
                        "agree": bool(value == 0.0),
                    }
                )
    return rows


# ---- cost ----------------------------------------------------------------------------------------
def cost_rows(base, repeats, steps, progress=None):
    """ms per step of every system on pyramid(base), interleaved repeat by repeat."""
    scene = sim.scenes.pyramid(base)
    runners = [build(system, scene, dt=DT) for system in SYSTEMS]
    try:
        for r in runners:
            r.step(WARMUP_STEPS)  # first steps excluded (contacts, caches)
        # round-robin, the order reversed every other repeat, as every benchmark (study.timing)
        times = interleaved(runners, [steps] * len(runners), repeats, progress)
        moved = [float(np.hypot(*(r.positions - runners[0].positions).T).max()) for r in runners]
    finally:
        for r in runners:
            r.close()
    medians = [statistics.median(t) for t in times]
    rows = []
    label = f"pyramid{base}"
    for k, system in enumerate(SYSTEMS):
        common = {
            "scene": label,
            "bodies": len(scene.bodies),
            "seconds": (WARMUP_STEPS + repeats * steps) * DT,
            "system": system,
            "tolerance": None,
            "agree": None,
        }
        rows += [
            {
                **common,
                "metric": "ms_per_step_median",
                "value": medians[k],
                "reference": medians[0],
                "reference_kind": REFERENCE,
            },
            {
                **common,
                "metric": "ms_per_step_min",
                "value": min(times[k]),
                "reference": min(times[0]),
                "reference_kind": REFERENCE,
            },
            {
                **common,
                "metric": "cost_vs_sim_off",
                "value": medians[k] / medians[0],
                "reference": 1.0,
                "reference_kind": REFERENCE,
            },
            {
                **common,
                "metric": "final_pose_diff_m",
                "value": moved[k],
                "reference": 0.0,
                "reference_kind": REFERENCE,
            },
        ]
    return rows


def run(sizes, repeats, steps):
    """The whole table: agreement rows, then cost rows."""
    sim.World(sim.scenes.stack(2), dt=DT).step(2)  # compile Numba kernels first
    n_cases = len(cases(sizes))
    with tqdm(total=n_cases * len(SYSTEMS) + repeats * len(SYSTEMS), desc=NAME, unit="run") as bar:
        rows = agreement_rows(sizes, bar)
        rows += cost_rows(sizes["cost_pyramid"], repeats, steps, bar)
    return pd.DataFrame(rows)


def main(argv=None, data_dir=None):
    """Command line entry; ``data_dir`` overrides results/data (tests)."""
    parser = argparse.ArgumentParser(
        prog=f"python -m experiments.{NAME}", description=first_paragraph(__doc__)
    )
    parser.add_argument("--quick", action="store_true", help="small sizes, few repeats (CI)")
    parser.add_argument(
        "--repeats", type=positive_int, default=None, help="timed repeats (default 7, quick 3)"
    )
    parser.add_argument(
        "--steps",
        type=positive_int,
        default=None,
        help="steps per timed repeat (default 20, quick 5)",
    )
    args = parser.parse_args(argv)
    started = code_state()  # the code that runs (collect says if it changes before the end)
    sizes = QUICK if args.quick else FULL
    repeats = or_default(args.repeats, sizes["repeats"])
    steps = or_default(args.steps, sizes["steps"])

    try:
        table = run(sizes, repeats, steps)
    except KeyboardInterrupt:
        raise SystemExit(interrupted(NAME, data_folder(args.quick, data_dir))) from None
    scenes = [scene for _, scene, _, _ in cases(sizes)] + [
        sim.scenes.pyramid(sizes["cost_pyramid"])
    ]
    probe = sim.scenes.single_box()
    settings = {}
    for system in SYSTEMS:
        with make_runner(system, probe, dt=DT) as r:
            settings[system] = r.settings
    parameters = {
        "dt": DT,
        "systems": list(SYSTEMS),
        "reference": REFERENCE,
        "solver_summary": {system: solver_summary(settings[system]) for system in SYSTEMS},
        "quick": args.quick,
        "sizes": sizes,
        "repeats": repeats,
        "steps_per_repeat": steps,
        "warmup_steps": WARMUP_STEPS,
        "tip_offset_deg": TIP_OFFSET_DEG,
        "pose_tolerance": POSE_TOLERANCE,
        "system_settings": settings,
    }
    folder = data_folder(args.quick, data_dir)
    metadata = collect(scenes, parameters, script=NAME, started=started)
    csv_path, _ = write_results(NAME, table, metadata, folder=folder)
    with pd.option_context(
        "display.width", 200, "display.max_columns", 20, "display.max_rows", 500
    ):
        print(
            table.drop(columns=["reference_kind"]).to_string(
                index=False, float_format=lambda x: f"{x:.4g}"
            )
        )
    print(f"wrote {csv_path}")
    return table


if __name__ == "__main__":
    main()
