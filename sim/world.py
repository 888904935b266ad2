"""``sim.World``: the Python facade. It validates a Scene and the settings, packs the bodies into
struct-of-arrays, and hands whole runs of steps to the compiled kernel in ``kernel.run``."""
import math
import numbers

import numpy as np

from . import contacts as C
from . import kernel as K
from . import layout as L
from .activity import CAUSES
from .broadphase import find_pairs, update_geometry
from .freeze import POLICY_NAMES, resolve
from .geometry import edge_normals, mass_properties
from .scene import Scene
from .state import State


#: Initial-impulse solve stops when no manifold's impulse changes by more than this fraction of the
#: largest over 10 sweeps (a base-40 pyramid then moves 0.02 mm in 6 s; ~3000 sweeps, 0.6 s).
INITIAL_TOLERANCE = 1e-6


class SimulationError(RuntimeError):
    """A run that cannot go on: a body's state became NaN or infinite, or flew out of range."""


#: the solver's fast paths (see World's ``fast_paths``): name -> bit of the FAST_PATHS setting
#: (A box-specific separating-axis test was built and measured too: it saved 2.5-4.9 % of a
#: pyramid(40) step, under the 5 % rule of experiments/bench_fast_paths.py, so it was removed.)
FAST_PATHS = {"friction": L.FAST_FRICTION}


def _fast_paths(value):
    """The fast paths switched on, as a sorted tuple of names; ValueError for unknown names."""
    if value is True:
        return tuple(sorted(FAST_PATHS))
    if value is False or value is None:
        return ()
    if isinstance(value, str):
        value = (value,)
    names = tuple(sorted(set(value)))
    unknown = [n for n in names if n not in FAST_PATHS]
    if unknown:
        raise ValueError(f"unknown fast path(s) {unknown}; choose from {sorted(FAST_PATHS)}")
    return names


def _positive(value, what, allow_zero=False):
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be a number, got {value!r}") from None
    if not math.isfinite(x) or x < 0.0 or (x == 0.0 and not allow_zero):
        raise ValueError(f"{what} must be {'>= 0' if allow_zero else '> 0'} and finite, got {value!r}")
    return x


def _count(value, what, minimum):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < minimum:
        raise ValueError(f"{what} must be an integer >= {minimum}, got {value!r}")
    return int(value)


class World:
    """A running simulation of a ``sim.Scene``.

    Parameters (SI units)
      dt                    time step, s (default 1/60)
      iterations            velocity iterations per step (default 10)
      freeze                "off" | "sleep" | "paper" | "extended" (see ``sim.freeze``)
      position_iterations   position-correction sweeps per step (default 3, >= 1)
      slop                  penetration left uncorrected, m (default 0.005, pymunk's collision_slop)
      speculative_distance  contacts are created this far before touching, m (default 0.02)
      baumgarte             fraction of the penetration removed per correction sweep (default 0.2)
      max_correction        largest position correction per point and sweep, m (default 0.2)
      restitution_threshold impacts slower than this do not bounce, m/s (default 1.0)
      warm_starting         start each step from last step's impulses (default True)
      overlap_tolerance     initial overlap allowed between bodies / with the floor, m (default 0.01)
      initial_iterations    most sweeps spent once, before step 1, solving the initial contact
                            impulses to convergence (nothing moves; stops early when converged;
                            default 5000, 0 disables): a
                            scene placed at rest starts in equilibrium instead of sagging while the
                            solver builds up pressure over the first steps. Needs warm_starting.
      fast_paths            True (default), False, or a collection of names from FAST_PATHS:
                            work skipped when the scene does not need it ("friction": no
                            friction rows for contacts whose friction coefficient is 0, which
                            is exact). False exists to measure the saving
                            (experiments/bench_fast_paths.py).
      **policy_parameters   the freeze policy's own parameters (e.g. impulse_threshold)

    Arrays read from a World are copies: positions (N,2) m (centres of mass), angles (N,) rad,
    velocities (N,2) m/s, angular_velocities (N,) rad/s, states (N,) int8 ``sim.State``.
    """

    def __init__(self, scene, dt=1 / 60, iterations=10, freeze="off", *, position_iterations=3,
                 slop=0.005, speculative_distance=0.02, baumgarte=0.2, max_correction=0.2,
                 restitution_threshold=1.0, warm_starting=True, overlap_tolerance=0.01,
                 initial_iterations=5000, fast_paths=True, **policy_parameters):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a sim.Scene, got {type(scene).__name__}")
        scene.validate()
        self.scene = scene
        self.dt = _positive(dt, "dt")
        self.iterations = _count(iterations, "iterations", 1)
        self.position_iterations = _count(position_iterations, "position_iterations", 1)
        self.slop = _positive(slop, "slop", allow_zero=True)
        self.speculative_distance = _positive(speculative_distance, "speculative_distance",
                                              allow_zero=True)
        self.baumgarte = _positive(baumgarte, "baumgarte", allow_zero=True)
        if self.baumgarte > 1.0:
            raise ValueError(f"baumgarte must be in [0, 1], got {baumgarte!r}")
        self.max_correction = _positive(max_correction, "max_correction")
        self.restitution_threshold = _positive(restitution_threshold, "restitution_threshold",
                                               allow_zero=True)
        self.warm_starting = bool(warm_starting)
        self.fast_paths = _fast_paths(fast_paths)
        self.overlap_tolerance = _positive(overlap_tolerance, "overlap_tolerance", allow_zero=True)
        self.initial_iterations = _count(initial_iterations, "initial_iterations", 0)
        self.freeze = freeze
        self.policy, self.policy_parameters = resolve(freeze, policy_parameters)

        self._pack(scene)
        self.events = []            # (step, body, from_state, to_state, cause)
        self.max_penetration = 0.0  # m, deepest contact penetration seen since the start
        self.penetration = 0.0      # m, after the last step
        self._resting = K.rebuild_resting((self._fsettings, self._isettings, self._counters),
                                          self._bodies, self._geometry, self._activity)
        self._check_initial_overlap()
        if self.initial_iterations and self.warm_starting:
            while K.presolve(self.initial_iterations, INITIAL_TOLERANCE,
                             *self._kernel_state()) == K.GROW:
                self._allocate_contacts(2 * len(self._pair_keys))

    def _kernel_state(self):
        """The argument tuples every kernel in ``sim.kernel`` takes (see its docstring)."""
        return ((self._fsettings, self._isettings, self._counters), self._bodies, self._geometry,
                self._contacts, self._activity, self._resting)

    # ---- set-up -----------------------------------------------------------------------------
    def _pack(self, scene):
        bodies = list(scene.bodies) + list(scene.static_bodies)
        n = len(scene.bodies)
        m = len(bodies)
        self.n_bodies = n
        counts = np.array([len(b.vertices) for b in bodies], np.int64)
        self._vert_start = np.zeros(m + 1, np.int64)          # (M+1,) offsets into vertex arrays
        np.cumsum(counts, out=self._vert_start[1:])
        v_total = int(self._vert_start[-1])
        self._local_verts = np.empty((v_total, 2))             # (V,2) m, body frame about the COM
        self._local_normals = np.empty((v_total, 2))           # (V,2) outward unit edge normals
        self._position = np.empty((m, 2))                      # (M,2) m, centre of mass
        self._angle = np.empty(m)                              # (M,) rad
        self._velocity = np.zeros((m, 2))                      # (M,2) m/s
        self._angular_velocity = np.zeros(m)                   # (M,) rad/s
        self._inv_mass = np.zeros(m)                           # (M,) 1/kg, 0 for static
        self._inv_inertia = np.zeros(m)                        # (M,) 1/(kg m^2), 0 for static
        self._friction = np.empty(m)                           # (M,) Coulomb mu
        self._restitution = np.empty(m)                        # (M,) in [0, 1]
        self.masses = np.empty(n)                              # (N,) kg
        self.inertias = np.empty(n)                            # (N,) kg m^2 about the COM
        self.extents = np.empty(m)                             # (M,) m, COM to farthest vertex
        for i, b in enumerate(bodies):
            mass, centroid, inertia = mass_properties(b.vertices, b.density)
            local = b.vertices - centroid
            s0, s1 = self._vert_start[i], self._vert_start[i + 1]
            self._local_verts[s0:s1] = local
            self._local_normals[s0:s1] = edge_normals(local)
            c, s = math.cos(b.angle), math.sin(b.angle)
            self._position[i] = (b.position[0] + c * centroid[0] - s * centroid[1],
                                 b.position[1] + s * centroid[0] + c * centroid[1])
            self._angle[i] = b.angle
            self._friction[i] = b.friction
            self._restitution[i] = b.restitution
            self.extents[i] = float(np.max(np.hypot(local[:, 0], local[:, 1])))
            if i < n:
                self._velocity[i] = b.velocity
                self._angular_velocity[i] = b.angular_velocity
                self._inv_mass[i] = 1.0 / mass
                self._inv_inertia[i] = 1.0 / inertia
                self.masses[i] = mass
                self.inertias[i] = inertia
        self._rotation = np.empty((m, 2))                      # (M,2) cos, sin of angle
        self._world_verts = np.empty((v_total, 2))             # (V,2) m
        self._world_normals = np.empty((v_total, 2))
        self._aabb = np.empty((m, 4))                          # (M,4) m, min x, min y, max x, max y
        update_geometry(np.arange(m), m, self._position, self._angle, self._vert_start,
                        self._local_verts, self._local_normals, self._rotation, self._world_verts,
                        self._world_normals, self._aabb, self.speculative_distance)
        # Grid cell of the broadphase, m: about two typical bodies wide, but large enough that
        # the biggest body (a long wall, a plank) covers at most ~32 cells per axis.
        typical = float(np.quantile(self.extents[:n], 0.9))
        cell_size = max(2.0 * typical + 2.0 * self.speculative_distance,
                        float(self.extents.max()) / 16.0)
        g = scene.gravity
        has_floor = scene.floor_y is not None
        self._fsettings = np.zeros(L.N_FLOAT_SETTINGS)
        self._fsettings[[L.DT, L.GRAVITY_X, L.GRAVITY_Y, L.FLOOR_Y, L.FLOOR_FRICTION,
                         L.FLOOR_RESTITUTION, L.SLOP, L.MARGIN, L.BAUMGARTE, L.MAX_CORRECTION,
                         L.RESTITUTION_THRESHOLD, L.CELL_SIZE]] = (
            self.dt, g[0], g[1], scene.floor_y if has_floor else 0.0, scene.floor_friction,
            scene.floor_restitution, self.slop, self.speculative_distance, self.baumgarte,
            self.max_correction, self.restitution_threshold, cell_size)
        for name, column in self.policy.FLOAT_SETTINGS.items():
            self._fsettings[column] = self.policy_parameters[name]
        self._isettings = np.zeros(L.N_INT_SETTINGS, np.int64)
        self._isettings[[L.ITERATIONS, L.POSITION_ITERATIONS, L.HAS_FLOOR, L.WARM_START,
                         L.N_DYNAMIC, L.POLICY, L.FAST_PATHS]] = (
            self.iterations, self.position_iterations, int(has_floor), int(self.warm_starting), n,
            POLICY_NAMES.index(self.freeze),
            sum(FAST_PATHS[name] for name in self.fast_paths))
        for name, column in self.policy.INT_SETTINGS.items():
            self._isettings[column] = self.policy_parameters[name]
        self._counters = np.zeros(L.N_COUNTERS, np.int64)
        self._counters[L.N_AWAKE] = n                          # every body starts awake
        self._bodies = (self._position, self._angle, self._velocity, self._angular_velocity,
                        self._inv_mass, self._inv_inertia, self._friction, self._restitution,
                        self._vert_start, self._local_verts, self._local_normals, self.extents)
        self._geometry = (self._rotation, self._world_verts, self._world_normals, self._aabb)
        self._states = np.full(n, State.FREE, np.int8)         # (N,) int8 sim.State
        self._activity = (
            self._states,
            np.arange(n, dtype=np.int64),                      # awake (N,) body indices
            np.arange(n, dtype=np.int64),                      # awake_slot (N,), -1 = frozen
            self._inv_mass.copy(),                             # solver_inv_mass (M,) 1/kg
            self._inv_inertia.copy(),                          # solver_inv_inertia (M,)
            np.zeros((4 * n + 64, 5), np.int64),               # events, see sim.activity
            np.zeros((n, self.policy.REAL_COLUMNS)),           # body_real: policy's own, per body
            np.zeros((n, self.policy.INT_COLUMNS), np.int64),  # body_int: policy's own, per body
            np.zeros((max(16, 4 * n), 2), np.int64),           # links: policy's body pairs
            np.zeros((max(16, 4 * n), 3)))                     # link_load: per link, policy's
        initial = getattr(self.policy, "initial", None)
        if initial is not None:
            initial(self._activity[7])
        self._allocate_contacts(max(64, 4 * m))

    def _allocate_contacts(self, capacity):
        """(Re)allocate pair and contact buffers, keeping the current manifolds (warm start)."""
        old = getattr(self, "_contacts", None)
        manifolds = C.allocate(capacity)                           # see sim.contacts
        if old is not None:
            k = int(self._counters[L.N_MANIFOLDS])
            for new_arr, old_arr in zip(manifolds, old[1:5]):
                new_arr[:k] = old_arr[:k]
        self._contacts = (np.empty(capacity, np.int64),            # pair_keys (P,) sorted
                          *manifolds,
                          np.empty(capacity, np.int64),            # prev_key
                          np.empty(capacity, np.int64),            # prev_count
                          np.empty((capacity, 2), np.int64),       # prev_id
                          np.empty((capacity, 2, 2)))              # prev_impulse, N s

    @property
    def _pair_keys(self):
        return self._contacts[0]

    @property
    def _manifolds(self):
        return self._contacts[1:5]

    def _check_initial_overlap(self):
        """Refuse scenes whose bodies start interpenetrated beyond ``overlap_tolerance``: the
        position correction would launch them apart and the run would measure nothing real."""
        scratch = C.allocate(len(self._pair_keys))
        keys = np.empty(len(self._pair_keys), np.int64)
        pair_args = (np.arange(self.n_bodies), self.n_bodies, self._aabb,
                     self.scene.floor_y is not None, self._fsettings[L.FLOOR_Y],
                     self._fsettings[L.CELL_SIZE], self._resting)
        n_pairs = find_pairs(*pair_args, keys)
        if n_pairs < 0:
            keys = np.empty(-n_pairs, np.int64)
            scratch = C.allocate(-n_pairs)
            n_pairs = find_pairs(*pair_args, keys)
        empty = np.empty(0, np.int64)
        count = C.collide_pairs(n_pairs, keys, len(self._angle), self._position, self._rotation,
                                self._vert_start, self._local_verts, self._local_normals,
                                self._world_verts, self._world_normals, self._friction,
                                self._restitution, self._fsettings[L.FLOOR_Y], 0.0, 0.0, 0.0,
                                *scratch, 0, empty, empty, np.empty((0, 2), np.int64),
                                np.empty((0, 2, 2)), False, *C.scratch())
        manifold_int, _, point_float, _ = scratch
        for c in range(count):
            k = manifold_int[c, C.POINT_COUNT]
            depth = -float(point_float[c, :k, C.SEPARATION].min())
            if depth > self.overlap_tolerance:
                a, b = int(manifold_int[c, C.BODY_A]), int(manifold_int[c, C.BODY_B])
                what_b = self._describe(b)
                what = (f"{what_b} starts {depth:.4g} m below the floor" if a < 0 else
                        f"{self._describe(a)} and {what_b} start overlapping by {depth:.4g} m")
                raise ValueError(f"{what} (overlap_tolerance is {self.overlap_tolerance} m)")

    def _describe(self, i):
        if i < self.n_bodies:
            return self.scene.body_name(i)
        j = i - self.n_bodies
        return self.scene.static_bodies[j].name or f"static body {j}"

    # ---- stepping ---------------------------------------------------------------------------
    def step(self, n=1):
        """Advance ``n`` steps (default 1). Raises SimulationError if a body goes non-finite."""
        n = _count(n, "n", 0)
        if n == 0:
            return self
        min_sep = np.zeros(n)
        done = 0
        while done < n:
            status, steps, self._resting = K.run(n - done, *self._kernel_state(), min_sep[done:])
            done += steps
            self._flush_events()
            if status == K.GROW:
                self._allocate_contacts(2 * len(self._pair_keys))
            elif status == K.NON_FINITE:
                self._record_penetration(min_sep[:done])
                i = int(self._counters[L.BAD_BODY])
                raise SimulationError(
                    f"step {self.step_count}: {self._describe(i)} diverged (non-finite, or "
                    f"farther than {K.MAX_COORDINATE:g} m) "
                    f"(position {self._position[i].tolist()}, angle {self._angle[i]}, velocity "
                    f"{self._velocity[i].tolist()}, angular velocity {self._angular_velocity[i]}); "
                    f"try a smaller dt or check the scene")
        self._record_penetration(min_sep)
        return self

    def _flush_events(self):
        """Move the kernel's event buffer into ``self.events`` as (step, body, from, to, cause)."""
        k = int(self._counters[L.N_EVENTS])
        if k:
            rows = self._activity[5][:k].tolist()
            self.events.extend((step, body, State(a), State(b), CAUSES[cause])
                               for step, body, a, b, cause in rows)
            self._counters[L.N_EVENTS] = 0

    def _record_penetration(self, min_sep):
        if len(min_sep):
            self.penetration = max(0.0, -float(min_sep[-1]))
            self.max_penetration = max(self.max_penetration, -float(min_sep.min()))

    # ---- observables (copies, so callers cannot corrupt the state) ---------------------------
    @property
    def positions(self):
        return self._position[:self.n_bodies].copy()

    @property
    def angles(self):
        return self._angle[:self.n_bodies].copy()

    @property
    def velocities(self):
        return self._velocity[:self.n_bodies].copy()

    @property
    def angular_velocities(self):
        return self._angular_velocity[:self.n_bodies].copy()

    @property
    def states(self):
        return self._states.copy()

    @property
    def frozen(self):
        """(N,) bool: bodies out of the awake list this step: not integrated, not solved, not
        collided against each other (what "frozen" costs nothing means). Under ``paper`` a body
        can be VERTICAL_STABLE or a sliding ROTATION_STABLE and still be awake."""
        return self._activity[2][:self.n_bodies] < 0

    @property
    def n_awake(self):
        """Number of bodies in the awake list."""
        return int(self._counters[L.N_AWAKE])

    @property
    def step_count(self):
        return int(self._counters[L.STEP_COUNT])

    @property
    def time(self):
        """Simulated time, s."""
        return self.step_count * self.dt

    def kinetic_energy(self):
        """Total kinetic energy, J (translational + rotational)."""
        v = self._velocity[:self.n_bodies]
        w = self._angular_velocity[:self.n_bodies]
        return 0.5 * float(self.masses @ np.einsum("ij,ij->i", v, v) + self.inertias @ (w * w))

    def potential_energy(self):
        """Gravitational potential energy relative to the origin, J."""
        g = np.asarray(self.scene.gravity)
        return -float(self.masses @ (self._position[:self.n_bodies] @ g))

    def vertices(self, i):
        """World vertices (K,2) of dynamic body ``i`` at the current pose, m."""
        c, s = math.cos(self._angle[i]), math.sin(self._angle[i])
        local = self._local_verts[self._vert_start[i]:self._vert_start[i + 1]]
        return local @ np.array([[c, s], [-s, c]]) + self._position[i]

    def contacts(self):
        """The contact points of the last step: dict of arrays over points —
        body_a, body_b (-1 = floor) (P,) int; point (P,2) m (anchor on B); normal (P,2) A->B;
        separation (P,) m; normal_impulse, tangent_impulse (P,) N s."""
        count = int(self._counters[L.N_MANIFOLDS])
        mi, mf, pf, _ = self._manifolds
        n_pts = mi[:count, C.POINT_COUNT]
        rows = np.repeat(np.arange(count), n_pts)
        cols = np.concatenate([np.arange(k) for k in n_pts]) if count else np.zeros(0, int)
        b = mi[rows, C.BODY_B]
        return {"body_a": mi[rows, C.BODY_A].copy(), "body_b": b.copy(),
                "point": pf[rows, cols][:, [C.ANCHOR_BX, C.ANCHOR_BY]] + self._position[b],
                "normal": mf[rows][:, [C.NORMAL_X, C.NORMAL_Y]].copy(),
                "separation": pf[rows, cols, C.SEPARATION].copy(),
                "normal_impulse": pf[rows, cols, C.NORMAL_IMPULSE].copy(),
                "tangent_impulse": pf[rows, cols, C.TANGENT_IMPULSE].copy()}

    def __repr__(self):
        return (f"World(scene={self.scene.name!r}, bodies={self.n_bodies}, dt={self.dt}, "
                f"iterations={self.iterations}, freeze={self.freeze!r}, step={self.step_count})")
