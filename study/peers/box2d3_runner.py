"""A ``sim.Scene`` built and stepped in Box2D v3 (pyb2d3), for benchmarks: the state of the art
sim's solver is measured against.

Box2D v3 is the solver sim's soft step follows (``sim.soft_step``): substeps, a soft contact
with its stiffness in Hz, one biased solve and one relax sweep per substep, restitution at the
end, graph colouring and wide (SIMD) batches. Timing it in the same process as sim and pymunk
(``experiments/bench_step``) is the fair way to say how far sim's solver is from it. It is a
*timing* peer: it steps a scene and reports the same observables as the study's other runners
(poses, velocities, sleeping), but it is not in the study's registry of compared systems
(``study.systems.BENCH_ONLY``), so no figure or table but the benchmarks runs it.

Matching sim's conventions
- Every body's origin is its centre of mass (``com_pose``). Box2D computes its mass and rotational
  inertia from the same polygon and density as sim (equal to float32 round-off; the tests pin
  it), so both engines integrate identical bodies.
- Polygons are given as they are, with no skin: Box2D v3's polygons take a radius, set to 0.
- Friction mixes as sqrt(mu_a mu_b) and restitution as max(e_a, e_b) in Box2D v3 by default,
  as in sim; the restitution threshold (1 m/s) is sim's default.
- The floor is a static box FLOOR_THICKNESS (1 m) thick whose top face is y = floor_y, as wide as
  the scene's extent plus 1 km on each side (the other peers' floors). Not the chain of edges the
  Box2D 2.3 runner uses: a chain is one-sided and has no thickness, and in drop(200) seeds 4 and 6
  (dt 1/60, 240 steps) Box2D v3 let the pile push a small triangle (0.1 m) through it, to fall
  forever; on the box no body of seeds 0-7 goes below the floor. The box's float32 vertices lie a
  kilometre from the bodies on it, which misbehaved in Box2D 2.3's polygon contacts; in Box2D v3 a
  box placed on it and a 3 m/s slide on it give their exact answers (the tests).
- Box2D v3 steps with ``substeps`` substeps (its testbed's default, 4, as sim's) and solves each
  once with bias and once without: ``iterations`` is that 1 and cannot be changed (b2World_Step
  takes only the substep count).

What this build of Box2D is (recorded in ``settings``)
- pyb2d3 (nanobind bindings of Box2D >= 3.1) as its wheel ships it: compiled for SSE2, one
  thread: 128-bit packed instructions, 4 float32 contacts per instruction (Box2D v3 can also be
  compiled for AVX2: 256-bit, 8 float32). sim's kernels are compiled by Numba for the machine they
  run on: 256-bit packed instructions on the study's machine (``experiments/bench_kernels``), 4
  float64 per instruction. So both solve 4 contacts per instruction here; sim's wider registers
  are an advantage this build of Box2D does not take, and benchmarks say so beside the number.
- float32 throughout, like Box2D 2.3.

What it refuses (ValueError naming the body)
- Polygons of more than MAX_POLYGON_VERTICES (8) vertices, and polygons whose convex hull Box2D
  computes with another vertex count (it welds vertices closer than its linear slop, 5 mm, and
  drops collinear ones).
- Initial speeds at or beyond Box2D's limits, which it clamps silently: its maximum linear speed
  (MAX_LINEAR_SPEED, 400 m/s) and a turn of MAX_TURN (pi/4) per substep (188 rad/s at 4
  substeps of 1/60 s). A body that reaches either limit in a run makes ``step`` raise a
  RuntimeError at the end of that call (the check reads every body's velocity once per call, in
  one bulk read; ``engine_seconds`` keeps the time spent inside Box2D's steps apart, which is
  what benchmarks time, study.timing.timed).
"""

import importlib.metadata
import math
import time

import numpy as np
import pyb2d3

from sim.arguments import count, positive
from sim.scene import Scene

from .lifetime import ClosesOnExit
from .guards import check_mass, finite
from .pose import body_label, com_pose

#: Box2D v3's solve sweeps per substep: one biased, one relax (not a setting in Box2D v3).
ITERATIONS = 1
#: Substeps per step: Box2D v3's testbed default, and sim's.
DEFAULT_SUBSTEPS = 4
#: Most vertices in a Box2D v3 polygon (B2_MAX_POLYGON_VERTICES).
MAX_POLYGON_VERTICES = 8
#: The floor's width is the scene's extent plus 1 km on each side, rounded up to this, m.
FLOOR_SEGMENT = 10.0
#: Thickness of the floor box under floor_y, m (pymunk's and pybullet's floor boxes too).
FLOOR_THICKNESS = 1.0
#: Box2D v3's default maximum linear speed, m/s (b2WorldDef.maximumLinearSpeed: 4 m per step at
#: 100 steps per second, read from the library at import).
MAX_LINEAR_SPEED = float(pyb2d3.WorldDef().maximum_linear_speed)
#: Box2D v3's largest turn per substep, rad (B2_MAX_ROTATION): faster spins are clamped.
MAX_TURN = 0.25 * math.pi
#: The SIMD width of this build (see the module docstring).
SIMD = "SSE2 (pyb2d3 wheel)"


def _polygon(local, where):
    """The Box2D v3 polygon of ``local`` (K,2) m, about the centre of mass; ValueError if Box2D
    cannot hold it as it is."""
    k = len(local)
    if k > MAX_POLYGON_VERTICES:
        raise ValueError(
            f"box2d3: {where} has {k} vertices; Box2D v3 takes at most {MAX_POLYGON_VERTICES}"
        )
    hull = pyb2d3.compute_hull(np.ascontiguousarray(local, dtype=np.float32))
    if hull.count != k:
        raise ValueError(
            f"box2d3: {where}: Box2D's convex hull of its {k} vertices has {hull.count} (it welds "
            f"vertices closer than 5 mm and drops collinear ones)"
        )
    return pyb2d3.polygon(hull=hull, radius=0.0)


class Box2d3Runner(ClosesOnExit):
    """Run ``scene`` in Box2D v3 at step ``dt`` s with ``substeps`` substeps, sleeping off (the
    benchmarks time solvers with nothing frozen)."""

    name = "box2d3"
    #: ``step`` checks Box2D's silent speed clamps at the end of each call only (one bulk read of
    #: the velocities per call): a caller that must know of a clamp inside a long call steps one
    #: at a time (experiments/bench_step.py replays its timed window so)
    checks_clamps_per_call = True

    def __init__(self, scene, dt=1 / 60, iterations=ITERATIONS, substeps=DEFAULT_SUBSTEPS):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a sim.Scene, got {type(scene).__name__}")
        self.dt = positive(dt, "dt")
        if iterations != ITERATIONS:
            raise ValueError(
                f"box2d3: iterations must be {ITERATIONS} (Box2D v3 solves each substep once "
                f"with bias and once without; trade accuracy for speed with substeps), got "
                f"{iterations!r}"
            )
        self.substeps = count(substeps, "substeps", 1, 64, "Box2D v3 takes a small substep count")
        #: rad/s: the spin Box2D clamps at (MAX_TURN per substep)
        self.max_angular_speed = MAX_TURN * self.substeps / self.dt
        self.engine_seconds = 0.0
        self.scene = scene.snapshot()
        self.step_count = 0
        scene = self.scene

        world = pyb2d3.World(gravity=tuple(float(g) for g in scene.gravity))
        world.sleeping_enabled = False
        self.world = world
        self._bodies = pyb2d3.Bodies()
        self._body_list = []
        x_lo, x_hi = math.inf, -math.inf
        for i, b in enumerate(scene.bodies):
            where = body_label("body", i, b.name)
            speed = math.hypot(*b.velocity)
            if speed >= MAX_LINEAR_SPEED or abs(b.angular_velocity) >= self.max_angular_speed:
                raise ValueError(
                    f"box2d3: {where} starts at {speed:g} m/s and {b.angular_velocity:g} rad/s; "
                    f"Box2D v3 clamps speeds at {MAX_LINEAR_SPEED:g} m/s and spins at "
                    f"{self.max_angular_speed:g} rad/s (a turn of pi/4 per substep)"
                )
            com, local, mass, inertia = com_pose(b)
            check_mass("box2d3", scene, i, mass, inertia)  # sim's range, as every peer
            body = world.create_dynamic_body(
                position=(float(com[0]), float(com[1])),
                rotation=float(b.angle),
                linear_velocity=(float(b.velocity[0]), float(b.velocity[1])),
                angular_velocity=float(b.angular_velocity),
            )
            self._shape(body, _polygon(local, where), b.friction, b.restitution, b.density)
            self._bodies.append(body)
            self._body_list.append(body)
            reach = float(np.max(np.hypot(local[:, 0], local[:, 1])))
            x_lo, x_hi = min(x_lo, com[0] - reach), max(x_hi, com[0] + reach)
        for j, b in enumerate(scene.static_bodies):
            where = body_label("static body", j, b.name)
            com, local, _, _ = com_pose(b)
            body = world.create_static_body(
                position=(float(com[0]), float(com[1])), rotation=float(b.angle)
            )
            self._shape(body, _polygon(local, where), b.friction, b.restitution, b.density)
            reach = float(np.max(np.hypot(local[:, 0], local[:, 1])))
            x_lo, x_hi = min(x_lo, com[0] - reach), max(x_hi, com[0] + reach)

        self.floor_span = None  # (x_min, x_max) m of the floor box
        if scene.floor_y is not None:
            if not math.isfinite(x_lo):
                x_lo = x_hi = 0.0
            margin = (x_hi - x_lo) + 1000.0
            n_edges = math.ceil((x_hi - x_lo + 2.0 * margin) / FLOOR_SEGMENT)
            half = 0.5 * n_edges * FLOOR_SEGMENT
            centre = 0.5 * (x_lo + x_hi)
            self.floor_span = (centre - half, centre + half)
            # a box FLOOR_THICKNESS thick whose top face is floor_y (see the module docstring:
            # not a chain, through which Box2D v3 let a pile push a small body)
            floor = world.create_static_body(
                position=(centre, float(scene.floor_y) - 0.5 * FLOOR_THICKNESS)
            )
            t = 0.5 * FLOOR_THICKNESS
            corners = np.array([[-half, -t], [half, -t], [half, t], [-half, t]])
            self._shape(
                floor,
                pyb2d3.polygon(points=corners.astype(np.float32)),
                scene.floor_friction,
                scene.floor_restitution,
                1.0,
            )

        self.settings = {
            "engine": "box2d3",
            "version": f"pyb2d3 {importlib.metadata.version('pyb2d3')} (Box2D >= 3.1)",
            "precision": "float32",
            "simd": SIMD,
            "threads": 1,
            "dt": self.dt,
            "substeps": self.substeps,
            "iterations": ITERATIONS,
            "relax_iterations": ITERATIONS,
            "sleeping": False,
            "contact_hertz": float(pyb2d3.WorldDef().contact_hertz),
            "contact_damping_ratio": float(pyb2d3.WorldDef().contact_damping_ratio),
            "restitution_threshold": float(world.restitution_threshold),
            "continuous": bool(world.continuous_enabled),
            "max_linear_speed": MAX_LINEAR_SPEED,
            "max_angular_speed": self.max_angular_speed,
            "friction_mixing": "sqrt(mu_a mu_b)",
            "restitution_mixing": "max(e_a, e_b)",
            "polygon_radius_m": 0.0,
            "floor": None
            if self.floor_span is None
            else {
                "kind": "static box",
                "top_y": scene.floor_y,
                "thickness_m": FLOOR_THICKNESS,
                "x_span": [float(x) for x in self.floor_span],
            },
        }

    @staticmethod
    def _shape(body, polygon, friction, restitution, density):
        material = pyb2d3.surface_material(friction=float(friction), restitution=float(restitution))
        shape = pyb2d3.shape_def(density=float(density), material=material)
        body.create_polygon_shape(shape, polygon)

    def step(self, n=1):
        """Advance ``n`` steps of ``dt``; RuntimeError if a body ends them at one of Box2D's
        speed limits (it would have been slowed silently)."""
        self.ensure_open()
        n = count(n, "n", 0)
        step, dt, substeps = self.world.step, self.dt, self.substeps
        t0 = time.perf_counter()
        for _ in range(n):
            step(dt, substeps)
        self.engine_seconds += time.perf_counter() - t0
        self.step_count += n
        if self._body_list:
            speed = np.hypot(*self.velocities.T).max()
            spin = np.abs(self.angular_velocities).max()
            # float32: a clamped body sits at the limit to round-off
            if speed >= 0.999 * MAX_LINEAR_SPEED or spin >= 0.999 * self.max_angular_speed:
                raise RuntimeError(
                    f"box2d3: at step {self.step_count} a body moves at {speed:g} m/s or spins "
                    f"at {spin:g} rad/s, Box2D v3's limit ({MAX_LINEAR_SPEED:g} m/s, "
                    f"{self.max_angular_speed:g} rad/s): it clamps faster motion silently"
                )
        return self

    @property
    def time(self):
        """Simulated time, s."""
        return self.step_count * self.dt

    # ---- observables (fresh float64 arrays of Box2D's float32 values, row i = scene body i) ----
    def _rows(self, read, width):
        """(N, width) float64 of one of Box2D's bulk reads (none on an empty scene)."""
        if not self._body_list:
            return np.zeros((0, width))
        return np.asarray(read(), dtype=np.float64).reshape(len(self._body_list), width)

    @property
    def positions(self):
        """(N,2) m, centres of mass."""
        self.ensure_open()
        return finite(
            "box2d3", self.scene, self.step_count, "position",
            self._rows(self._bodies.get_positions, 2),
        )  # fmt: skip

    @property
    def angles(self):
        """(N,) rad, CCW, in (-pi, pi] (Box2D v3 keeps a rotation, not an angle)."""
        self.ensure_open()
        rot = self._rows(self._bodies.get_rotations, 2)  # (cos, sin)
        return finite(
            "box2d3", self.scene, self.step_count, "angle",
            np.arctan2(rot[:, 1], rot[:, 0]),
        )  # fmt: skip

    @property
    def velocities(self):
        """(N,2) m/s of the centres of mass."""
        self.ensure_open()
        return finite(
            "box2d3", self.scene, self.step_count, "velocity",
            self._rows(self._bodies.get_linear_velocities, 2),
        )  # fmt: skip

    @property
    def angular_velocities(self):
        """(N,) rad/s."""
        self.ensure_open()
        return finite(
            "box2d3", self.scene, self.step_count, "angular velocity",
            self._rows(self._bodies.get_angular_velocities, 1)[:, 0],
        )  # fmt: skip

    @property
    def asleep(self):
        """(N,) bool: Box2D's body is not awake (never, with sleeping off)."""
        self.ensure_open()
        return np.array([not b.awake for b in self._body_list], dtype=bool)

    def close(self):
        """Destroy the Box2D world."""
        if self.world is not None:
            self.world.destroy()
            self.world = None
        self.closed = True

    def __repr__(self):
        return (
            f"Box2d3Runner(scene={self.scene.name!r}, bodies={len(self._body_list)}, "
            f"dt={self.dt}, substeps={self.substeps}, step={self.step_count})"
        )
