"""The failure catalogue's scenarios: small scenes where freezing resting bodies can go wrong, each
with the outcome physics expects and a classifier that reads the outcome off a final pose.

Every scenario is built from ``sim.Body`` / ``sim.Scene`` with only what its question needs, and is
a ``Scenario``: ``build(**overrides)`` (the scene; keyword overrides change its parameters, for the
later study of numerical extremes), ``seconds`` it runs (``duration(scene)``), ``event_s`` when
the danger arrives, ``classify(scene, positions, angles)`` -> an outcome label (one of
``labels``), ``measure(scene, positions, angles)`` -> the one continuous quantity the label is
judged on (``measure_name``, unit in the name) and ``expected``, the label physics says. Every body
is named; ``key_bodies(scene)`` are all but those named "projectile..." (the bodies the question
is about: pose errors are taken over them).

The dangers come from the seed paper's own admitted limits (``docs/seed/translation.md`` section
6: no general rest test, no way back to motion, two bodies only; and section 5.2's "an edge
parallel to the floor is treated exactly like the floor") and from the engines' known ones (a body
is put to sleep when it is merely slow: slow sliding, creeping down a slope, tipping slowly out of
an unstable equilibrium).

Anything that must happen *after everything froze* is scheduled by time, since runners cannot be
edited mid-run: a projectile starts far away and slides towards its target on a frictionless
surface (the floor, for a projectile of friction 0, since pairs mix friction by geometric mean; or
a static shelf of friction 0), so it arrives at ``arrive_s`` (default 3.5 s: after Bullet's fixed
2 s of deactivation time, the slowest sleeper of the study, plus time to settle). A projectile
sliding at constant speed arrives at the same time in every engine (Chipmunk's integration order
moves it v dt further, 0.07 m at 4 m/s: 17 ms earlier), which a falling or thrown one would not.

Scenarios (each builder's docstring has its geometry and the physics of its expected outcome):

    support_removed       a load resting on a support that a projectile knocks away  -> fell
    overhang              seed figure 3: A slides off B's edge                       -> fell off
    tipping               a tall box at rest on its corner, centre of mass outside   -> toppled
    unstable_equilibrium  a plank whose centre of mass is 2 mm past its support edge -> tipped off
    slow_sliding          a box sliding slower than every sleep threshold            -> slid
    slope_creep           a box creeping down a slope just steeper than friction     -> slid
    impact_on_stack       a projectile hits the top box of a frozen 4-box column     -> toppled
    load_on_overhang      a load slides onto the overhanging end of a frozen plank   -> tipped
    wake_cascade          a projectile tips the first of a row of frozen dominoes    -> all fell
    three_bodies          three boxes, each over the one below, the top two together
                          past the bottom's edge (the seed's two-body rule passes)    -> toppled
    unstable_ledge        unstable_equilibrium's danger on a static ledge: a block   -> tipped off
    slow_glide            slow_sliding's danger with a hexagon on ice                -> slid
    slope_creep_plank     slope_creep's danger with a wide plank, higher friction    -> slid

The last three repeat a danger with other geometry: they were added when ``extended``'s rest test
became a certificate of equilibrium (it fixed the first of each kind), to check the fix is not
tied to one scene.

Units: metres, seconds, kilograms (per square metre for densities), radians.
"""

from dataclasses import dataclass
import inspect
import math
from typing import Callable

import numpy as np

import sim

G = 9.81  # m/s^2, every scene's gravity (sim.Scene's default)
ARRIVE_S = 3.5  # s, when a scheduled projectile reaches its target (see above)
SHELF_THICKNESS = 0.2  # m, static shelves a projectile slides along
SHELF_GAP = 0.05  # m, between a shelf's end and the body it leads to


@dataclass(frozen=True)
class Scenario:
    """One entry of the catalogue (see the module docstring)."""

    name: str
    question: str  # what can go wrong, and whose limit it is
    builder: Callable  # builder(**params) -> sim.Scene
    seconds: float  # s simulated
    expected: str  # the outcome physics says
    labels: tuple  # every label classify can return
    classifier: Callable  # classifier(scene, positions, angles) -> label
    measurer: Callable  # measurer(scene, positions, angles) -> float
    measure_name: str  # what measure() returns, with its unit in the name
    event_s: float | None = None  # s, when the danger arrives (None: from the start)

    @property
    def params(self):
        """The builder's parameters and their defaults (the catalogue's scene)."""
        return {k: p.default for k, p in inspect.signature(self.builder).parameters.items()}

    def build(self, **overrides):
        """The scene, with parameters overridden by keyword (unknown names are an error)."""
        unknown = sorted(set(overrides) - set(self.params))
        if unknown:
            raise ValueError(
                f"scenario {self.name}: unknown parameter(s) {', '.join(unknown)}; "
                f"it takes {', '.join(sorted(self.params)) or 'none'}"
            )
        return self.builder(**{**self.params, **overrides})

    def classify(self, scene, positions, angles):
        """The outcome label of a final pose: positions (N,2) m, angles (N,) rad."""
        positions, angles = _pose(scene, positions, angles)
        label = self.classifier(scene, positions, angles)
        if label not in self.labels:
            raise RuntimeError(
                f"scenario {self.name}: classifier returned {label!r}, not one of {self.labels}"
            )
        return label

    def measure(self, scene, positions, angles):
        """The continuous quantity behind the label (``measure_name``), of a final pose."""
        positions, angles = _pose(scene, positions, angles)
        return float(self.measurer(scene, positions, angles))

    def event_time(self, scene):
        """When the danger arrives in ``scene``, s (its ``arrive_s`` if it was built with
        another), or None when it is there from the start."""
        if self.event_s is None:
            return None
        return float(scene.params.get("arrive_s", self.event_s))

    def duration(self, scene):
        """Seconds to run ``scene`` (a scene may carry its own, as slope_creep does: its
        expected distance depends on it)."""
        return float(scene.params.get("seconds", self.seconds))


def _pose(scene, positions, angles):
    """Validated (N,2) m and (N,) rad arrays for ``scene``'s bodies."""
    positions = np.asarray(positions, dtype=float)
    angles = np.asarray(angles, dtype=float)
    n = len(scene.bodies)
    if positions.shape != (n, 2) or angles.shape != (n,):
        raise ValueError(
            f"scene {scene.name}: expected positions ({n}, 2) and angles ({n},), "
            f"got {positions.shape} and {angles.shape}"
        )
    if not (np.isfinite(positions).all() and np.isfinite(angles).all()):
        raise ValueError(f"scene {scene.name}: the pose is not finite")
    return positions, angles


# ---- geometry of a final pose ------------------------------------------------------------------
def wrap(angle):
    """Angle(s) mapped to (-pi, pi], rad (engines report unwrapped angles)."""
    return np.angle(np.exp(1j * np.asarray(angle, dtype=float)))


def world_vertices(scene, i, position, angle):
    """(K,2) m: world vertices of dynamic body ``i`` with its centre of mass at ``position``."""
    body = scene.bodies[i]
    local = body.vertices - body.centroid
    c, s = math.cos(angle), math.sin(angle)
    return local @ np.array([[c, s], [-s, c]]) + np.asarray(position, dtype=float)


def bottom(scene, positions, angles, i):
    """Lowest point of body ``i``, m."""
    return float(world_vertices(scene, i, positions[i], angles[i])[:, 1].min())


def index(scene, name):
    """Index of the dynamic body called ``name`` (builders name every body they place)."""
    for i, b in enumerate(scene.bodies):
        if b.name == name:
            return i
    raise ValueError(f"scene {scene.name}: no body named {name!r}")


def key_bodies(scene):
    """Indices of every body that is not a projectile: the structure the question is about.
    (A projectile's own end pose says nothing about freezing and can lie anywhere.)"""
    return [i for i, b in enumerate(scene.bodies) if not b.name.startswith("projectile")]


def _shelf(x_from, x_to, top):
    """A static, frictionless shelf from x_from to x_to (m) whose top face is at ``top``."""
    return sim.Body.box(
        x_to - x_from,
        SHELF_THICKNESS,
        position=(0.5 * (x_from + x_to), top - 0.5 * SHELF_THICKNESS),
        friction=0.0,
        name="shelf",
    )


# ---- 1. support removed ------------------------------------------------------------------------
def support_removed(speed=4.0, arrive_s=ARRIVE_S, load_friction=0.05):
    """A load (0.8 x 0.4 m) rests on a support (1 x 1 m box, mu 0.6); a heavy low projectile
    (1.0 x 0.3 m, 3 kg, friction 0) slides along the floor at ``speed`` m/s and hits the support's
    foot at ``arrive_s``. The support and projectile leave together (inelastic: 3 m/s at the
    defaults, decelerated by the support's floor friction over ~3 m). The load is nearly
    frictionless (``load_friction`` 0.05: 0.17 with the support, geometric mean), so the support
    is pulled from under it as a tablecloth is (friction drags the load at most
    mu g t^2 / 2 = 8 cm in the 0.3 s the support takes to pass), and it must fall 1 m to the floor
    (the projectile, low and fast, has passed before the load comes down to its height).

    Why 0.05 and not 0 (it was 0 before solver v2): a load resting on a frictionless support keeps
    whatever horizontal velocity the solve leaves it, and solver v2 leaves round-off (1e-22 m/s);
    ``paper`` freezes a rotation-stable body only once Coulomb friction has stopped it, so with
    mu = 0 it slid at 1e-22 m/s for ever and was never frozen: the danger met no frozen load.
    Any friction stops it within a step. The question is the same: the support is still pulled
    from under the load, and the load must still fall.

    Danger: nothing touches the load; only its support moves (the seed's second limit: nothing
    wakes a body whose support is knocked away, it floats)."""
    gap = speed * arrive_s
    bodies = [
        sim.Body.box(1.0, 1.0, position=(0.0, 0.5), friction=0.6, name="support"),
        sim.Body.box(0.8, 0.4, position=(0.0, 1.2), friction=load_friction, name="load"),
        sim.Body.box(
            1.0,
            0.3,
            position=(-0.5 - gap - 0.5, 0.15),
            velocity=(speed, 0.0),
            friction=0.0,
            density=10.0,
            name="projectile",
        ),
    ]
    return sim.Scene(
        bodies=bodies,
        name="support_removed",
        params={"speed": speed, "arrive_s": arrive_s, "load_friction": load_friction},
    )


def _support_removed_outcome(scene, p, a):
    load, support = index(scene, "load"), index(scene, "support")
    low = bottom(scene, p, a, load)
    if low < 0.05:
        return "fell"
    s = world_vertices(scene, support, p[support], a[support])
    under = s[:, 0].min() <= p[load, 0] <= s[:, 0].max() and abs(s[:, 1].max() - low) < 0.05
    return "stayed" if under else "floating"


# ---- 2. overhang (seed figure 3) ---------------------------------------------------------------
def overhang(speed=2.5, friction=0.2):
    """Seed figure 3 (``sim.scenes.seed_fig3``): A (0.8 x 0.4) rests on B (2 x 1) and slides right
    at ``speed`` m/s with friction ``friction``; it would slide v^2 / (2 mu g) = 1.6 m on an
    endless surface, so its centre of mass passes B's edge (0.9 m away) and it falls to the floor.

    Danger: the seed's rule for it (section 5.2) exists; sleeping sees a body slow near the edge."""
    scene = sim.scenes.seed_fig3(speed=speed, friction=friction)
    scene.name = "overhang"
    return scene


def _overhang_measure(scene, p, a):
    return float(p[index(scene, "A"), 1])


def _overhang_outcome(scene, p, a):
    return "fell off" if _overhang_measure(scene, p, a) < 1.0 else "stayed on"  # B's top: 1 m


# ---- 3. tipping ---------------------------------------------------------------------------------
def tipping(width=0.5, height=2.0, past_deg=5.0, friction=0.6):
    """A ``width`` x ``height`` box starts at rest standing on one corner, tilted ``past_deg``
    beyond its tipping angle atan(width / height) (14.0 degrees), so its centre of mass is outside
    its support (the corner): it must topple onto its long side (|angle| -> 90 degrees).

    Danger: it starts at rest, slow at first (seed limit 1, no general rest test)."""
    angle = math.atan(width / height) + math.radians(past_deg)
    lowest = -0.5 * width * math.sin(angle) - 0.5 * height * math.cos(angle)
    body = sim.Body.box(
        width, height, position=(0.0, -lowest), angle=angle, friction=friction, name="box"
    )
    return sim.Scene(
        bodies=[body],
        name="tipping",
        params={"width": width, "height": height, "past_deg": past_deg, "friction": friction},
    )


def _tipping_measure(scene, p, a):
    return float(abs(wrap(a[0])))


def _tipping_outcome(scene, p, a):
    tilt = _tipping_measure(scene, p, a)
    if tilt > math.radians(75.0):
        return "toppled"
    return "upright" if tilt < math.radians(5.0) else "stuck leaning"


# ---- 4. unstable equilibrium -------------------------------------------------------------------
def unstable_equilibrium(past=0.002, length=2.0, thickness=0.2, friction=0.6):
    """A plank (``length`` x ``thickness``) lies on a 1 x 1 m box with its centre of mass ``past``
    m beyond the box's right edge. No support point is under its centre of mass, so it must tip
    about the edge: slowly at first (tilt ~ (past / (thickness / 2)) (cosh(k t) - 1), k = 1.7/s:
    0.5 rad after ~2.3 s for 2 mm), then it slides off and falls.

    Danger: for the first second it moves less than every sleep threshold (engines' known limit,
    seed limit 1)."""
    support = sim.Body.box(1.0, 1.0, position=(0.0, 0.5), friction=friction, name="support")
    plank = sim.Body.box(
        length,
        thickness,
        position=(0.5 + past, 1.0 + 0.5 * thickness),
        friction=friction,
        name="plank",
    )
    return sim.Scene(
        bodies=[support, plank],
        name="unstable_equilibrium",
        params={"past": past, "length": length, "thickness": thickness, "friction": friction},
    )


def unstable_ledge(past=0.001, length=1.5, thickness=0.3, friction=0.6):
    """``unstable_equilibrium`` with other geometry: a thicker block (``length`` x ``thickness``)
    lies on a static ledge (a 1 x 1 m static box) with its centre of mass ``past`` m beyond the
    ledge's edge. Its support cannot move, so only the block's own rest test decides: it must tip
    about the edge, slowly at first (as the plank does), and fall.

    Danger: as unstable_equilibrium's, on an immovable support: the block is slow for a second
    or more, and rests on two points (a whole face), not one."""
    ledge = sim.Body.box(1.0, 1.0, position=(0.0, 0.5), friction=friction, name="ledge")
    block = sim.Body.box(
        length,
        thickness,
        position=(0.5 + past, 1.0 + 0.5 * thickness),
        friction=friction,
        name="plank",
    )
    return sim.Scene(
        bodies=[block],
        static_bodies=[ledge],
        name="unstable_ledge",
        params={"past": past, "length": length, "thickness": thickness, "friction": friction},
    )


def _unstable_measure(scene, p, a):
    """How far the plank's centre dropped, m."""
    plank = index(scene, "plank")
    return float(scene.bodies[plank].position[1] - p[plank, 1])


def _unstable_outcome(scene, p, a):
    """ "tipped off": the plank came down to the floor (one end, or all of it, on it); "balanced":
    still flat on the box; "stuck tilted": tilted yet touching nothing but the box's corner,
    which cannot be a resting pose (it was frozen mid-tip)."""
    plank = index(scene, "plank")
    if bottom(scene, p, a, plank) < 0.02:
        return "tipped off"
    return "balanced" if abs(wrap(a[plank])) < 0.05 else "stuck tilted"


# ---- 5. slow sliding ---------------------------------------------------------------------------
def slow_sliding(speed=0.04, friction=0.001):
    """``sim.scenes.sliding_box``: a unit box slides on the floor at ``speed`` m/s (below every
    system's sleep speed: sim-sleep 0.05 m/s, Chipmunk's idle speed g dt = 0.16 m/s, Bullet's
    sqrt(0.05) = 0.22 m/s, extended's rest speed 0.02 m/s is crossed halfway) with Coulomb
    friction ``friction`` (floor and box alike): it must travel v^2 / (2 mu g) = 8.2 cm at the
    defaults, stopping after v / (mu g) = 4.1 s.

    Danger: a slow body is not a resting one (engines' known limit, seed limit 1)."""
    scene = sim.scenes.sliding_box(speed=speed, friction=friction)
    scene.name = "slow_sliding"
    scene.bodies[0].name = "box"
    return scene


def slow_glide(speed=0.05, friction=0.002, radius=0.4):
    """``slow_sliding`` with other geometry: a hexagon (circumradius ``radius``, resting on a
    flat edge) glides on the floor at ``speed`` m/s with Coulomb friction ``friction`` (floor and
    body alike): v^2 / (2 mu g) = 6.4 cm at the defaults, stopping after v / (mu g) = 2.5 s; it
    is under extended's rest speed for its last 1.0 s.

    Danger: as slow_sliding's, for a body with more than one contact point and rotational
    inertia of its own."""
    body = sim.Body.regular(6, radius, velocity=(speed, 0.0), friction=friction, name="box")
    body.position = (0.0, radius * math.cos(math.pi / 6))
    return sim.Scene(
        bodies=[body],
        floor_friction=friction,
        name="slow_glide",
        params={"speed": speed, "friction": friction, "radius": radius},
    )


def _slide_expected(scene):
    v, mu = scene.params["speed"], scene.params["friction"]
    return v * v / (2.0 * mu * G)


def _slide_measure(scene, p, a):
    """Distance slid as a fraction of v^2 / (2 mu g)."""
    return float((p[0, 0] - scene.bodies[0].position[0]) / _slide_expected(scene))


def _fraction_outcome(fraction):
    if fraction < 0.1:
        return "stuck"
    if fraction < 0.9:
        return "stopped short"
    return "slid" if fraction <= 1.1 else "slid too far"


# ---- 6. slope creep ----------------------------------------------------------------------------
def slope_creep(acceleration=0.05, friction=0.3, size=0.5, seconds=6.0):
    """A ``size`` box on a static ramp whose slope is just steeper than its friction angle, so it
    slides down from rest at a = g (sin(theta) - mu cos(theta)) = ``acceleration`` m/s^2 (theta =
    16.98 degrees at the defaults, friction atan(0.3) = 16.70 degrees): 0.9 m in 6 s, at 0.3 m/s at
    the end but only 0.025 m/s after 0.5 s.

    Danger: it accelerates slower than extended's rest_acceleration (0.1 m/s^2) and stays under
    every sleep speed for seconds (engines' known limit: sleeping on a slope)."""
    return _on_ramp(
        "slope_creep",
        acceleration,
        friction,
        size,
        size,
        {"acceleration": acceleration, "friction": friction, "size": size, "seconds": seconds},
    )


def _on_ramp(name, acceleration, friction, width, height, params):
    """A ``width`` x ``height`` box at rest on a static ramp steep enough that it slides down at
    ``acceleration`` m/s^2 with Coulomb friction ``friction``; ``params`` plus the slope
    (theta_rad) are the scene's parameters."""
    # solve sin(t) - mu cos(t) = a / g for t by Newton's method (a few steps from atan(mu))
    theta = math.atan(friction)
    for _ in range(20):
        theta -= (math.sin(theta) - friction * math.cos(theta) - acceleration / G) / (
            math.cos(theta) + friction * math.sin(theta)
        )
    length = 10.0
    top = length * math.tan(theta)
    ramp = sim.Body(
        vertices=[(0.0, 0.0), (length, 0.0), (0.0, top)], friction=friction, name="ramp"
    )
    along = 2.0  # m from the ramp's top corner, down the slope
    surface = np.array([along * math.cos(theta), top - along * math.sin(theta)])
    normal = np.array([math.sin(theta), math.cos(theta)])
    centre = surface + 0.5 * height * normal
    box = sim.Body.box(
        width, height, position=tuple(centre), angle=-theta, friction=friction, name="box"
    )
    return sim.Scene(
        bodies=[box], static_bodies=[ramp], name=name, params={**params, "theta_rad": theta}
    )


def slope_creep_plank(acceleration=0.03, friction=0.5, width=1.2, height=0.25, seconds=6.0):
    """``slope_creep`` with other geometry: a long low plank (``width`` x ``height``) on a ramp
    whose slope is just steeper than a higher friction's angle (atan(0.5) = 26.57 degrees), so it
    slides from rest at a = ``acceleration`` m/s^2: 0.54 m in 6 s, under 0.02 m/s for 0.7 s.

    Danger: as slope_creep's, for a body whose supports are far apart (a wide contact holds no
    better against sliding)."""
    return _on_ramp(
        "slope_creep_plank",
        acceleration,
        friction,
        width,
        height,
        {
            "acceleration": acceleration,
            "friction": friction,
            "width": width,
            "height": height,
            "seconds": seconds,
        },
    )


def _slope_measure(scene, p, a):
    """Distance slid down the slope as a fraction of a t^2 / 2."""
    theta = scene.params["theta_rad"]
    down = np.array([math.cos(theta), -math.sin(theta)])
    travelled = float((p[0] - np.asarray(scene.bodies[0].position)) @ down)
    t = scene.params["seconds"]
    return travelled / (0.5 * scene.params["acceleration"] * t * t)


# ---- 7. impact on a frozen stack ---------------------------------------------------------------
def impact_on_stack(height=4, speed=4.0, arrive_s=ARRIVE_S, projectile_density=12.0):
    """A column of ``height`` unit boxes (mu 0.6); a heavy projectile (0.5 x 0.5 m, 3 kg at the
    defaults) slides along a frictionless static shelf level with the top box's base and hits the
    top box's lower half at ``speed`` m/s at ``arrive_s``. Its momentum (12 N s), delivered 3.25 m
    up a 4 kg column, tips the whole column over about the bottom box's far corner: every box,
    the bottom one included, ends on the floor (checked at dt/8).

    Danger: a hit on one frozen body must wake it and pass its momentum down through bodies that
    are not hit (seed section 3: a rotation-stable body is special only until a collision; its
    second limit: nothing else wakes a body)."""
    top = float(height - 1)  # m, the top box's base
    gap = speed * arrive_s
    bodies = [
        sim.Body.box(1.0, 1.0, position=(0.0, 0.5 + k), friction=0.6, name=f"box {k}")
        for k in range(height)
    ]
    x_face = -0.5 - gap  # the projectile's front face at t = 0
    bodies.append(
        sim.Body.box(
            0.5,
            0.5,
            position=(x_face - 0.25, top + 0.25),
            velocity=(speed, 0.0),
            friction=0.6,
            density=projectile_density,
            name="projectile",
        )
    )
    shelf = _shelf(x_face - 1.0, -0.5 - SHELF_GAP, top)
    return sim.Scene(
        bodies=bodies,
        static_bodies=[shelf],
        name="impact_on_stack",
        params={
            "height": height,
            "speed": speed,
            "arrive_s": arrive_s,
            "projectile_density": projectile_density,
        },
    )


def _moved(scene, p, a, i):
    """How far body i's centre moved from its start, m."""
    return float(np.hypot(*(p[i] - np.asarray(scene.bodies[i].position))))


def _impact_measure(scene, p, a):
    """How far the column's bottom box moved, m."""
    return _moved(scene, p, a, 0)


def _impact_outcome(scene, p, a):
    """A box "moved" if its centre moved 0.1 m or it turned 0.1 rad. "toppled": the bottom box
    moved (the column went over as a whole); "stood": nothing moved; "top knocked off": only the
    top box moved; "base stayed": boxes above the bottom one moved, the bottom one did not (the
    column broke above a base that never woke)."""
    height = scene.params["height"]
    moved = [_moved(scene, p, a, k) > 0.1 or abs(wrap(a[k])) > 0.1 for k in range(height)]
    if moved[0]:
        return "toppled"
    if not any(moved):
        return "stood"
    return "top knocked off" if not any(moved[:-1]) else "base stayed"


# ---- 8. load on an overhang --------------------------------------------------------------------
def load_on_overhang(speed=2.0, arrive_s=ARRIVE_S, length=3.0, com_inside=0.2):
    """A plank (``length`` x 0.2 m, 0.6 kg) lies on a column of two unit boxes, overhanging to the
    right, its centre of mass ``com_inside`` m inside the column's edge (it rests). A 1 kg load
    (0.5 x 0.5 m, mu 0.6) slides in from the right along a frictionless static shelf 1 cm above
    the plank's top and onto the plank's overhanging end at ``arrive_s``, where friction stops it
    within 0.35 m: its weight ~1 m beyond the edge outweighs the plank's 0.2 m inside (moment
    ~10 N m against 1.2 N m), so the plank must tip over the edge.

    Danger: the seed treats a rotation-stable body's floor-parallel top edge "exactly like the
    floor" (section 5.2), so a body landing on it never loads it; and a load on an overhang is a
    three-body problem (plank, column, load)."""
    top = 2.2  # m, the plank's top face
    plank_x = 0.5 - com_inside  # the column's right edge is at x = 0.5
    x_end = plank_x + 0.5 * length  # the plank's overhanging end
    gap = speed * arrive_s
    shelf_from = x_end + SHELF_GAP
    bodies = [
        sim.Body.box(1.0, 1.0, position=(0.0, 0.5), friction=0.6, name="box 0"),
        sim.Body.box(1.0, 1.0, position=(0.0, 1.5), friction=0.6, name="box 1"),
        sim.Body.box(length, 0.2, position=(plank_x, top - 0.1), friction=0.6, name="plank"),
        sim.Body.box(
            0.5,
            0.5,
            position=(x_end + gap + 0.25, top + 0.01 + 0.25),
            velocity=(-speed, 0.0),
            friction=0.6,
            density=4.0,
            name="projectile load",
        ),
    ]
    shelf = _shelf(shelf_from, x_end + gap + 1.5, top + 0.01)
    return sim.Scene(
        bodies=bodies,
        static_bodies=[shelf],
        name="load_on_overhang",
        params={"speed": speed, "arrive_s": arrive_s, "length": length, "com_inside": com_inside},
    )


def _plank_tilt(scene, p, a):
    return float(abs(wrap(a[index(scene, "plank")])))


def _load_outcome(scene, p, a):
    """ "tipped": the plank's centre dropped 0.2 m or it turned 0.2 rad; else "held"."""
    plank = index(scene, "plank")
    dropped = scene.bodies[plank].position[1] - p[plank, 1]
    return "tipped" if dropped > 0.2 or _plank_tilt(scene, p, a) > 0.2 else "held"


# ---- 9. wake cascade ---------------------------------------------------------------------------
def wake_cascade(
    n=8, pitch=0.6, width=0.15, height=1.0, speed=2.0, arrive_s=ARRIVE_S, projectile_density=12.0
):
    """A row of ``n`` dominoes (``width`` x ``height``, mu 0.6, ``pitch`` apart); a small, dense
    projectile (0.25 x 0.25 m, 0.75 kg at the defaults: 1.5 N s at 2 m/s, above both policies'
    impulse thresholds, so the first domino is woken by every policy) slides along a frictionless
    static shelf whose top is at 0.7 ``height`` and strikes the first domino high up at
    ``arrive_s``, tipping it onto the next: each falling domino tips the next, and all must fall
    (pitch < height).

    Danger: every domino must be woken by its neighbour's fall, a weak, slow impact (a falling
    domino carries ~0.1 N s, under both impulse thresholds), through the whole row."""
    gap = speed * arrive_s
    shelf_top = 0.7 * height
    bodies = [
        sim.Body.box(
            width, height, position=(k * pitch, 0.5 * height), friction=0.6, name=f"domino {k}"
        )
        for k in range(n)
    ]
    x_face = -0.5 * width - gap
    bodies.append(
        sim.Body.box(
            0.25,
            0.25,
            position=(x_face - 0.125, shelf_top + 0.125),
            velocity=(speed, 0.0),
            friction=0.6,
            density=projectile_density,
            name="projectile",
        )
    )
    shelf = _shelf(x_face - 1.0, -0.5 * width - SHELF_GAP, shelf_top)
    return sim.Scene(
        bodies=bodies,
        static_bodies=[shelf],
        name="wake_cascade",
        params={
            "n": n,
            "pitch": pitch,
            "width": width,
            "height": height,
            "speed": speed,
            "arrive_s": arrive_s,
            "projectile_density": projectile_density,
        },
    )


def _dominoes_fallen(scene, p, a):
    """How many dominoes lean more than 0.2 rad (11 degrees; one resting on the next leans
    asin((pitch - width) / height) = 27 degrees, a standing one 0)."""
    n = scene.params["n"]
    return int(np.count_nonzero(np.abs(wrap(a[:n])) > 0.2))


def _cascade_outcome(scene, p, a):
    n = scene.params["n"]
    k = _dominoes_fallen(scene, p, a)
    if k == n:
        return "all fell"
    return "none fell" if k == 0 else "some fell"


# ---- 10. three bodies --------------------------------------------------------------------------
def three_bodies(offset=0.4, width=1.0, thickness=0.5):
    """Three ``width`` x ``thickness`` boxes stacked like a staircase, each ``offset`` m right of
    the one below: each centre of mass is over the box directly below it (the seed's two-body
    test passes for every pair), but the top two together have their centre of mass at 1.5
    ``offset`` = 0.6 m, beyond the bottom box's edge at 0.5 m, so the top two must topple off.

    Danger: the seed's third limit, collisions among three or more bodies are not handled."""
    bodies = [
        sim.Body.box(
            width,
            thickness,
            position=(k * offset, (k + 0.5) * thickness),
            friction=0.6,
            name=f"box {k}",
        )
        for k in range(3)
    ]
    return sim.Scene(
        bodies=bodies,
        name="three_bodies",
        params={"offset": offset, "width": width, "thickness": thickness},
    )


def _three_measure(scene, p, a):
    """How far the top box's centre dropped, m."""
    return float(scene.bodies[2].position[1] - p[2, 1])


def _three_outcome(scene, p, a):
    return "toppled" if _three_measure(scene, p, a) > 0.5 * scene.params["thickness"] else "stood"


# ---- the catalogue -----------------------------------------------------------------------------
def _catalogue():
    s = [
        Scenario(
            "support_removed",
            "a support knocked away from under a frozen load (seed limit 2: no way back to motion)",
            support_removed,
            6.0,
            "fell",
            ("fell", "stayed", "floating"),
            _support_removed_outcome,
            lambda sc, p, a: bottom(sc, p, a, index(sc, "load")),
            "load_bottom_m",
            event_s=ARRIVE_S,
        ),
        Scenario(
            "overhang",
            "seed figure 3: a body sliding off its support's edge",
            overhang,
            4.0,
            "fell off",
            ("fell off", "stayed on"),
            _overhang_outcome,
            _overhang_measure,
            "A_height_m",
        ),
        Scenario(
            "tipping",
            "a body at rest on a corner, centre of mass outside (seed limit 1)",
            tipping,
            4.0,
            "toppled",
            ("toppled", "upright", "stuck leaning"),
            _tipping_outcome,
            _tipping_measure,
            "tilt_rad",
        ),
        Scenario(
            "unstable_equilibrium",
            "a plank 2 mm past its support's edge tips slowly at "
            "first (engines' sleep; seed limit 1)",
            unstable_equilibrium,
            6.0,
            "tipped off",
            ("tipped off", "balanced", "stuck tilted"),
            _unstable_outcome,
            _unstable_measure,
            "plank_drop_m",
        ),
        Scenario(
            "slow_sliding",
            "a body sliding slower than the sleep thresholds (engines' sleep; seed limit 1)",
            slow_sliding,
            6.0,
            "slid",
            ("stuck", "stopped short", "slid", "slid too far"),
            lambda sc, p, a: _fraction_outcome(_slide_measure(sc, p, a)),
            _slide_measure,
            "slide_fraction",
        ),
        Scenario(
            "slope_creep",
            "a body creeping down a slope just past its friction angle (engines' sleep)",
            slope_creep,
            6.0,
            "slid",
            ("stuck", "stopped short", "slid", "slid too far"),
            lambda sc, p, a: _fraction_outcome(_slope_measure(sc, p, a)),
            _slope_measure,
            "slide_fraction",
        ),
        Scenario(
            "unstable_ledge",
            "unstable_equilibrium on an immovable ledge: a block 1 mm past its edge",
            unstable_ledge,
            6.0,
            "tipped off",
            ("tipped off", "balanced", "stuck tilted"),
            _unstable_outcome,
            _unstable_measure,
            "plank_drop_m",
        ),
        Scenario(
            "slow_glide",
            "slow_sliding with a hexagon on near-frictionless ice",
            slow_glide,
            4.0,
            "slid",
            ("stuck", "stopped short", "slid", "slid too far"),
            lambda sc, p, a: _fraction_outcome(_slide_measure(sc, p, a)),
            _slide_measure,
            "slide_fraction",
        ),
        Scenario(
            "slope_creep_plank",
            "slope_creep with a wide plank and a higher friction",
            slope_creep_plank,
            6.0,
            "slid",
            ("stuck", "stopped short", "slid", "slid too far"),
            lambda sc, p, a: _fraction_outcome(_slope_measure(sc, p, a)),
            _slope_measure,
            "slide_fraction",
        ),
        Scenario(
            "impact_on_stack",
            "a projectile hits a frozen stack's top box (seed section 3)",
            impact_on_stack,
            6.0,
            "toppled",
            ("toppled", "stood", "top knocked off", "base stayed"),
            _impact_outcome,
            _impact_measure,
            "base_moved_m",
            event_s=ARRIVE_S,
        ),
        Scenario(
            "load_on_overhang",
            "a load lands on a frozen plank's overhanging end (seed "
            "5.2: an edge treated as the floor; three bodies)",
            load_on_overhang,
            6.0,
            "tipped",
            ("tipped", "held"),
            _load_outcome,
            _plank_tilt,
            "plank_tilt_rad",
            event_s=ARRIVE_S,
        ),
        Scenario(
            "wake_cascade",
            "a row of frozen dominoes, each woken by its neighbour's fall",
            wake_cascade,
            7.0,
            "all fell",
            ("all fell", "some fell", "none fell"),
            _cascade_outcome,
            _dominoes_fallen,
            "dominoes_fallen",
            event_s=ARRIVE_S,
        ),
        Scenario(
            "three_bodies",
            "three bodies: the top two together past the bottom's edge (seed limit 3)",
            three_bodies,
            3.0,
            "toppled",
            ("toppled", "stood"),
            _three_outcome,
            _three_measure,
            "top_drop_m",
        ),
    ]
    return {x.name: x for x in s}


#: name -> Scenario, in the catalogue's order
SCENARIOS = _catalogue()


def get(name):
    """The scenario called ``name``; a clear error for an unknown one."""
    try:
        return SCENARIOS[name]
    except KeyError:
        raise ValueError(
            f"unknown scenario {name!r}; choose one of {', '.join(SCENARIOS)}"
        ) from None
