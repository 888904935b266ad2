"""fig_tradeoff's measurement code (the script ``experiments/fig_tradeoff.py`` holds the
configuration, the sweeps and the methods in its docstring): the ``landing`` scene and the exact
rest pose of its scenes (``rest_pose``), the one penetration routine every engine is measured by
(``Polygons``, ``deepest_overlap``), the parameter grids, the untimed accuracy run (an executor
task) and the timed runs, and the table's columns with the errors of one row (``error_row``)."""

import math

import numpy as np

import sim
from study import common
from study.common import build, n_awake, pose_error
from study.overlap import pad, separation, world_vertices
from study.timing import timed
from sim.geometry import mass_properties

DROP = 0.5  # m, landing: fall height of each row and step of the loners' heights
GAP = 0.125  # m, landing: gap between neighbours in a row (as sim.scenes.pyramid)
FRICTION = 0.6  # as every builder in sim.scenes


# ---- scenes ------------------------------------------------------------------------------------
def landing(base=8, layers=2, loners=3, drop=DROP, size=1.0, gap=GAP, friction=FRICTION):
    """Boxes that fall a short height flat onto others and onto the floor, then settle.

    A row of ``base`` boxes on the floor; ``layers`` rows above, each one box shorter and centred
    over the gaps of the row below, its bottom ``drop`` m above that row's top; ``loners`` boxes
    beside the pile falling flat onto the floor from drop, 2 drop, 3 drop m. All start at rest,
    none touching, so every landing is flat and the contact sequence does not depend on dt."""
    if base < 1 or layers < 0 or layers >= base or loners < 0:
        raise ValueError(
            f"landing needs base >= 1, 0 <= layers < base, loners >= 0; got "
            f"base={base}, layers={layers}, loners={loners}"
        )
    pitch = size + gap
    bodies = []
    y = 0.0  # bottom of the current row, m
    for layer in range(layers + 1):
        n = base - layer
        bodies += [
            sim.Body.box(
                size, size, position=((k - (n - 1) / 2) * pitch, y + size / 2), friction=friction
            )
            for k in range(n)
        ]
        y += size + drop
    x0 = (base / 2 + 1.5) * pitch  # clear of the pile's widest row by > 1 m
    bodies += [
        sim.Body.box(
            size,
            size,
            position=(x0 + 1.5 * pitch * j, size / 2 + drop * (j + 1)),
            friction=friction,
        )
        for j in range(loners)
    ]
    return sim.Scene(
        bodies=bodies,
        name="landing",
        params={
            "base": base,
            "layers": layers,
            "loners": loners,
            "drop": drop,
            "size": size,
            "gap": gap,
            "friction": friction,
        },
    )


def make_scene(name, params):
    """The scene called ``name`` (``landing`` or a ``sim.scenes`` builder) built with ``params``."""
    if name == "landing":
        return landing(**params)
    if name not in sim.scenes.BUILDERS:
        raise ValueError(f"unknown scene {name!r}")
    return sim.scenes.BUILDERS[name](**params)


def rest_pose(scene):
    """The exact final pose of a scene, from symmetry and statics, no engine involved: (N,2) m
    centres of mass, (N,) rad. pyramid: it was placed at rest, in equilibrium: the start pose.
    landing: every landing is flat and the scene mirror-symmetric, so no box moves sideways or
    turns; each comes to rest on the row below (rigid bodies: no overlap), row L's centres at
    (L + 1/2) size, the loners' at size / 2."""
    com = np.array([_centre_of_mass(b) for b in scene.bodies])
    angles = np.array([b.angle for b in scene.bodies], dtype=float)
    if scene.name == "pyramid":
        return com, angles
    if scene.name != "landing":
        raise ValueError(f"no exact rest pose known for scene {scene.name!r}")
    p = scene.params
    rows = [layer for layer in range(p["layers"] + 1) for _ in range(p["base"] - layer)]
    rows += [0] * p["loners"]
    com[:, 1] = (np.array(rows) + 0.5) * p["size"]
    return com, np.zeros_like(angles)


def _centre_of_mass(body):
    """World centre of mass of a scene body (m): what every runner reports as its position."""
    _, centroid, _ = mass_properties(body.vertices, body.density)
    c, s = math.cos(body.angle), math.sin(body.angle)
    return np.asarray(body.position, dtype=float) + np.array(
        [c * centroid[0] - s * centroid[1], s * centroid[0] + c * centroid[1]]
    )


def scene_tag(scene):
    """The scene's name in the table (its builder and main sizes)."""
    if scene.name == "landing":
        p = scene.params
        return f"landing({p['base']},{p['layers']},{p['loners']})"
    return common.label(scene)


# ---- the one penetration routine ---------------------------------------------------------------
class Polygons:
    """The scene's polygons, ready for ``deepest_overlap``: every dynamic body's vertices about its
    centre of mass (the pose every runner reports), padded to one vertex count by repeating the
    last vertex (a repeated vertex adds a zero-length edge, which is skipped), the static bodies'
    world vertices, and the floor's height."""

    def __init__(self, scene):
        scene.validate()
        self.n = len(scene.bodies)
        k = max(len(b.vertices) for b in list(scene.bodies) + list(scene.static_bodies))
        self.local = np.empty((self.n, k, 2))  # (N,K,2) m, body frame about the COM
        for i, b in enumerate(scene.bodies):
            _, centroid, _ = mass_properties(b.vertices, b.density)
            self.local[i] = pad(np.asarray(b.vertices, dtype=float) - centroid, k)
        self.statics = np.array([pad(world_vertices(b), k) for b in scene.static_bodies]).reshape(
            len(scene.static_bodies), k, 2
        )  # (S,K,2) m, world
        self.floor_y = scene.floor_y  # m or None

    def world(self, positions, angles):
        """(N,K,2) m: world vertices of every dynamic body at this pose."""
        c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
        x, y = self.local[..., 0], self.local[..., 1]
        return np.stack([c * x - s * y, s * x + c * y], axis=-1) + np.asarray(positions)[:, None]


def deepest_overlap(polygons, positions, angles):
    """The deepest overlap at this pose, m (0 when nothing overlaps): over every pair of dynamic
    bodies, every dynamic-static pair (separating-axis test: the overlap of two convex polygons
    is minus their largest separation along the edge normals of either) and every body against
    the floor (how far its lowest vertex is below floor_y)."""
    w = polygons.world(positions, angles)
    deepest = 0.0
    if polygons.floor_y is not None and len(w):
        deepest = max(deepest, float(polygons.floor_y - w[..., 1].min()))
    others = np.concatenate([w, polygons.statics]) if len(polygons.statics) else w
    lo, hi = w.min(axis=1), w.max(axis=1)  # (N,2) bounding boxes
    olo, ohi = others.min(axis=1), others.max(axis=1)
    touch = ((lo[:, None] <= ohi[None]) & (olo[None] <= hi[:, None])).all(axis=2)
    n = len(w)
    touch[:, :n] &= np.triu(np.ones((n, n), dtype=bool), k=1)  # each dynamic pair once
    i, j = np.nonzero(touch)
    if len(i):
        a, b = w[i], others[j]
        sep = np.maximum(separation(a, b), separation(b, a))
        deepest = max(deepest, float(-sep.min()))
    return max(deepest, 0.0)


# ---- runs --------------------------------------------------------------------------------------
def grid(default, step, exponents):
    """default * 10^(k step) for every k (k = 0 gives the default exactly)."""
    return [default if k == 0 else default * 10.0 ** (k * step) for k in exponents]


def solver_grid(default, exponents):
    """default * 2^k for every k, as whole numbers (a substep or sweep count); ValueError if one
    is not whole or below 1."""
    values = []
    for k in exponents:
        value = default * 2.0**k
        if value < 1 or value != int(value):
            raise ValueError(f"{default} * 2^{k} = {value} is not a whole number >= 1")
        values.append(int(value))
    return values


def accuracy_run(task):
    """One untimed run, sampled every ``sample_every`` steps (executor task: a plain dict).
    Returns the final pose, penetration over the run, and how much was asleep."""
    scene = make_scene(task["scene"], task["scene_params"])
    polygons = Polygons(scene)
    runner = build(task["system"], scene, dt=task["dt"], **task["settings"])
    try:
        every, samples = task["sample_every"], task["samples"]
        deepest = deepest_overlap(polygons, runner.positions, runner.angles)
        awake_sum, all_asleep_at = 0, math.nan
        for s in range(1, samples + 1):
            runner.step(every)
            depth = deepest_overlap(polygons, runner.positions, runner.angles)
            deepest = max(deepest, depth)
            awake = n_awake(runner)
            awake_sum += awake
            if awake == 0 and math.isnan(all_asleep_at):
                all_asleep_at = runner.time
        return {
            "positions": runner.positions,
            "angles": runner.angles,
            "penetration_max_m": deepest,
            "penetration_final_m": depth,
            "n_awake_final": awake,
            "awake_fraction": awake_sum / (samples * polygons.n),
            "all_asleep_at_s": all_asleep_at,
            "settings": runner.settings,
        }
    finally:
        runner.close()


def timed_runs(scene, runs, steps, repeats, progress):
    """Wall times (s) of steps 2..``steps`` of a fresh runner per run, ``repeats`` rounds
    round-robin over the runs (order reversed every other round); also the final pose and awake
    count of the last round. ``runs``: (system, runner settings, label for the progress bar) each;
    ``progress`` a tqdm bar, advanced once per run."""
    times = [[] for _ in runs]
    final = [None] * len(runs)
    order = list(range(len(runs)))
    for r in range(repeats):
        for k in order if r % 2 == 0 else order[::-1]:
            system, settings, label = runs[k]
            progress.set_postfix_str(f"{scene_tag(scene)} {system} {label}")
            runner = build(system, scene, **settings)
            try:
                runner.step(1)  # the first step is not timed
                times[k].append(timed(runner, steps - 1))
                final[k] = (runner.positions, n_awake(runner))
            finally:
                runner.close()
            progress.update()
    return times, final


# ---- the table ---------------------------------------------------------------------------------
#: the CSV's columns, in order (described in the script's docstring)
COLUMNS = [
    "scene",
    "bodies",
    "system",
    "engine",
    "role",
    "parameter",
    "value",
    "unit",
    "is_default",
    "dt_s",
    "steps",
    "repeats",
    "wall_s_median",
    "wall_s_min",
    "wall_s_all",
    "off_wall_s_median",
    "speedup",
    "speedup_min",
    "n_awake_final",
    "awake_fraction",
    "all_asleep_at_s",
    "pose_error_max_m",
    "pose_error_mean_m",
    "angle_error_max_rad",
    "exact_error_max_m",
    "exact_angle_error_max_rad",
    "freeze_error_max_m",
    "freeze_angle_error_max_rad",
    "penetration_max_m",
    "penetration_final_m",
    "replay_difference_m",
]


def error_row(
    tag,
    scene,
    *,
    system,
    engine,
    role,
    parameter,
    unit,
    value,
    is_default,
    dt,
    steps,
    res,
    ref,
    exact,
    off=None,
):
    """One table row (every column of ``COLUMNS``; the timing columns NaN, for the caller to fill):
    the run ``res``'s pose errors against its engine's reference ``ref`` (none for the reference
    itself) and against the exact pose ``exact`` (positions, angles), its penetration and how
    much of it slept.

    ``off``: the same engine's run with sleeping off at the same dt and default settings (the
    baseline), given for the freezing rows (roles baseline and sweep). Their ``freeze_error_*``
    is the pose difference from it: the error freezing adds, apart from the engine's own solver
    error (the baseline's error against the reference). NaN for the other roles."""
    if role == "reference":
        d_max = d_mean = a_max = math.nan  # the reference itself: no error to speak of
    else:
        d_max, a_max = pose_error(res["positions"], res["angles"], ref["positions"], ref["angles"])
        d_mean = float(np.hypot(*(res["positions"] - ref["positions"]).T).mean())
    e_max, e_angle = pose_error(res["positions"], res["angles"], *exact)
    row = dict.fromkeys(COLUMNS, math.nan)
    if off is not None:
        row["freeze_error_max_m"], row["freeze_angle_error_max_rad"] = pose_error(
            res["positions"], res["angles"], off["positions"], off["angles"]
        )
    row.update(
        exact_error_max_m=e_max,
        exact_angle_error_max_rad=e_angle,
        scene=tag,
        bodies=len(scene.bodies),
        system=system,
        engine=engine,
        role=role,
        parameter=parameter,
        value=value,
        unit=unit,
        is_default=bool(is_default),
        dt_s=dt,
        steps=steps,
        n_awake_final=res["n_awake_final"],
        awake_fraction=res["awake_fraction"],
        all_asleep_at_s=res["all_asleep_at_s"],
        pose_error_max_m=d_max,
        pose_error_mean_m=d_mean,
        angle_error_max_rad=a_max,
        penetration_max_m=res["penetration_max_m"],
        penetration_final_m=res["penetration_final_m"],
    )
    return row
