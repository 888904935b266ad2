"""A ``sim.Scene`` built and stepped in pybullet (Bullet 3), 2D by construction, observed like a
``sim.World``.

Axes and angles
- sim's plane (x, y) is Bullet's x-z plane: sim x -> Bullet x, sim y -> Bullet z, gravity along -z.
  sim's angle is counter-clockwise about sim's +z (out of the screen), which is Bullet's -y
  (x cross z = -y), so a sim angle theta is a rotation by -theta about Bullet's +y, and a sim
  angular velocity w is -w about +y. (tests/adapters/test_pybullet_runner.py checks the world
  vertices of a
  rotated box.)
- Each dynamic body is its own URDF: a massless fixed base and one link joined to it by a `planar`
  joint (axis y). The link can only translate in x-z and rotate about y, so bodies stay exactly in
  the plane; ``out_of_plane()`` measures it. (Not the prismatic-prismatic-revolute chain: pybullet
  puts a velocity motor on each such joint and its cost grows with N^2.) The joint's origin is the
  body's initial pose, so all joint coordinates start at 0 (pybullet's resetJointStateMultiDof
  ignores planar joints, and getJointStateMultiDof returns only 2 of their 3 coordinates).
- Mass, inertia and shapes (a URDF box, or a convex mesh inset by the collision margin) are
  sim's own: ``pybullet_urdf`` writes them.
- The floor is a static box whose top is floor_y, 1 m thick and 1 km wider than the scene on each
  side (a plane gave a resting box a one-corner contact in its first step); static polygons are
  fixed URDF links.
- Files (URDF, OBJ) are written to a temporary folder and deleted as soon as they are loaded.
- Poses come from getLinkState (position, velocities) and the planar joint's rotation coordinate
  (getJointState, unwrapped), never from Euler angles (Bullet's pitch is limited to +-pi/2).
  getLinkState needs computeForwardKinematics=1: without it, it returns the pose of one step
  earlier (free fall then looked like Chipmunk's explicit Euler).
- changeDynamics silently ignores a link's material (lateralFriction, restitution) when the same
  call also sets linearDamping, angularDamping or maxJointVelocity, so they go in two calls
  (tests check that the values read back).

Settings that differ from pybullet's defaults, to match sim
- fixedTimeStep = dt, numSubSteps = 0 (one Bullet step per step), numSolverIterations = iterations
  (default 50: 10 lets a base-20 pyramid creep and a base-40 one collapse; see below).
- Damping: Bullet's multibodies default to linear and angular damping 0.04 (a quadratic drag: a
  falling body loses 13 % of its speed in 1 s); set to 0, as are joint damping and rolling and
  spinning friction. The largest joint velocity (default 100, which Bullet enforces by clamping
  silently) is raised to 1e15 (MAX_JOINT_VELOCITY).
- Friction: Bullet multiplies the two coefficients; each shape stores sqrt(mu), so pairs mix by
  geometric mean exactly as in sim.
- Restitution: Bullet multiplies too, and pybullet offers no per-pair override or contact callback,
  so sim's max cannot be had for every pair. The floor and static bodies store 1.0 and each body
  max(e_body, largest of floor and static e): body-floor (and body-static when the statics share
  the floor's e) contacts get exactly max(e_body, e_floor); body-body contacts get the product of
  the two bodies' values instead of the max (exact when both are 0). ``settings`` records whether
  the scene's pairs are all exact. Impacts slower than sim's restitution threshold (1 m/s) do not
  bounce (restitutionVelocityThreshold).
- Initial velocities: since a planar joint's velocity cannot be set, they enter as an impulse over
  the first step (force m v0 / dt and torque I w0 / dt at the centre of mass). Bullet, like sim,
  updates velocities before solving contacts and moves positions with the new velocity, so the
  first step sees v0 + g dt either way. Before the first step the observables report v0.
- Sleeping is off unless ``sleeping=True`` (URDF_ENABLE_SLEEPING). Bullet puts a multibody to sleep
  when the sum of squares of its joint velocities stays under sleep_threshold (default 0.05,
  (m/s)^2 + (rad/s)^2) for 2 s (fixed in Bullet). getDynamicsInfo does not report sleep, so a body
  counts as asleep when its velocities are exactly 0.0 and its pose did not change over the last
  step. ``step`` therefore reads every pose before its last step (5 ms for 1000 bodies, through
  the Python API): that read is the runner's, not Bullet's, so ``engine_seconds`` (the time
  inside Bullet's step calls, what benchmarks time; study.timing) leaves it out.

Measured deviations (tests/adapters/test_pybullet_runner.py pins them; dt 1/60)
- A body that spins in free flight drifts: Bullet integrates the planar joint's translation
  velocity in the rotating body frame with explicit Euler, which scales the speed by
  sqrt(1 + (w dt)^2) per step. A box spinning at 2 rad/s gains 0.34 m/s sideways in a 1 s fall
  (error proportional to dt). Resting and sliding bodies (w ~ 0) are unaffected; free fall without
  spin, sliding and resting match sim to round-off and Bullet's 1e-5 m contact penetration.
- Bounces overshoot: the apex is e^2 h plus ~10 % (e = 0.5, 0.7, 0.9: +11, +10, +9 %; sim +5 %,
  pymunk 0 %). The box penetrates ~2 cm at impact and the position correction (no split impulse
  for multibodies) pushes it out with extra speed.
- Stacks settle softly and creep: with 50 iterations the boxes of a base-10 pyramid move up to
  2.4 cm in 5 s (sim 2e-7 m, pymunk 1 cm), of a base-20 one 0.14 m (mean sinking 2.5 cm), of a
  base-40 one 0.9 m (sinking 10 cm). With 10 iterations: base 20 0.78 m, base 40 collapses.
"""

import importlib.metadata
import inspect
import math
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np
import pybullet as pb

import sim
from sim.arguments import count, flag, positive
from sim.scene import Scene

from .lifetime import ClosesOnExit
from .bullets import bullets
from .limits import LIMITS_WHY, MAX_ITERATIONS
from .guards import PYBULLET_MASS, check_mass, checked_contacts, finite, steps
from .pose import com_pose
from .pybullet_urdf import (
    COLLISION_MARGIN,
    HALF_DEPTH,
    dynamic_urdf,
    geometry_xml,
    pitch_quaternion,
    static_urdf,
    x_extent,
)

#: Solver iterations when none are given (see the module docstring).
DEFAULT_ITERATIONS = 50
#: btMultiBody's sleep timeout, s: fixed in Bullet, not settable from pybullet.
DEACTIVATION_TIME = 2.0
#: btMultiBody's default sleep threshold: sum of squared joint velocities, (m/s)^2 + (rad/s)^2.
DEFAULT_SLEEP_THRESHOLD = 0.05
#: Impacts slower than this do not bounce, m/s: sim.World's default restitution_threshold.
RESTITUTION_THRESHOLD = inspect.signature(sim.World).parameters["restitution_threshold"].default
#: Largest planar-joint velocity Bullet allows, m/s along a slide and rad/s about the hinge.
#: Bullet clamps a faster joint without a word: its default, 100, clipped a 12 s fall, and the
#: 1000 used until 2026-12 turned a body launched at 1500 m/s (or spinning at 1500 rad/s) into
#: one at 1000. So the cap lies beyond any motion a scene can have.
MAX_JOINT_VELOCITY = 1e15
#: Thickness of the floor box under floor_y, m.
FLOOR_THICKNESS = 1.0


def restitution_values(scene):
    """Per-shape restitution to store in Bullet (which multiplies a pair's two values), and
    whether every possible pair then gets sim's max(e_a, e_b) exactly.

    Returns (bodies (N,) array, environment value for the floor and static bodies, exact flag)."""
    env = ([scene.floor_restitution] if scene.floor_y is not None else []) + [
        b.restitution for b in scene.static_bodies
    ]
    e = np.array([b.restitution for b in scene.bodies], dtype=np.float64)
    stored = np.maximum(e, max(env)) if env else e.copy()
    env_value = 1.0
    exact = all(r * env_value == max(ei, es) for ei, r in zip(e, stored) for es in env)
    # body-body pairs, over distinct (e, stored) values (a value pairs with itself only if two
    # bodies share it)
    values, counts = np.unique(np.stack([e, stored], axis=1), axis=0, return_counts=True)
    for a in range(len(values)):
        for b in range(a, len(values)):
            if (a != b or counts[a] > 1) and values[a, 1] * values[b, 1] != max(
                values[a, 0], values[b, 0]
            ):
                exact = False
    return stored, env_value, exact


class PybulletRunner(ClosesOnExit):
    """Run ``scene`` in pybullet, one DIRECT client per runner (``close()`` disconnects).

    dt               step, s                 iterations   numSolverIterations (default 50)
    sleeping         URDF_ENABLE_SLEEPING on every body, or never sleep
    sleep_threshold  Bullet's sleep threshold, sum of squared joint velocities; None = default 0.05
                     (only with sleeping: without it, refused, as it would change nothing)
    restitution_threshold  m/s, impacts slower than this do not bounce (sim's default, 1.0)

    Bodies marked ``bullet`` are ordinary bodies here (the runner enables none of Bullet's
    continuous collision): ``settings["bullets"]`` says so.
    """

    def __init__(
        self,
        scene,
        dt=1 / 60,
        iterations=DEFAULT_ITERATIONS,
        sleeping=False,
        sleep_threshold=None,
        restitution_threshold=RESTITUTION_THRESHOLD,
    ):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a sim.Scene, got {type(scene).__name__}")
        self.dt = positive(dt, "dt")
        iterations = count(iterations, "iterations", 1, MAX_ITERATIONS, LIMITS_WHY)
        self.sleeping = flag(sleeping, "sleeping")
        if sleep_threshold is not None and not self.sleeping:
            raise ValueError(
                f"pybullet: sleep_threshold applies only with sleeping (system pybullet-sleep); "
                f"pybullet runs with sleeping off, so sleep_threshold={sleep_threshold!r} would "
                f"change nothing"
            )
        if sleep_threshold is not None:
            sleep_threshold = positive(sleep_threshold, "sleep_threshold", allow_zero=True)
        restitution_threshold = positive(
            restitution_threshold, "restitution_threshold", allow_zero=True
        )
        # a copy: edits to the caller's scene after this do not reach the run (nor its reports)
        self.scene = scene.snapshot()
        self.step_count = 0
        self._client = pb.connect(pb.DIRECT)
        if self._client < 0:
            raise RuntimeError("pybullet could not start a DIRECT client")
        try:
            self._build(self.scene, iterations, sleep_threshold, restitution_threshold)
        except BaseException:
            self.close()
            raise

    # ---- set-up -----------------------------------------------------------------------------
    def _build(self, scene, iterations, sleep_threshold, restitution_threshold):
        c = self._client
        pb.setGravity(scene.gravity[0], 0.0, scene.gravity[1], physicsClientId=c)
        pb.setPhysicsEngineParameter(
            fixedTimeStep=self.dt,
            numSubSteps=0,
            numSolverIterations=iterations,
            restitutionVelocityThreshold=restitution_threshold,
            physicsClientId=c,
        )
        stored_e, env_e, exact_e = restitution_values(scene)
        flags = pb.URDF_USE_INERTIA_FROM_FILE | (pb.URDF_ENABLE_SLEEPING if self.sleeping else 0)
        self._ids = []  # pybullet body id of scene body i
        self._mass = np.empty(len(scene.bodies))
        self._inertia = np.empty(len(scene.bodies))
        self._angle0 = np.empty(len(scene.bodies))
        self._com0 = np.empty((len(scene.bodies), 2))
        self._kick = []  # (body id, force, torque) applied in the first step
        shapes = {"box": 0, "mesh": 0}
        folder = tempfile.mkdtemp(prefix="freeze2d-pybullet-")
        self.files_folder = folder  # deleted below; kept as a name for tests
        try:
            for i, b in enumerate(scene.bodies):
                com, local, mass, inertia = com_pose(b)
                check_mass("pybullet", scene, i, mass, inertia, PYBULLET_MASS)
                geometry, kind = geometry_xml(local, folder, f"body{i}")
                shapes[kind] += 1
                path = Path(folder) / f"body{i}.urdf"
                path.write_text(dynamic_urdf(geometry, mass, inertia, com, b.angle))
                uid = pb.loadURDF(str(path), useFixedBase=True, flags=flags, physicsClientId=c)
                kwargs = {}
                if sleep_threshold is not None:
                    kwargs["sleepThreshold"] = float(sleep_threshold)
                # Two calls: given damping or maxJointVelocity, changeDynamics silently skips
                # the link's material (lateralFriction stayed 0.5 when they shared one call).
                pb.changeDynamics(
                    uid,
                    0,
                    lateralFriction=math.sqrt(b.friction),
                    restitution=float(stored_e[i]),
                    rollingFriction=0.0,
                    spinningFriction=0.0,
                    jointDamping=0.0,
                    frictionAnchor=0,
                    physicsClientId=c,
                    **kwargs,
                )
                pb.changeDynamics(
                    uid,
                    0,
                    linearDamping=0.0,
                    angularDamping=0.0,
                    maxJointVelocity=MAX_JOINT_VELOCITY,
                    physicsClientId=c,
                )
                self._ids.append(uid)
                self._mass[i], self._inertia[i] = mass, inertia
                self._angle0[i], self._com0[i] = b.angle, com
                vx, vy = b.velocity
                if vx or vy or b.angular_velocity:
                    self._kick.append(
                        (
                            uid,
                            [mass * vx / self.dt, 0.0, mass * vy / self.dt],
                            [com[0], 0.0, com[1]],
                            [0.0, -inertia * b.angular_velocity / self.dt, 0.0],
                        )
                    )
            self._static_ids = []
            for j, b in enumerate(scene.static_bodies):
                com, local, _, _ = com_pose(b)
                geometry, kind = geometry_xml(local, folder, f"static{j}")
                shapes[kind] += 1
                path = Path(folder) / f"static{j}.urdf"
                path.write_text(static_urdf(geometry))
                uid = pb.loadURDF(
                    str(path),
                    basePosition=(com[0], 0.0, com[1]),
                    baseOrientation=pitch_quaternion(b.angle),
                    useFixedBase=True,
                    physicsClientId=c,
                )
                pb.changeDynamics(
                    uid,
                    -1,
                    lateralFriction=math.sqrt(b.friction),
                    restitution=env_e,
                    rollingFriction=0.0,
                    spinningFriction=0.0,
                    physicsClientId=c,
                )
                self._static_ids.append(uid)
        finally:
            shutil.rmtree(folder, ignore_errors=True)

        self._floor = None
        self.floor_span = None  # (x_min, x_max) m of the floor box
        if scene.floor_y is not None:
            # A box rather than a plane: against Bullet's plane a resting box gets one contact
            # point in its first step (a corner) and is knocked ~1 mm sideways; box-box contacts
            # come with all four corners at once. Wide like pymunk's floor segment.
            x_lo, x_hi = x_extent(scene)
            margin = (x_hi - x_lo) + 1000.0
            self.floor_span = (x_lo - margin, x_hi + margin)
            half = (
                0.5 * (self.floor_span[1] - self.floor_span[0]),
                2 * HALF_DEPTH,
                0.5 * FLOOR_THICKNESS,
            )
            shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half, physicsClientId=c)
            centre = (
                0.5 * (self.floor_span[0] + self.floor_span[1]),
                0.0,
                scene.floor_y - 0.5 * FLOOR_THICKNESS,
            )
            self._floor = pb.createMultiBody(0.0, shape, -1, centre, physicsClientId=c)
            pb.changeDynamics(
                self._floor,
                -1,
                lateralFriction=math.sqrt(scene.floor_friction),
                restitution=env_e,
                rollingFriction=0.0,
                spinningFriction=0.0,
                physicsClientId=c,
            )

        self._cache_step = -1
        self._cache = None
        self._previous = None  # (positions, joint angles) before the last step
        #: s of wall time inside Bullet's own step calls (what benchmarks time; study.timing)
        self.engine_seconds = 0.0
        self.settings = {
            "engine": "pybullet",
            "system": self.name,
            "pybullet_version": importlib.metadata.version("pybullet"),
            "pybullet_api_version": pb.getAPIVersion(physicsClientId=c),
            "dt": self.dt,
            # what study.timing times for this runner: not the runner's own Python reads
            "timed": "engine_seconds: wall time inside Bullet's step calls",
            "iterations": iterations,
            "num_sub_steps": 0,
            "sleeping": self.sleeping,
            "deactivation_time_s": DEACTIVATION_TIME,
            "sleep_threshold": DEFAULT_SLEEP_THRESHOLD
            if sleep_threshold is None
            else float(sleep_threshold),
            "restitution_velocity_threshold": restitution_threshold,
            "joint": "planar (axis y), fixed massless base",
            "inertia": "from URDF (sim's)",
            "shapes": {"box": shapes["box"], "convex_mesh": shapes["mesh"]},
            "collision_margin": COLLISION_MARGIN,
            "mesh_inset": COLLISION_MARGIN,
            "extrusion_depth": 2 * HALF_DEPTH,
            "linear_damping": 0.0,
            "angular_damping": 0.0,
            "joint_damping": 0.0,
            "rolling_friction": 0.0,
            "spinning_friction": 0.0,
            "friction_anchor": False,
            "max_joint_velocity": MAX_JOINT_VELOCITY,
            "friction_mixing": "product of sqrt(mu) = geometric mean (exact)",
            "restitution_mixing": "product; floor and statics store 1.0, bodies "
            "max(e_body, e_environment)",
            "restitution_exact_for_all_pairs": bool(exact_e),
            "initial_velocity": "impulse over the first step",
            "bullets": bullets(scene, False, "ordinary bodies: no continuous collision enabled"),
            "floor": None
            if self._floor is None
            else {
                "shape": "box",
                "top_z": scene.floor_y,
                "thickness": FLOOR_THICKNESS,
                "x_span": list(self.floor_span),
            },
        }

    @property
    def name(self):
        return "pybullet-sleep" if self.sleeping else "pybullet"

    # ---- stepping ---------------------------------------------------------------------------
    def step(self, n=1):
        """Advance ``n`` steps of ``dt``."""
        self.ensure_open()
        n = steps(n)
        if n == 0:
            return self
        c = self._client
        step = pb.stepSimulation
        clock = time.perf_counter  # Bullet's own stepping, apart from the runner's reads
        if self._kick:  # initial velocities, see the docstring
            for uid, force, at, torque in self._kick:
                pb.applyExternalForce(uid, 0, force, at, pb.WORLD_FRAME, physicsClientId=c)
                pb.applyExternalTorque(uid, 0, torque, pb.WORLD_FRAME, physicsClientId=c)
            self._kick = []
            t0 = clock()
            step(physicsClientId=c)
            self.engine_seconds += clock() - t0
            self.step_count += 1
            n -= 1
        if self.sleeping and n:  # keep the pose before the last step
            t0 = clock()
            for _ in range(n - 1):
                step(physicsClientId=c)
            self.engine_seconds += clock() - t0
            self.step_count += n - 1
            self._previous = self._read_pose()  # the runner's, not Bullet's: not timed
            t0 = clock()
            step(physicsClientId=c)
            self.engine_seconds += clock() - t0
            self.step_count += 1
        else:
            t0 = clock()
            for _ in range(n):
                step(physicsClientId=c)
            self.engine_seconds += clock() - t0
            self.step_count += n
        return self

    @property
    def time(self):
        """Simulated time, s."""
        return self.step_count * self.dt

    # ---- observables ------------------------------------------------------------------------
    def _read_pose(self):
        c = self._client
        pos = np.empty((len(self._ids), 2))
        q0 = np.empty(len(self._ids))
        for i, uid in enumerate(self._ids):
            p = pb.getLinkState(uid, 0, computeForwardKinematics=1, physicsClientId=c)[0]
            pos[i] = p[0], p[2]
            q0[i] = pb.getJointState(uid, 0, physicsClientId=c)[0]
        return pos, q0

    def _read(self):
        """Positions, angles, velocities, angular velocities, and raw link states, cached until
        the next step."""
        if self._cache_step == self.step_count:
            return self._cache
        c = self._client
        n = len(self._ids)
        pos = np.empty((n, 2))
        vel = np.empty((n, 2))
        q0 = np.empty(n)
        w = np.empty(n)
        raw_pos = np.empty((n, 3))
        raw_orn = np.empty((n, 4))
        raw_vel = np.empty((n, 6))
        for i, uid in enumerate(self._ids):
            s = pb.getLinkState(
                uid, 0, computeLinkVelocity=1, computeForwardKinematics=1, physicsClientId=c
            )
            raw_pos[i], raw_orn[i] = s[0], s[1]
            raw_vel[i, :3], raw_vel[i, 3:] = s[6], s[7]
            q0[i] = pb.getJointState(uid, 0, physicsClientId=c)[0]
        pos[:, 0], pos[:, 1] = raw_pos[:, 0], raw_pos[:, 2]
        vel[:, 0], vel[:, 1] = raw_vel[:, 0], raw_vel[:, 2]
        w[:] = -raw_vel[:, 4]
        angles = self._angle0 - q0
        if self.step_count == 0:  # the first-step impulse is still pending
            vel = np.array([b.velocity for b in self.scene.bodies], dtype=np.float64)
            w = np.array([b.angular_velocity for b in self.scene.bodies], dtype=np.float64)
        self._cache = (pos, angles, vel, w, q0, raw_pos, raw_orn, raw_vel)
        self._cache_step = self.step_count
        return self._cache

    @property
    def positions(self):
        """(N,2) m, centres of mass."""
        self.ensure_open()
        return finite("pybullet", self.scene, self.step_count, "position", self._read()[0].copy())

    @property
    def angles(self):
        """(N,) rad, CCW, unwrapped (from the planar joint's rotation coordinate)."""
        self.ensure_open()
        return finite("pybullet", self.scene, self.step_count, "angle", self._read()[1].copy())

    @property
    def velocities(self):
        """(N,2) m/s of the centres of mass."""
        self.ensure_open()
        return finite("pybullet", self.scene, self.step_count, "velocity", self._read()[2].copy())

    @property
    def angular_velocities(self):
        """(N,) rad/s, CCW."""
        self.ensure_open()
        return finite(
            "pybullet", self.scene, self.step_count, "angular velocity",
            self._read()[3].copy(),
        )  # fmt: skip

    @property
    def asleep(self):
        """(N,) bool: velocities exactly 0.0 and pose unchanged over the last step (Bullet does
        not report sleep). Always False with sleeping off."""
        self.ensure_open()
        n = len(self._ids)
        if not self.sleeping or self._previous is None or self.step_count == 0:
            return np.zeros(n, dtype=bool)
        pos, _, _, _, q0, _, _, raw_vel = self._read()
        prev_pos, prev_q0 = self._previous
        return (raw_vel == 0.0).all(axis=1) & (pos == prev_pos).all(axis=1) & (q0 == prev_q0)

    def out_of_plane(self):
        """How far the bodies left the x-z plane: dict of max |y| of the centres of mass (m), max
        tilt of a body's y axis away from world y (rad), max |velocity along y| (m/s), max angular
        velocity about x or z (rad/s), and the largest distance a fixed base moved (m)."""
        _, _, _, _, _, raw_pos, raw_orn, raw_vel = self._read()
        qx, qz = raw_orn[:, 0], raw_orn[:, 2]
        tilt = np.arccos(np.clip(1.0 - 2.0 * (qx * qx + qz * qz), -1.0, 1.0))
        base = max(
            (
                math.hypot(*pb.getBasePositionAndOrientation(uid, physicsClientId=self._client)[0])
                for uid in self._ids
            ),
            default=0.0,
        )
        return {
            "max_abs_y_m": float(np.abs(raw_pos[:, 1]).max()),
            "max_tilt_rad": float(tilt.max()),
            "max_abs_vy_m_s": float(np.abs(raw_vel[:, 1]).max()),
            "max_abs_wxz_rad_s": float(np.abs(raw_vel[:, [3, 5]]).max()),
            "max_base_drift_m": float(base),
        }

    def vertices(self, i):
        """World vertices (K,2) of dynamic body ``i`` as Bullet places its shape: the scene's
        polygon carried by the link's position and quaternion (for axis tests)."""
        _, _, _, _, _, raw_pos, raw_orn, _ = self._read()
        _, local, _, _ = com_pose(self.scene.bodies[i])
        m = np.array(pb.getMatrixFromQuaternion(raw_orn[i].tolist()), dtype=np.float64).reshape(
            3, 3
        )
        # the x and z rows of m applied to (x, 0, z), elementwise (no BLAS: sim.geometry.place)
        x, z = local[:, 0], local[:, 1]
        px, _, pz = raw_pos[i]
        return np.stack([m[0, 0] * x + m[0, 2] * z + px, m[2, 0] * x + m[2, 2] * z + pz], axis=1)

    @checked_contacts("pybullet")
    def contacts(self):
        """The contact points of the last step, as SimRunner.contacts gives them: {"body_a",
        "body_b": (K,) int (scene body i, static body j as N + j, the floor -1), "point": (K,2)
        m (on B), "normal": (K,2) unit, A to B (Bullet's contactNormalOnB points from B to A:
        turned round), "normal_impulse": (K,) N s, pushing B along the normal}. Bullet reports
        a force, its impulse over the step divided by dt: times dt again."""
        self.ensure_open()
        index = {uid: i for i, uid in enumerate(self._ids)}
        index.update({uid: len(self._ids) + j for j, uid in enumerate(self._static_ids)})
        found = pb.getContactPoints(physicsClientId=self._client)
        k = len(found)
        point, normal, impulse = np.empty((k, 2)), np.empty((k, 2)), np.empty(k)
        pair = np.empty((k, 2), dtype=np.int64)
        for j, c in enumerate(found):
            pair[j] = index.get(c[1], -1), index.get(c[2], -1)  # bodyUniqueIdA, B
            point[j] = c[6][0], c[6][2]  # positionOnB, x-z plane -> 2D
            normal[j] = -c[7][0], -c[7][2]
            impulse[j] = c[9] * self.dt  # normalForce
        return {
            "body_a": pair[:, 0],
            "body_b": pair[:, 1],
            "point": point,
            "normal": normal,
            "normal_impulse": impulse,
        }

    # ---- lifetime ---------------------------------------------------------------------------
    def close(self):
        """Disconnect the pybullet client (idempotent)."""
        self.closed = True
        client, self._client = getattr(self, "_client", -1), -1
        if client is not None and client >= 0:
            try:
                pb.disconnect(physicsClientId=client)
            except Exception:  # already gone, or pybullet torn down at exit
                pass

    def __del__(self):
        self.close()

    def __repr__(self):
        return (
            f"PybulletRunner(scene={self.scene.name!r}, bodies={len(self.scene.bodies)}, "
            f"dt={self.dt}, iterations={self.settings.get('iterations')}, "
            f"sleeping={self.sleeping}, step={self.step_count})"
        )
