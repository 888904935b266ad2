"""bench_freeze's part 4: what ``extended`` costs where nothing can rest, phase by phase.

Two scenes where no body can come to rest: "fall" (boxes falling from FALL_HEIGHT m, never
touching before the floor) and "drift" (boxes in zero gravity without a floor, moving at about
DRIFT_SPEED m/s with a random spread and spin: neighbours close in and collide, but none is ever
slow). Each is timed under sim-off and sim-extended (FLIGHT_SYSTEMS).

Why phases. Neither scene is stationary: 1000 falling boxes cost sim-off about 0.09 ms a step at the
start and ~2.4 ms at its end (step 1420; 2026-12-07): fast bodies reach farther (their swept boxes
and speculative margins grow, and boxes falling one above the other get speculative contacts), and
the drift's cost changes as neighbours meet. Timed as consecutive repeats of one run, each repeat
was a different phase: the median over repeats mixed phases, the ratio of two medians could set
neighbouring phases against each other, and the cheapest phase (where a fixed per-body cost weighs
most) got one sample. So each phase is timed on its own. A sim-off run is stepped to the phase's
first step and its state (centres of mass, angles, velocities) becomes a scene (``restarted``);
every repeat builds both systems fresh on that scene, steps WARMUP_STEPS untimed and times the same
``steps`` steps, the two systems back to back (order reversed every other repeat). Every repeat of a
phase then times the same motion. A phase's overhead is the median over repeats of the paired ratio
extended / off (back to back, slow load drifts cancel); the target is judged on the worst phase.
"""

import statistics

import numpy as np

import sim
from sim.polygons import mass_properties_many
from study.common import build, label, n_awake
from study.protocols import (
    FLY_PITCH,
    WARMUP_STEPS,
    block,
    fall_scene,
    flight_budget,
    long_row,
    timing_rows,
)
from study.timing import timed

PART = "in_flight_overhead"
FLIGHT_SYSTEMS = ("sim-off", "sim-extended")
DRIFT_SPEED = 3.0  # m/s, the drifting block's common velocity along x
DRIFT_SPREAD = 0.5  # m/s, +- uniform spread per velocity component; spin +- 1 rad/s
DRIFT_SEED = 0  # the drift scene's random velocities
#: where the phases start, as fractions of the span a scene can be timed over
PHASES = (0.0, 0.5, 1.0)


def drift_scene(n, seed=DRIFT_SEED):
    """n boxes in zero gravity, no floor, moving at DRIFT_SPEED m/s along x with a random spread
    and spin: neighbours close in and collide, but no body is ever slow."""
    rng = np.random.default_rng(seed)
    v = np.column_stack(
        [
            DRIFT_SPEED + rng.uniform(-DRIFT_SPREAD, DRIFT_SPREAD, n),
            rng.uniform(-DRIFT_SPREAD, DRIFT_SPREAD, n),
        ]
    )
    w = rng.uniform(-1.0, 1.0, n)
    return sim.Scene(
        bodies=block(n, 0.0, v, w),
        name="drift",
        floor_y=None,
        gravity=(0.0, 0.0),
        params={
            "n": n,
            "seed": seed,
            "speed": DRIFT_SPEED,
            "spread": DRIFT_SPREAD,
            "pitch": FLY_PITCH,
        },
    )


def restarted(scene, runner):
    """``scene`` with its dynamic bodies where ``runner`` has taken them: the same polygons and
    materials at the runner's poses and velocities, each polygon re-expressed about its centroid
    (a runner reports centres of mass, a Scene places body frames). Its params gain
    ``from_step``, the runner's step count."""
    a = scene.snapshot().body_arrays
    _, centroid, _ = mass_properties_many(a.vertices, a.vert_start, a.density)
    counts = np.diff(a.vert_start)
    return sim.Scene.from_arrays(
        a.vertices - np.repeat(centroid, counts, axis=0),
        runner.positions,
        vert_start=a.vert_start,
        angle=runner.angles,
        velocity=runner.velocities,
        angular_velocity=runner.angular_velocities,
        density=a.density,
        friction=a.friction,
        restitution=a.restitution,
        bullet=a.bullet,
        names=a.names,
        static_bodies=scene.static_bodies,
        floor_y=scene.floor_y,
        gravity=scene.gravity,
        floor_friction=scene.floor_friction,
        floor_restitution=scene.floor_restitution,
        name=scene.name,
        params={**scene.params, "from_step": runner.step_count},
    )


def phase_starts(span):
    """The first step of each phase (PHASES) over ``span`` steps."""
    return sorted({int(round(f * span)) for f in PHASES})


def spans(config):
    """(scene, steps over which its phases may start) of each scene: the fall's phases end
    before the boxes near the floor (``flight_budget``), the drift's within
    config["drift_span"]."""
    steps = config["flight_steps"]
    n = config["flight_n"]
    return (
        (fall_scene(n), max(0, flight_budget() - WARMUP_STEPS - steps)),
        (drift_scene(n), config["drift_span"]),
    )


def _time_phase(scene, steps, repeats, progress):
    """Per-step times (ms) of FLIGHT_SYSTEMS over ``repeats`` fresh builds on ``scene``, back to
    back; also the fewest awake before and after any timing, and the slowest body's speed at the
    end of sim-extended's last repeat (m/s)."""
    times = [[] for _ in FLIGHT_SYSTEMS]
    before = [scene.n_bodies] * len(FLIGHT_SYSTEMS)
    after = list(before)
    slowest = np.inf
    order = list(range(len(FLIGHT_SYSTEMS)))
    for r in range(repeats):
        for k in order if r % 2 == 0 else order[::-1]:
            with build(FLIGHT_SYSTEMS[k], scene) as runner:
                runner.step(WARMUP_STEPS)
                before[k] = min(before[k], n_awake(runner))
                times[k].append(1e3 * timed(runner, steps) / steps)
                after[k] = min(after[k], n_awake(runner))
                if FLIGHT_SYSTEMS[k] == "sim-extended":
                    slowest = float(np.hypot(*runner.velocities.T).min())
            progress.update()
    return times, before, after, slowest


def in_flight_overhead(config, repeats, progress):
    """Part 4's rows: per phase (scene "<scene> from step s") each system's timing and
    sim-extended's ratios to sim-off; per scene the worst phase (metrics
    ``ratio_to_off_worst`` and ``worst_phase_step``)."""
    rows = []
    steps = config["flight_steps"]
    i_off, i_ext = FLIGHT_SYSTEMS.index("sim-off"), FLIGHT_SYSTEMS.index("sim-extended")
    for scene, span in spans(config):
        tag = label(scene)
        n = scene.n_bodies
        worst, worst_step = -np.inf, 0
        with build("sim-off", scene) as reference:
            for start in phase_starts(span):
                progress.set_postfix_str(f"{tag}: to step {start}")
                reference.step(start - reference.step_count)
                phase = restarted(scene, reference)
                progress.set_postfix_str(f"{tag} from step {start}: timing")
                times, before, after, slowest = _time_phase(phase, steps, repeats, progress)
                # back to back in every repeat: their ratio cancels slow load drifts
                paired = statistics.median(e / o for e, o in zip(times[i_ext], times[i_off]))
                if paired > worst:
                    worst, worst_step = paired, start
                ratio_med = statistics.median(times[i_ext]) / statistics.median(times[i_off])
                for k, system in enumerate(FLIGHT_SYSTEMS):
                    ok = before[k] == n and after[k] == n
                    common = dict(
                        part=PART,
                        scene=f"{tag} from step {start}",
                        system=system,
                        bodies=n,
                        n_aw=before[k],
                        n_fr=n - before[k],
                        flag="" if ok else "a body froze: not an in-flight scene",
                    )
                    rows += timing_rows(common, times[k], before[k], after[k], steps, repeats)
                    rows.append(
                        long_row(**common, metric="phase_start_step", value=start, unit="steps")
                    )
                    if k == i_ext:
                        rows += [
                            long_row(
                                **common,
                                metric="ratio_to_off_median",
                                value=ratio_med,
                                unit="ratio",
                            ),
                            long_row(
                                **common, metric="ratio_to_off_paired", value=paired, unit="ratio"
                            ),
                            long_row(**common, metric="min_speed_after", value=slowest, unit="m/s"),
                        ]
        common = dict(part=PART, scene=tag, system="sim-extended", bodies=n, n_aw=n, n_fr=0)
        rows += [
            long_row(**common, metric="ratio_to_off_worst", value=worst, unit="ratio"),
            long_row(**common, metric="worst_phase_step", value=worst_step, unit="steps"),
        ]
    return rows


def n_timings(config, repeats):
    """Timed runs part 4 makes (for a progress bar)."""
    return sum(len(phase_starts(span)) for _, span in spans(config)) * len(FLIGHT_SYSTEMS) * repeats
