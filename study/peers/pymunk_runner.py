"""A ``sim.Scene`` built and stepped in pymunk (Chipmunk2D), observed like a ``sim.World``.

Matching sim's conventions
- A pymunk body's ``position`` is its centre of mass: every polygon is given to pymunk with its
  vertices relative to its centroid (sim.geometry.mass_properties), and mass and moment are sim's
  own values, so both engines integrate identical bodies.
- Friction: Chipmunk multiplies the two shapes' coefficients; sim mixes by geometric mean. Each
  shape stores sqrt(mu), so the product is sqrt(mu_a) * sqrt(mu_b) = sqrt(mu_a * mu_b).
- Restitution: Chipmunk multiplies elasticities; sim takes the max. A pre-solve handler sets
  ``arbiter.restitution = max(e_a, e_b)`` every step (Chipmunk recomputes the product each step).
  It is installed only when some restitution > 0, since a Python callback per contact per step
  would otherwise slow every benchmark for nothing. (In pymunk 7 the arbiter attribute is
  ``restitution``; assigning ``arbiter.elasticity`` just adds a Python attribute and does nothing.)
  Unlike sim, Chipmunk has no restitution velocity threshold: slow impacts bounce too.
- The floor half-plane y <= floor_y becomes a static box FLOOR_THICKNESS (1 m) thick whose top
  face is y = floor_y, wide enough that nothing in the scene can slide off its ends (the scene's
  extent again plus 1 km on each side), as the other peers' floors. A box, not a zero-thickness
  segment: a small fast body that ends a step below a segment's line is pushed out of whichever
  side it is nearer, so it could fall through; below a box's top face it is pushed back up
  (until it is more than half the thickness deep).
- Integration order differs: Chipmunk moves positions with the old velocity, then updates the
  velocity, so in free flight its positions trail sim's by one velocity update (g dt t: 0.16 m
  after 1 s at dt 1/60); velocities agree exactly.

Vertex indices and shape ids matter in Chipmunk (found while checking a 5-box column)
Chipmunk keys each contact point, for warm starting, by a hash of the features that made it, and a
polygon vertex's feature hash is CP_HASH_PAIR(shape id, vertex index) = id*C ^ index*C
(cpCollision.c). That is symmetric, and zero when id == index, so with small shape ids (a space
numbers shapes 0, 1, 2, ... as they are added) distinct contact points can share a hash and pick
up each other's cached impulses. Seen with pymunk.Poly's own vertex order (its hull starts at the
leftmost-lowest vertex, so a box's bottom face is edge 0) and the floor added first (id 0, boxes
1..5): a free-standing column of 5 unit boxes (dt 1/60, 10 iterations) walks ~0.15 m sideways in
2 s and falls within 10 s, while Poly.create_box's order, or the floor added last, holds it to
< 1 cm. The outcome depended jointly on vertex order and on the order shapes were added. Two
measures make it depend on neither:
- shape ids start at SHAPE_ID_START (above any vertex count), so no feature hash is zero and no
  two (id, index) pairs are swaps of each other;
- each polygon is given raw (no hull) and rotated to start at a canonical vertex, the lowest in
  the body frame, ties (within round-off) broken by the rightmost: for an axis-aligned box exactly
  create_box's order, and for any polygon independent of where the caller's list started.
"""

import math
import time

import numpy as np
import pymunk
from pymunk._chipmunk import lib as _chipmunk  # the C API; pymunk's own pickling uses this call

from sim.arguments import count, flag, positive
from sim.geometry import MAX_VERTICES
from sim.scene import Scene

from .lifetime import ClosesOnExit
from .bullets import bullets
from .limits import LIMITS_WHY, MAX_ITERATIONS
from .guards import check_mass, checked_contacts, finite, steps
from .pose import com_pose

#: First shape id given out by the space: above every vertex index a sim polygon can have.
SHAPE_ID_START = MAX_VERTICES
#: Thickness of the floor box under floor_y, m (the pybullet runner's floor too; Box2D's is a
#: chain of edges, see box2d_runner).
FLOOR_THICKNESS = 1.0
#: s a body must stay idle before its group may sleep, when sleeping and none is given (Chipmunk's
#: own default is infinity: never)
DEFAULT_SLEEP_TIME = 0.5


def canonical_vertices(local):
    """Rotate a CCW vertex list (K,2) to start at the lowest vertex, the rightmost of ties.

    Ties are judged within 1e-9 of the polygon's size, so that round-off left by subtracting
    the centroid (a box's bottom corners at y = -0.5 and -0.5 - 1e-17) cannot flip the choice."""
    v = np.asarray(local, dtype=np.float64)
    tol = 1e-9 * float(np.max(np.abs(v)))
    lowest = np.flatnonzero(v[:, 1] <= v[:, 1].min() + tol)
    start = int(lowest[np.argmax(v[lowest, 0])])
    return np.roll(v, -start, axis=0)


def _poly(pm_body, local):
    """A Poly with exactly these vertices in this order (Poly() would reorder them by its hull)."""
    verts = [tuple(p) for p in local.tolist()]
    shape = pymunk.Poly(pm_body, verts)
    shape.unsafe_set_vertices(verts)  # raw: safe here, the shape is not in a space yet
    return shape


def _max_restitution(arbiter, space, data):
    """Pre-solve: sim's restitution mixing, max(e_a, e_b), from the shapes' stored elasticity."""
    a, b = arbiter.shapes
    arbiter.restitution = max(a.elasticity, b.elasticity)


class PymunkRunner(ClosesOnExit):
    """Run ``scene`` in pymunk.

    dt              step, s                 iterations   Chipmunk solver iterations per step
    sleeping        use Chipmunk's sleeping (space.sleep_time_threshold = sleep_time) or not (inf)
    sleep_time      s a body must stay idle before its group may sleep (None: DEFAULT_SLEEP_TIME)
    idle_speed      m/s below which a body counts as idle; None leaves Chipmunk's rule, |gravity|
                    * dt (0.1635 m/s at dt 1/60: the space holds 0, which Chipmunk reads as
                    that; ``settings`` records the speed in effect). Each engine sleeps at its
                    own default (study.peers.DEFAULT_ITERATIONS: as its authors tuned it), and
                    Chipmunk's is the loosest: Box2D's b2_linearSleepTolerance is 0.01 m/s, sim's
                    sleep_speed 0.05 m/s, so pymunk-sleep stops slow slides the others let run
    collision_slop  m of penetration Chipmunk leaves uncorrected (sim's ``slop``)

    sleep_time and idle_speed only act with sleeping: given without it they are refused (a value
    that changed nothing would otherwise be recorded as if it had). Bodies marked ``bullet`` are
    ordinary bodies here (Chipmunk has no continuous collision): ``settings["bullets"]`` says so.
    """

    def __init__(
        self,
        scene,
        dt=1 / 60,
        iterations=10,
        sleeping=False,
        sleep_time=None,
        idle_speed=None,
        collision_slop=0.005,
    ):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a sim.Scene, got {type(scene).__name__}")
        self.dt = positive(dt, "dt")
        iterations = count(iterations, "iterations", 1, MAX_ITERATIONS, LIMITS_WHY)
        sleeping = flag(sleeping, "sleeping")
        for option, value in (("sleep_time", sleep_time), ("idle_speed", idle_speed)):
            if value is not None and not sleeping:
                raise ValueError(
                    f"pymunk: {option} applies only with sleeping (system pymunk-sleep); "
                    f"pymunk runs with sleeping off, so {option}={value!r} would change nothing"
                )
        sleep_time = DEFAULT_SLEEP_TIME if sleep_time is None else sleep_time
        sleep_time = positive(sleep_time, "sleep_time", allow_zero=True)
        idle_speed = (
            None if idle_speed is None else positive(idle_speed, "idle_speed", allow_zero=True)
        )
        collision_slop = positive(collision_slop, "collision_slop", allow_zero=True)
        # a copy: edits to the caller's scene after this do not reach the run (nor its reports)
        self.scene = scene.snapshot()
        self.step_count = 0
        #: s of wall time inside Chipmunk's step calls (what benchmarks time; study.timing)
        self.engine_seconds = 0.0
        scene = self.scene

        space = pymunk.Space()
        _chipmunk.cpSpaceSetShapeIDCounter(space._space, SHAPE_ID_START)
        space.gravity = scene.gravity
        space.iterations = iterations
        space.collision_slop = collision_slop
        space.sleep_time_threshold = sleep_time if sleeping else float("inf")
        if idle_speed is not None:
            space.idle_speed_threshold = idle_speed
        self.space = space

        self._bodies = []
        # pymunk body -> its index in contacts(): static body j is N + j, the floor -1 (sim's)
        self._static_index = {}
        x_lo, x_hi = math.inf, -math.inf
        for i, b in enumerate(scene.bodies):
            com, local, mass, inertia = com_pose(b)
            check_mass("pymunk", scene, i, mass, inertia)
            local = canonical_vertices(local)
            pm = pymunk.Body(mass, inertia)
            pm.position, pm.angle = com, b.angle
            pm.velocity, pm.angular_velocity = b.velocity, b.angular_velocity
            space.add(pm, self._material(_poly(pm, local), b.friction, b.restitution))
            self._bodies.append(pm)
            reach = float(np.max(np.hypot(local[:, 0], local[:, 1])))
            x_lo, x_hi = min(x_lo, com[0] - reach), max(x_hi, com[0] + reach)

        for j, b in enumerate(scene.static_bodies):
            com, local, _, _ = com_pose(b)
            local = canonical_vertices(local)
            pm = pymunk.Body(body_type=pymunk.Body.STATIC)
            pm.position, pm.angle = com, b.angle
            space.add(pm, self._material(_poly(pm, local), b.friction, b.restitution))
            self._static_index[pm] = len(scene.bodies) + j

        self.floor_span = None  # (x_min, x_max) m of the floor box
        if scene.floor_y is not None:
            # Wider than anything travels in a run: the scene's extent again plus 1 km each side.
            margin = (x_hi - x_lo) + 1000.0
            self.floor_span = (x_lo - margin, x_hi + margin)
            (x0, x1), y = self.floor_span, scene.floor_y
            # CCW from the top right corner: edge 0 is the top face, whatever the box's width
            corners = np.array(
                [(x1, y), (x0, y), (x0, y - FLOOR_THICKNESS), (x1, y - FLOOR_THICKNESS)]
            )
            floor = _poly(space.static_body, corners)
            space.add(self._material(floor, scene.floor_friction, scene.floor_restitution))

        if min(s._hashid for s in space.shapes) < SHAPE_ID_START:  # pymunk changed underneath
            raise RuntimeError("pymunk ignored the shape id counter; see the module docstring")

        bouncy = (scene.floor_restitution > 0 and scene.floor_y is not None) or any(
            b.restitution > 0 for b in list(scene.bodies) + list(scene.static_bodies)
        )
        if bouncy:
            space.on_collision(None, None, pre_solve=_max_restitution)
        self.sleeping = bool(sleeping)
        self.settings = {
            "engine": "pymunk",
            "system": self.name,
            "pymunk_version": pymunk.version,
            "chipmunk_version": pymunk.chipmunk_version,
            "dt": self.dt,
            # what study.timing times for this runner: not the runner's own Python reads
            "timed": "engine_seconds: wall time inside Chipmunk's step calls",
            "iterations": space.iterations,
            "sleeping": self.sleeping,
            "sleep_time_threshold": space.sleep_time_threshold,
            # the speed Chipmunk uses: it reads the space's 0 as |gravity| * dt
            # (cpSpaceProcessComponents), and 0 was recorded as if nothing were idle
            "idle_speed_threshold": space.idle_speed_threshold
            or math.hypot(*scene.gravity) * self.dt,
            "idle_speed_rule": "set"
            if space.idle_speed_threshold
            else "Chipmunk's default, |gravity| * dt",
            "collision_slop": space.collision_slop,
            "collision_bias": space.collision_bias,
            "collision_persistence": space.collision_persistence,
            "damping": space.damping,
            "restitution_max_handler": bouncy,
            "bullets": bullets(
                scene, False, "ordinary bodies: Chipmunk has no continuous collision"
            ),
            "shape_id_start": SHAPE_ID_START,
            "polygon_vertices": "raw, lowest-then-rightmost first",
            "floor": None
            if self.floor_span is None
            else {
                "shape": "box",
                "thickness_m": FLOOR_THICKNESS,
                "top_y": scene.floor_y,
                "x_span": list(self.floor_span),
            },
        }

    @staticmethod
    def _material(shape, friction, restitution):
        shape.friction = math.sqrt(friction)  # product of two sqrt = geometric mean
        shape.elasticity = restitution  # read back by _max_restitution
        return shape

    @property
    def name(self):
        return "pymunk-sleep" if self.sleeping else "pymunk"

    def step(self, n=1):
        """Advance ``n`` steps of ``dt``."""
        self.ensure_open()
        n = steps(n)
        step, dt = self.space.step, self.dt
        t0 = time.perf_counter()
        for _ in range(n):
            step(dt)
        self.engine_seconds += time.perf_counter() - t0
        self.step_count += n
        return self

    @property
    def time(self):
        """Simulated time, s."""
        return self.step_count * self.dt

    # ---- observables (fresh arrays, row i = scene body i) ---------------------------------------
    @property
    def positions(self):
        """(N,2) m, centres of mass."""
        self.ensure_open()
        return finite(
            "pymunk", self.scene, self.step_count, "position",
            np.array([tuple(b.position) for b in self._bodies], dtype=np.float64),
        )  # fmt: skip

    @property
    def angles(self):
        """(N,) rad, CCW."""
        self.ensure_open()
        return finite(
            "pymunk", self.scene, self.step_count, "angle",
            np.array([b.angle for b in self._bodies], dtype=np.float64),
        )  # fmt: skip

    @property
    def velocities(self):
        """(N,2) m/s of the centres of mass."""
        self.ensure_open()
        return finite(
            "pymunk", self.scene, self.step_count, "velocity",
            np.array([tuple(b.velocity) for b in self._bodies], dtype=np.float64),
        )  # fmt: skip

    @property
    def angular_velocities(self):
        """(N,) rad/s."""
        self.ensure_open()
        return finite(
            "pymunk", self.scene, self.step_count, "angular velocity",
            np.array([b.angular_velocity for b in self._bodies], dtype=np.float64),
        )  # fmt: skip

    @property
    def asleep(self):
        """(N,) bool, Chipmunk's is_sleeping per body."""
        self.ensure_open()
        return np.array([b.is_sleeping for b in self._bodies], dtype=bool)

    @checked_contacts("pymunk")
    def contacts(self):
        """The contact points of the last step, as SimRunner.contacts gives them: {"body_a",
        "body_b": (K,) int (scene body i, static body j as N + j, the floor -1), "point": (K,2)
        m (midway between the two shapes' points), "normal": (K,2) unit, A to B,
        "normal_impulse": (K,) N s, pushing B along the normal}. Chipmunk reports only a pair's
        total impulse (``Arbiter.total_impulse``, the impulse on its first shape), so each of
        the pair's points gets an even share of it: the sum over a pair is exact, the split
        between its points is not."""
        self.ensure_open()
        index = {b: i for i, b in enumerate(self._bodies)}
        index.update(self._static_index)
        seen, pair, point, normal, impulse = set(), [], [], [], []

        def add(arbiter):
            key = frozenset(id(s) for s in arbiter.shapes)
            if key in seen:  # an arbiter between two bodies is seen twice
                return
            seen.add(key)
            cps = arbiter.contact_point_set
            if not cps.points:
                return
            n = np.array(cps.normal, dtype=np.float64)
            jx, jy = arbiter.total_impulse
            share = -(jx * n[0] + jy * n[1]) / len(cps.points)  # elementwise: no BLAS
            # the arbiter's shapes in its order: the normal points from the first to the second
            ab = tuple(index.get(shape.body, -1) for shape in arbiter.shapes)
            for p in cps.points:
                pair.append(ab)
                point.append(0.5 * (np.array(p.point_a) + np.array(p.point_b)))
                normal.append(n)
                impulse.append(share)

        for body in self._bodies:
            body.each_arbiter(add)
        k = len(point)
        pair = np.array(pair, dtype=np.int64).reshape(k, 2)
        return {
            "body_a": pair[:, 0],
            "body_b": pair[:, 1],
            "point": np.array(point, dtype=np.float64).reshape(k, 2),
            "normal": np.array(normal, dtype=np.float64).reshape(k, 2),
            "normal_impulse": np.array(impulse, dtype=np.float64),
        }

    def close(self):
        """Nothing to release (the space is freed with the runner); here so every runner can be
        closed alike."""
        self.closed = True

    def __repr__(self):
        return (
            f"PymunkRunner(scene={self.scene.name!r}, bodies={len(self._bodies)}, "
            f"dt={self.dt}, iterations={self.space.iterations}, sleeping={self.sleeping}, "
            f"step={self.step_count})"
        )
