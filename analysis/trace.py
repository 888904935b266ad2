"""A rerun recording (``.rrd``) of one run, to inspect it frame by frame.

    python -m analysis.trace SCENE FREEZE [--size N] [--steps N] [--out PATH]
    make trace SCENE=... FREEZE=...
    rerun results/recordings/<scene>__<policy>.rrd                      (opens it)

Per step, on the timeline ``step``:
  world/bodies         every body as a closed line strip, coloured by its state (frozen bodies darker)
  world/floor          the floor line (once, static)
  world/contacts       contact points of the step
  world/impulses       normal impulses as arrows (N s, scaled by ``--arrow-scale`` m per N s)
  events               freeze/wake events as text log entries
  timeline/awake       bodies in the awake list
  timeline/kinetic_energy   J
  timeline/step_ms     wall time of the step itself, ms (logging excluded)
"""
import argparse
import time
from pathlib import Path

import numpy as np
import rerun as rr

import sim
from analysis.style import STATE_RGB
from experiments.paths import RECORDINGS, ensure

#: state -> RGB (FREE, VERTICAL_STABLE, ROTATION_STABLE, SLEEPING): the figures' colours
STATE_COLORS = np.array(STATE_RGB, np.uint8)


def record(scene, freeze, steps, path, dt=1 / 60, arrow_scale=0.5, **world_settings):
    """Run ``scene`` under ``freeze`` for ``steps`` steps and write the recording to ``path``.
    Returns the World at the end."""
    world = sim.World(scene, dt=dt, freeze=freeze, **world_settings)
    rec = rr.RecordingStream(f"freeze2d-{scene.name}-{freeze}")
    rec.save(str(path))
    if scene.floor_y is not None:
        xs = np.concatenate([world.positions[:, 0], [0.0]])
        span = float(np.ptp(xs)) + 20.0
        mid = float(xs.mean())
        rec.log("world/floor", rr.LineStrips2D([[(mid - span / 2, scene.floor_y),
                                                  (mid + span / 2, scene.floor_y)]],
                                                colors=[(0, 0, 0)]), static=True)
    n_events = 0
    for step in range(steps + 1):
        rec.set_time("step", sequence=world.step_count)
        if step > 0:
            t0 = time.perf_counter()
            world.step()
            rec.set_time("step", sequence=world.step_count)
            rec.log("timeline/step_ms", rr.Scalars(1e3 * (time.perf_counter() - t0)))
        strips = [np.vstack([v, v[:1]]) for v in (world.vertices(i) for i in range(world.n_bodies))]
        colors = STATE_COLORS[world.states.astype(int)].copy()
        colors[world.frozen] = colors[world.frozen] // 2          # frozen: darker
        rec.log("world/bodies", rr.LineStrips2D(strips, colors=colors))
        contacts = world.contacts()
        rec.log("world/contacts", rr.Points2D(contacts["point"], radii=0.02))
        rec.log("world/impulses", rr.Arrows2D(
            origins=contacts["point"],
            vectors=contacts["normal"] * contacts["normal_impulse"][:, None] * arrow_scale))
        for event in world.events[n_events:]:
            at, body, before, after, cause = event
            rec.log("events", rr.TextLog(f"step {at}: {scene.body_name(body)} "
                                         f"{before.name} -> {after.name} ({cause})"))
        n_events = len(world.events)
        rec.log("timeline/awake", rr.Scalars(float(world.n_awake)))
        rec.log("timeline/kinetic_energy", rr.Scalars(world.kinetic_energy()))
    rec.flush()
    return world


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m analysis.trace",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("scene", choices=sorted(sim.scenes.BUILDERS), help="a sim.scenes builder")
    parser.add_argument("freeze", choices=sim.POLICY_NAMES, help="freeze policy")
    parser.add_argument("--size", type=int, default=None,
                        help="the builder's size argument (rest_row n, stack height, pyramid "
                             "base, drop n); default the builder's own")
    parser.add_argument("--steps", type=int, default=300, help="steps to record (default 300)")
    parser.add_argument("--out", default=None, help="output .rrd (default results/recordings/)")
    parser.add_argument("--arrow-scale", type=float, default=0.5, help="m per N s of impulse")
    args = parser.parse_args(argv)
    if args.steps < 1:
        parser.error("--steps must be >= 1")
    path = Path(args.out) if args.out else RECORDINGS / f"{args.scene}__{args.freeze}.rrd"
    ensure(path.parent)
    build = sim.scenes.BUILDERS[args.scene]
    scene = build() if args.size is None else build(args.size)
    record(scene, args.freeze, args.steps, path, arrow_scale=args.arrow_scale)
    print(f"wrote {path}   (open it with: rerun {path})")
    return path


if __name__ == "__main__":
    main()
