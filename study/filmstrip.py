"""Frame-by-frame records of small scenes, for the seed's figures 1-3 (fig_states,
fig_edge_as_floor, fig_overhang): every body's pose, outline and freeze state at every step, and
every freeze/wake event, under each policy asked for.

One long table, column ``kind``:
  "body"   one row per (policy, step, body): time s, state (sim.State int), frozen (out of the awake
           list), x, y m (centre of mass), angle rad, speed m/s, outline "x0 y0 x1 y1 ..." m (world
           vertices, counter-clockwise)
  "event"  one row per event: step, body, from_state, state (to), cause
Step 0 is the start pose. The runs are a few hundred steps of two or three bodies: cheap, so
``--quick`` runs them unchanged.

Each policy runs as every experiment runs sim (study.common.build): dt 1/60 s, slop
0.005 m, sim's own default solver settings (its soft step: 4 substeps per step, 1 biased + 1
relax sweep per substep). The metadata records each policy's full settings (``runner.settings``,
``system_settings``).
"""

import numpy as np
import pandas as pd

from study.common import DT, build


def _body_rows(world, policy):
    rows = []
    speeds = np.hypot(*world.velocities.T)
    for i in range(world.n_bodies):
        outline = " ".join(f"{c:.6g}" for c in world.vertices(i).ravel())
        rows.append(
            {
                "kind": "body",
                "policy": policy,
                "step": world.step_count,
                "time": world.step_count * world.dt,
                "body": i,
                "name": world.scene.body_name(i),
                "state": int(world.states[i]),
                "frozen": bool(world.frozen[i]),
                "x": float(world.positions[i, 0]),
                "y": float(world.positions[i, 1]),
                "angle": float(world.angles[i]),
                "speed": float(speeds[i]),
                "outline": outline,
            }
        )
    return rows


def record(scene, policies, steps, dt=DT, settings_out=None):
    """Run ``scene`` under each policy for ``steps`` steps; the long table described above. Each
    policy's runner settings are stored in the dict ``settings_out`` (if given), keyed by system
    name (sim-<policy>)."""
    if steps < 1:
        raise ValueError(f"steps must be >= 1, got {steps}")
    rows = []
    for policy in policies:
        runner = build(f"sim-{policy}", scene, dt=dt)
        if settings_out is not None:
            settings_out[runner.name] = runner.settings
        world = runner.world
        rows += _body_rows(world, policy)
        for _ in range(steps):
            world.step()
            rows += _body_rows(world, policy)
        for at, body, before, after, cause in world.events:
            rows.append(
                {
                    "kind": "event",
                    "policy": policy,
                    "step": at,
                    "time": at * dt,
                    "body": body,
                    "name": scene.body_name(body),
                    "from_state": int(before),
                    "state": int(after),
                    "cause": cause,
                }
            )
    return pd.DataFrame(rows)


def experiment(name, doc, builder, policies, steps):
    """The ``main`` of a filmstrip experiment: ``builder()`` run ``steps`` steps under
    ``policies``."""
    from study.common import entry

    def run(config, args):
        scene = builder()
        settings = {}
        table = record(scene, config["policies"], config["steps"], settings_out=settings)
        return table, [scene], {"dt": DT, "system_settings": settings}

    config = {"policies": tuple(policies), "steps": steps}
    return entry(name, doc, config, config, run)


def outline_xy(outline):
    """(K,2) vertices from an ``outline`` string."""
    return np.array(outline.split(), float).reshape(-1, 2)
