"""A ``sim.Scene`` built and stepped in Box2D 2.3 (pybox2d), observed like a ``sim.World``.

Matching sim's conventions
- A Box2D body's origin is its centre of mass: every polygon is given with its vertices relative
  to its centroid (sim.geometry.mass_properties), and mass and rotational inertia are set to sim's
  own values with ``massData`` (fixtures have density 0, so Box2D never recomputes them).
- Friction and restitution mix exactly as in sim without help: Box2D 2.3's b2MixFriction is
  sqrt(mu_a mu_b) (geometric mean) and b2MixRestitution max(e_a, e_b). Impacts slower than
  b2_velocityThreshold (1 m/s, sim's restitution_threshold default) do not bounce; that
  threshold is a compile-time constant in Box2D 2.3, so it cannot follow a sim setting.
- Box2D gives every polygon a skin of b2_polygonRadius (0.01 m): contacts are made and resolved
  on the polygon grown by that radius, so a box given as is would rest 1.5 cm above the floor
  (skin 0.02 m minus b2_linearSlop). Every polygon is therefore inset by the radius: the contact
  surface is then the scene's polygon itself, with corners rounded by 0.01 m (as the pybullet
  runner insets its meshes by Bullet's margin). The floor is a static chain of straight edges
  FLOOR_SEGMENT m long (wider than the scene by its own extent plus 1 km on each side, like the
  other peers' floors) whose skin's top is at ``floor_y``; static bodies are static polygons.
  Not one wide box: Box2D's polygon-polygon contacts with a float32 box 2 km wide (its vertices
  1 km from the bodies on it) misbehaved: a box slid to a stop on it jolted 2 s later (8 cm/s,
  tilted 2.6 mrad), a placed stack(5) moved at 2 cm/s or faster for 188 of 1200 steps and a
  stack(10) for 910, and stack(10) sank 3.1 cm instead of 2.0 in 5 s; none of it on a box 24 m
  wide, on the chain, or on one edge 4 km long (measured 2026-12-06). Edges are also how Box2D's
  own testbed builds its grounds. The chain keeps every edge's vertices within FLOOR_SEGMENT of
  the bodies on it, and its ghost vertices make it one smooth surface (no internal corners to
  catch on, as tiled boxes would have). On an edge the contact is the polygon's flat part, its
  rounded corners left out (points at x = +-0.49 m for a 1 m box), where against a static box
  Box2D clips two skins beyond the corners (+-0.51 m). A plank 1/30 m wide placed on its end
  sinks 2.7 mm into the chain, within the b2_linearSlop Box2D leaves (5 mm), where it stayed put
  on the box; 1/10 m wide and wider stays put on both (table_extremes' plank upright: 30:1 drifts
  8 % of its width, degraded, on the chain).
- Box2D integrates semi-implicitly (velocity first, then position with the new velocity), once
  per step, as Bullet does: free fall from rest gives y0 - g dt^2 n (n+1)/2 after n steps.
- Box2D computes in float32: positions, velocities, masses carry a relative round-off of ~6e-8
  (a body 10 m from the origin is placed to ~1e-6 m), far above sim's float64 and the other
  peers'. The observables are float64 copies of those float32 values.
- ``angles`` is Box2D's sweep angle, which it never wraps.

What Box2D cannot build faithfully (a ValueError naming the body and the reason, never an
approximation)
- Polygons of more than b2_maxPolygonVertices vertices (16 in pybox2d 2.3.10's build; Box2D's
  own b2Settings.h default is 8).
- Polygons too small or too thin for the 0.01 m skin: the inset polygon must keep every edge,
  in its direction, longer than b2_linearSlop (0.005 m; Box2D welds closer vertices).
- Polygons Box2D's hull changes beyond float32 round-off (it silently drops collinear vertices:
  that is accepted when the dropped vertex lies on the hull's boundary).
- Initial speeds beyond Box2D's per-step limits (b2_maxTranslation 2 m and b2_maxRotation pi/2
  per step, i.e. 120 m/s and 94 rad/s at dt 1/60). Box2D clamps faster motion silently, so
  ``step`` raises a RuntimeError if a body ends a ``step()`` call at either limit. The check
  reads every body once per call through the Python binding (1.2 ms for 820 bodies, 14 ms for
  10 000: as much as many Box2D steps of a sleeping scene), so it is exact for runs stepped one
  step at a time and costs little in ``step(n)``; a clamp that ends inside a ``step(n)`` call
  goes unseen. The time Box2D itself spends stepping is kept apart (``engine_seconds``), and
  benchmarks time that (study.timing.timed): the check is not Box2D's cost.
Box2D's tolerances (slop, skin, sleep) are tuned for moving bodies of 0.1 to 10 m; smaller or
larger ones are built, and ``settings["body_size_m"]`` records the scene's range against it.
Box2D asserts (an AssertionError in pybox2d) on shapes it cannot use; those become ValueErrors.

Measured deviations from sim (tests/adapters/test_box2d_runner.py pins them; dt 1/60)
- Round-off: float32, e.g. 8e-7 m after a 1 s fall from 10 m, 1.7e-5 rad after 9 rad of spin.
- Resting overlap: Box2D's position iterations leave up to b2_linearSlop (5 mm) of overlap, so a
  dropped box rests 5.0 mm into the floor (one placed touching stays put: 2e-10 m in 5 s), and
  a pyramid sinks by about 5 mm per row.
- Bounces fall short: the apex is e^2 h less 5-8 % (e = 0.5, 0.7, 0.9: -7.5, -5.6, -4.6 %; sim
  +5 %): continuous collision stops a falling body at its time of impact with the static floor
  and the rest of that step's motion is lost (without it: +5 %, with a 1.9 cm overlap).
- Angular momentum in a free collision drifts (+1.5 % in one test; linear momentum keeps to
  float32): the position iterations move overlapping bodies apart without touching their
  velocities (pymunk -1.4 %, pybullet -6 %, sim exact).
- Contact points: Box2D clips a face contact between two polygons two skins beyond the incident
  corners, so a 1 m box on a static box reports points at x = +-0.51 m (``contacts()``); on the
  floor's edges the points are its inset corners, x = +-0.49 m. Corners are rounded by 1 cm.
- A box tipped back onto its base rocks longer: settled after 6 s (sim 5 s).
- Slides stop where the discrete answer says, as in Bullet (1.12185 m for 3 m/s on mu 0.4).

Iterations: Box2D's testbed defaults, 8 velocity and 3 position iterations per step. Measured, no
reason to choose otherwise: what a pyramid does in 5 s hardly depends on them (base 20: the boxes
move at most 0.111 m with 8, 0.107 m with 20 or 50; base 40: 0.52, 0.55, 0.56 m) since it is
the overlap each contact keeps (up to b2_linearSlop, 5 mm per row: mean sinking 3.2 cm at base
20, 15 cm at base 40), not an unconverged solve; more iterations only cost time (base 20: 0.37,
0.56, 1.14 ms per step).
"""

import importlib.metadata
import math
import time

import Box2D
import numpy as np

from sim.arguments import count, flag, positive
from sim.scene import Scene

from .lifetime import ClosesOnExit
from .bullets import bullets
from .limits import LIMITS_WHY, MAX_ITERATIONS
from .guards import BOX2D_INERTIA, BOX2D_MASS, check_mass, checked_contacts, finite, steps
from .pose import body_label, com_pose
from .pybullet_urdf import inset

#: Box2D's testbed defaults (b2World::Step's velocityIterations, positionIterations).
DEFAULT_ITERATIONS = 8
DEFAULT_POSITION_ITERATIONS = 3
#: Length of the floor chain's edges, m: an edge's vertices are never farther than this from a
#: body on it (float32; see the module docstring)
FLOOR_SEGMENT = 10.0
#: Most vertices Box2D accepts in a polygon, as this build of Box2D was compiled.
MAX_POLYGON_VERTICES = int(Box2D.b2_maxPolygonVertices)
#: Skin around every polygon, m; polygons are inset by it.
POLYGON_RADIUS = float(Box2D.b2_polygonRadius)
#: Moving bodies Box2D's tolerances are tuned for, m (Box2D manual, "Units").
RECOMMENDED_SIZE = (0.1, 10.0)
#: Box2D's sleep rule, compiled in (b2Settings.h; no runtime setting): a body idle below both
#: tolerances (m/s, rad/s) for the time (s) sleeps, with its island.
BOX2D_SLEEP = {
    "b2_linearSleepTolerance": float(Box2D.b2_linearSleepTolerance),
    "b2_angularSleepTolerance": float(Box2D.b2_angularSleepTolerance),
    "b2_timeToSleep": float(Box2D.b2_timeToSleep),
}
#: Relative round-off of a float32, with room for a few operations.
FLOAT32_TOL = 8 * float(np.finfo(np.float32).eps)


def _distance_to_boundary(points, polygon):
    """Distance of each point (P,2) to the boundary of the closed polygon (K,2), m."""
    a = polygon
    e = np.roll(polygon, -1, axis=0) - a
    d = points[:, None, :] - a[None, :, :]  # (P,K,2)
    t = np.clip(np.einsum("pkj,kj->pk", d, e) / np.einsum("kj,kj->k", e, e), 0.0, 1.0)
    gap = d - t[:, :, None] * e[None, :, :]
    return np.hypot(gap[..., 0], gap[..., 1]).min(axis=1)


def box2d_polygon(local, where):
    """The vertices (K,2) m to give Box2D for the polygon ``local`` (K,2) m (CCW, about the
    centre of mass): ``local`` inset by the skin, so that Box2D's contact surface is ``local``.
    ValueError, starting "box2d: <where>", if Box2D cannot hold it faithfully."""
    v = np.asarray(local, dtype=np.float64)
    if len(v) > MAX_POLYGON_VERTICES:
        raise ValueError(
            f"box2d: {where} has {len(v)} vertices; Box2D 2.3 allows at most "
            f"{MAX_POLYGON_VERTICES} (b2_maxPolygonVertices)"
        )
    inner = inset(v, POLYGON_RADIUS)
    e_in = np.roll(inner, -1, axis=0) - inner
    e_out = np.roll(v, -1, axis=0) - v
    # An edge that shrank to nothing or turned round means the skin does not fit inside (sim's
    # polygons have no zero-length edges, so the division is safe).
    along = np.einsum("ij,ij->i", e_in, e_out) / np.hypot(e_out[:, 0], e_out[:, 1])
    if np.any(along <= float(Box2D.b2_linearSlop)):
        raise ValueError(
            f"box2d: {where} is too small or too thin for Box2D's "
            f"{POLYGON_RADIUS:g} m polygon skin (b2_polygonRadius): the polygon "
            f"shrunk by the skin must keep every edge longer than b2_linearSlop "
            f"{float(Box2D.b2_linearSlop):g} m, and its shortest would be "
            f"{along.min():.3g} m (negative: the edge turns round)"
        )
    return inner


def _check_hull(shape, wanted, where):
    """Box2D's shape must be ``wanted`` (K,2) up to float32 round-off and dropped collinear
    vertices: each of its vertices one of ours, each of ours on its boundary."""
    got = np.array([tuple(p) for p in shape.vertices], dtype=np.float64)
    tol = FLOAT32_TOL * max(1.0, float(np.abs(wanted).max()))
    nearest = np.hypot(*(got[:, None, :] - wanted[None, :, :]).transpose(2, 0, 1)).min(axis=1)
    off = _distance_to_boundary(wanted, got)
    if nearest.max() > tol or off.max() > tol:
        raise ValueError(
            f"box2d: {where}: Box2D's convex hull changed the polygon by "
            f"{max(nearest.max(), off.max()):.3g} m (more than float32 round-off)"
        )


class Box2dRunner(ClosesOnExit):
    """Run ``scene`` in Box2D 2.3.

    dt                   step, s
    iterations           velocity iterations per step (Box2D's testbed default 8)
    position_iterations  position iterations per step (default 3)
    sleeping             Box2D's sleeping (its default tolerances) or none (allowSleeping False)
    warm_starting        start each step from the last step's impulses (Box2D's default True)
    continuous           continuous collision (Box2D's default True: dynamic bodies are swept
                         against static ones, sim's "bullet" bodies against every body)
    """

    #: ``step`` checks Box2D's silent motion clamps at the end of each call only (see the module
    #: docstring): a caller that must know of a clamp inside a long call steps one at a time
    #: (experiments/bench_step.py replays its timed window so)
    checks_clamps_per_call = True

    def __init__(
        self,
        scene,
        dt=1 / 60,
        iterations=DEFAULT_ITERATIONS,
        sleeping=False,
        position_iterations=DEFAULT_POSITION_ITERATIONS,
        warm_starting=True,
        continuous=True,
    ):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a sim.Scene, got {type(scene).__name__}")
        self.dt = positive(dt, "dt")
        self.iterations = count(iterations, "iterations", 1, MAX_ITERATIONS, LIMITS_WHY)
        self.position_iterations = count(
            position_iterations, "position_iterations", 0, MAX_ITERATIONS, LIMITS_WHY
        )
        self.sleeping = flag(sleeping, "sleeping")
        warm_starting = flag(warm_starting, "warm_starting")
        continuous = flag(continuous, "continuous")
        # a copy: edits to the caller's scene after this do not reach the run (nor its reports)
        self.scene = scene.snapshot()
        self.step_count = 0
        #: s of wall time inside Box2D's own step calls (what benchmarks time; study.timing)
        self.engine_seconds = 0.0
        scene = self.scene
        # Box2D clamps a step's motion to these; a faster body would silently be slowed.
        self.max_speed = float(Box2D.b2_maxTranslation) / self.dt  # m/s
        self.max_angular_speed = float(Box2D.b2_maxRotation) / self.dt  # rad/s
        if math.hypot(*scene.gravity) * self.dt >= self.max_speed:
            raise ValueError(
                f"box2d: dt {self.dt:.4g} s is too long for Box2D: one step of "
                f"gravity ({math.hypot(*scene.gravity) * self.dt:.4g} m/s) already "
                f"reaches its per-step motion limit, b2_maxTranslation "
                f"{float(Box2D.b2_maxTranslation):g} m / dt = "
                f"{self.max_speed:.4g} m/s"
            )

        world = Box2D.b2World(gravity=tuple(scene.gravity), doSleep=self.sleeping)
        world.warmStarting = warm_starting
        world.continuousPhysics = continuous
        world.subStepping = False
        self.world = world
        try:
            self._build(scene)
        except AssertionError as exc:  # any other b2Assert while building (none known)
            raise ValueError(f"box2d: Box2D refused the scene {scene.name!r} ({exc})") from None

        sizes = self._sizes
        self.settings = {
            "engine": "box2d",
            "system": self.name,
            "box2d_version": importlib.metadata.version("box2d"),
            "precision": "float32",
            "dt": self.dt,
            # what study.timing times for this runner: not the runner's own Python reads
            "timed": "engine_seconds: wall time inside Box2D's step calls",
            "iterations": self.iterations,
            "position_iterations": self.position_iterations,
            "sleeping": self.sleeping,
            **BOX2D_SLEEP,
            "warm_starting": world.warmStarting,
            "continuous": world.continuousPhysics,
            "sub_stepping": world.subStepping,
            "bullets": bullets(
                scene,
                world.continuousPhysics,
                "b2Body bullets: swept against every body"
                if world.continuousPhysics
                else "ordinary bodies: continuous collision is off",
            ),
            "b2_linearSlop": float(Box2D.b2_linearSlop),
            "b2_angularSlop": float(Box2D.b2_angularSlop),
            "b2_polygonRadius": POLYGON_RADIUS,
            "polygon_inset": POLYGON_RADIUS,
            "b2_maxPolygonVertices": MAX_POLYGON_VERTICES,
            "b2_baumgarte": float(Box2D.b2_baumgarte),
            "b2_toiBaugarte": float(Box2D.b2_toiBaugarte),
            "b2_maxLinearCorrection": float(Box2D.b2_maxLinearCorrection),
            "b2_maxAngularCorrection": float(Box2D.b2_maxAngularCorrection),
            "b2_maxTranslation": float(Box2D.b2_maxTranslation),
            "b2_maxRotation": float(Box2D.b2_maxRotation),
            "max_speed_m_s": self.max_speed,
            "max_angular_speed_rad_s": self.max_angular_speed,
            "speed_limit_check": "at the end of every step() call",
            "b2_velocityThreshold": float(Box2D.b2_velocityThreshold),
            "friction_mixing": "sqrt(mu_a mu_b) = geometric mean (Box2D's own, exact)",
            "restitution_mixing": "max(e_a, e_b) (Box2D's own, exact)",
            "linear_damping": 0.0,
            "angular_damping": 0.0,
            "mass_data": "sim's mass and inertia about the centre of mass",
            "body_size_m": {
                "min": min(sizes),
                "max": max(sizes),
                "recommended": list(RECOMMENDED_SIZE),
            },
            "floor": None
            if self.floor_span is None
            else {
                "shape": "chain",
                "top_y": scene.floor_y,
                "segment_m": FLOOR_SEGMENT,
                "x_span": list(self.floor_span),
            },
        }

    # ---- set-up -----------------------------------------------------------------------------
    def _fixture(self, body, local, friction, restitution, where):
        """A polygon fixture of density 0 (mass data are set apart), material as given."""
        wanted = box2d_polygon(local, where)
        try:
            shape = Box2D.b2PolygonShape(vertices=[tuple(p) for p in wanted.tolist()])
        except AssertionError as exc:  # pybox2d's form of a b2Assert (no abort)
            raise ValueError(f"box2d: {where}: Box2D refused the polygon ({exc})") from None
        _check_hull(shape, wanted, where)
        return body.CreateFixture(
            shape=shape, density=0.0, friction=float(friction), restitution=float(restitution)
        )

    def _build(self, scene):
        world = self.world
        n = scene.n_bodies
        self._bodies = []
        self._sizes = []  # m, each dynamic body's diameter about its centroid
        # Each Box2D body's userData is its index in contacts(): scene body i, static n + j,
        # the floor -1.
        x_lo, x_hi = math.inf, -math.inf
        for i, b in enumerate(scene.bodies):
            where = body_label("body", i, b.name)
            com, local, mass, inertia = com_pose(b)
            check_mass("box2d", scene, i, mass, inertia, BOX2D_MASS, BOX2D_INERTIA)
            v0, w0 = math.hypot(*b.velocity), abs(b.angular_velocity)
            if v0 >= self.max_speed or w0 >= self.max_angular_speed:
                raise ValueError(
                    f"box2d: {where} starts at {v0:.4g} m/s, {w0:.4g} rad/s; Box2D clamps "
                    f"motion per step to b2_maxTranslation {float(Box2D.b2_maxTranslation):g} m "
                    f"and b2_maxRotation {float(Box2D.b2_maxRotation):.4g} rad ("
                    f"{self.max_speed:.4g} m/s, {self.max_angular_speed:.4g} rad/s at dt "
                    f"{self.dt:.4g} s)"
                )
            body = world.CreateDynamicBody(
                position=com,
                angle=float(b.angle),
                bullet=bool(b.bullet),
                linearDamping=0.0,
                angularDamping=0.0,
            )
            body.sleepingAllowed = self.sleeping
            self._fixture(body, local, b.friction, b.restitution, where)
            body.massData = Box2D.b2MassData(mass=float(mass), center=(0.0, 0.0), I=float(inertia))
            body.linearVelocity = tuple(b.velocity)
            body.angularVelocity = float(b.angular_velocity)
            self._bodies.append(body)
            body.userData = i
            reach = float(np.max(np.hypot(local[:, 0], local[:, 1])))
            self._sizes.append(2.0 * reach)
            x_lo, x_hi = min(x_lo, com[0] - reach), max(x_hi, com[0] + reach)

        for j, b in enumerate(scene.static_bodies):
            where = body_label("static body", j, b.name)
            com, local, _, _ = com_pose(b)
            body = world.CreateStaticBody(position=com, angle=float(b.angle))
            self._fixture(body, local, b.friction, b.restitution, where)
            body.userData = n + j
            reach = float(np.max(np.hypot(local[:, 0], local[:, 1])))
            x_lo, x_hi = min(x_lo, com[0] - reach), max(x_hi, com[0] + reach)

        self.floor_span = None  # (x_min, x_max) m of the floor chain
        if scene.floor_y is not None:
            # Wider than anything travels in a run, as the other peers' floors; a chain of short
            # edges, not one wide box (module docstring). Its body sits at the scene's centre,
            # its edges' line one skin below floor_y, so that the skin's top is floor_y (to
            # float32 round-off).
            margin = (x_hi - x_lo) + 1000.0
            n_edges = math.ceil((x_hi - x_lo + 2.0 * margin) / FLOOR_SEGMENT)
            half = 0.5 * n_edges * FLOOR_SEGMENT
            centre = 0.5 * (x_lo + x_hi)
            self.floor_span = (centre - half, centre + half)
            floor = world.CreateStaticBody(position=(centre, scene.floor_y - POLYGON_RADIUS))
            floor.CreateFixture(
                shape=Box2D.b2ChainShape(
                    vertices_chain=[(-half + k * FLOOR_SEGMENT, 0.0) for k in range(n_edges + 1)]
                ),
                density=0.0,
                friction=float(scene.floor_friction),
                restitution=float(scene.floor_restitution),
            )
            floor.userData = -1

    @property
    def name(self):
        return "box2d-sleep" if self.sleeping else "box2d"

    # ---- stepping ---------------------------------------------------------------------------
    def step(self, n=1):
        """Advance ``n`` steps of ``dt``. RuntimeError if a body ends the call at Box2D's
        per-step motion limit (see the module docstring): the run is then no longer the
        scene's. The check's time is not in ``engine_seconds``."""
        self.ensure_open()
        n = steps(n)
        step, dt = self.world.Step, self.dt
        vi, pi = self.iterations, self.position_iterations
        t0 = time.perf_counter()
        for _ in range(n):
            step(dt, vi, pi)
        self.engine_seconds += time.perf_counter() - t0
        self.step_count += n
        self._check_speed()
        return self

    def _check_speed(self):
        v, w = self.velocities, self.angular_velocities  # (checked finite as they are read)
        speed = np.hypot(v[:, 0], v[:, 1])
        spin = np.abs(w)
        fast = np.flatnonzero(
            (speed >= self.max_speed * (1 - FLOAT32_TOL))
            | (spin >= self.max_angular_speed * (1 - FLOAT32_TOL))
        )
        if fast.size:
            i = int(fast[0])
            where = body_label("body", i, self.scene.body_name(i))
            raise RuntimeError(
                f"box2d: {where} reached Box2D's per-step motion limit at "
                f"step {self.step_count} ({speed[i]:.4g} m/s, {spin[i]:.4g} "
                f"rad/s; limits {self.max_speed:.4g} m/s, "
                f"{self.max_angular_speed:.4g} rad/s)"
            )

    @property
    def time(self):
        """Simulated time, s."""
        return self.step_count * self.dt

    # ---- observables (fresh float64 arrays of Box2D's float32 values, row i = scene body i) --
    @property
    def positions(self):
        """(N,2) m, centres of mass (the bodies' origins)."""
        self.ensure_open()
        return finite(
            "box2d", self.scene, self.step_count, "position",
            np.array([tuple(b.position) for b in self._bodies], dtype=np.float64),
        )  # fmt: skip

    @property
    def angles(self):
        """(N,) rad, CCW, unwrapped (Box2D's sweep angle)."""
        self.ensure_open()
        return finite(
            "box2d", self.scene, self.step_count, "angle",
            np.array([b.angle for b in self._bodies], dtype=np.float64),
        )  # fmt: skip

    @property
    def velocities(self):
        """(N,2) m/s of the centres of mass."""
        self.ensure_open()
        return finite(
            "box2d", self.scene, self.step_count, "velocity",
            np.array([tuple(b.linearVelocity) for b in self._bodies], dtype=np.float64),
        )  # fmt: skip

    @property
    def angular_velocities(self):
        """(N,) rad/s, CCW."""
        self.ensure_open()
        return finite(
            "box2d", self.scene, self.step_count, "angular velocity",
            np.array([b.angularVelocity for b in self._bodies], dtype=np.float64),
        )  # fmt: skip

    @property
    def asleep(self):
        """(N,) bool, not Box2D's awake flag. Always False with sleeping off."""
        self.ensure_open()
        return np.array([not b.awake for b in self._bodies], dtype=bool)

    @checked_contacts("box2d")
    def contacts(self):
        """The touching contacts' manifold points after the last step, as in sim.World.contacts:
        body_a, body_b (K,) int (scene body i, static body j as N + j, -1 the floor); point (K,2)
        m, midway between the two surfaces; normal (K,2) unit, from A to B; normal_impulse,
        tangent_impulse (K,) N s, what Box2D's solver applied over the last step."""
        self.ensure_open()
        rows = []
        for c in self.world.contacts:
            if not c.touching or not c.enabled:
                continue
            manifold, world_manifold = c.manifold, c.worldManifold
            a, b = c.fixtureA.body.userData, c.fixtureB.body.userData
            normal = tuple(world_manifold.normal)
            for k in range(manifold.pointCount):
                p = manifold.points[k]
                rows.append(
                    (
                        a,
                        b,
                        *tuple(world_manifold.points[k]),
                        *normal,
                        p.normalImpulse,
                        p.tangentImpulse,
                    )
                )
        table = np.array(rows, dtype=np.float64).reshape(len(rows), 8)
        return {
            "body_a": table[:, 0].astype(np.int64),
            "body_b": table[:, 1].astype(np.int64),
            "point": table[:, 2:4],
            "normal": table[:, 4:6],
            "normal_impulse": table[:, 6],
            "tangent_impulse": table[:, 7],
        }

    # ---- lifetime ---------------------------------------------------------------------------
    def close(self):
        """Drop the Box2D world (idempotent); pybox2d frees it with its last reference."""
        self._bodies = []
        self.world = None
        self.closed = True

    def __repr__(self):
        return (
            f"Box2dRunner(scene={self.scene.name!r}, bodies={self.scene.n_bodies}, "
            f"dt={self.dt}, iterations={self.iterations}/{self.position_iterations}, "
            f"sleeping={self.sleeping}, step={self.step_count})"
        )
