"""``sim.World``: the Python facade. It validates a Scene and the settings, packs the bodies into
struct-of-arrays (``sim.packing``), builds the named state the kernels share (``sim.data``), and
hands whole runs of steps to the compiled step loop (``sim.kernel.run``)."""

import contextlib
import math
import signal
import threading
import time

import numpy as np

from . import data as D
from . import kernel as K
from . import soft_step
from .arguments import count, flag, positive
from .activity import CAUSES, initial_activity
from .broadphase import grid_buffers
from .clock import ticks_per_second
from .contacts import sort_awake, update_manifolds
from .continuous import toi_scratch
from .freeze import POLICY_NAMES, resolve
from .packing import pack
from .scene import Scene
from .state import State
from .tolerances import body_margin, body_slop, body_speculative, check_step

#: Initial-impulse solve stops when no contact's impulse changes by more than this fraction of the
#: largest over 10 sweeps.
INITIAL_TOLERANCE = 1e-6

#: Room for this many contacts per body (and grid entries per body) when a World is built; the
#: step loop reports a buffer it outgrows and the World grows it (tests set it small).
INITIAL_CAPACITY = 4

#: Settings of the solver before soft step, refused with the reason.
REMOVED = {
    "position_iterations": "the soft-step solver has no position-correction sweeps (the soft "
    "contact pushes bodies apart within the velocity solve); use substeps",
    "baumgarte": "the soft-step solver has no Baumgarte factor; contact stiffness is "
    "contact_hertz and damping_ratio",
    "max_correction": "the soft-step solver has no position correction; the push-out speed is "
    "push_speed (m/s)",
}


class SimulationError(RuntimeError):
    """A run that cannot go on: a body's state became NaN or infinite, or flew out of range."""


#: s: ``step(n)`` calls the compiled step loop in pieces of about this long. Ctrl-C cannot stop
#: compiled code, and is seen between the pieces: a long ``step`` stops within about this long, at
#: a step boundary (the pieces are the same steps: the run is bit-identical however it is cut).
CHUNK_S = 0.05
#: steps of the first piece, before the World has measured how long a step takes
FIRST_CHUNK = 64

#: Caps on the solver's counts. A step is compiled code that Ctrl-C cannot stop (it is seen only
#: between steps): iterations=10**9 made one step of one box take over a minute. Far beyond any
#: accuracy the sweeps buy (fig_tradeoff: the error stops falling long before), and each step
#: still a fraction of a second on a small scene.
MAX_SUBSTEPS = 1000
MAX_SWEEPS = 1000  # iterations, and relax_iterations, per substep
MAX_INITIAL_ITERATIONS = 10**6
LIMITS_WHY = (
    "a step cannot be interrupted, and more sweeps than this buy no accuracy "
    "(see sim.world.MAX_SWEEPS)"
)

#: the solver's fast paths (see World's ``fast_paths``)
FAST_PATHS = ("friction",)


def _fast_paths(value):
    """The fast paths switched on, as a sorted tuple of names; ValueError for unknown names."""
    if value is True:
        return tuple(sorted(FAST_PATHS))
    if value is False or value is None:
        return ()
    if isinstance(value, str):
        value = (value,)
    try:
        names = tuple(sorted(set(value)))
    except TypeError:
        raise ValueError(
            f"fast_paths must be True, False or a collection of names from "
            f"{FAST_PATHS}, got {value!r}"
        ) from None
    unknown = [n for n in names if n not in FAST_PATHS]
    if unknown:
        raise ValueError(
            f"fast_paths: unknown fast path(s) {unknown}; choose from {sorted(FAST_PATHS)}"
        )
    return names


#: kg and kg m^2: a dynamic body's mass and moment of inertia must lie in this range. A step
#: multiplies them by speeds squared (kinetic energy), by each other (a pair's effective mass) and
#: by their inverses; float64 holds 1e308, and 1e100 either way leaves room for all of those (a
#: 1 m box of density 1e308 built a World whose kinetic energy was inf).
MASS_RANGE = (1e-100, 1e100)


def _check_mass_properties(packed, describe):
    """ValueError naming the first dynamic body whose mass properties the solver cannot use:
    finite fields can still overflow them (vertices at 1e155 m square to inf: mass inf, inertia
    NaN), underflow them (density 1e-320 kg/m^2: a mass whose inverse is inf), or leave
    ``MASS_RANGE``."""
    n = packed.n_dynamic
    lo, hi = MASS_RANGE
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        fine = (
            (packed.mass >= lo)
            & (packed.mass <= hi)
            & (packed.inertia >= lo)
            & (packed.inertia <= hi)
            & np.isfinite(packed.position[:n]).all(axis=1)
            & np.isfinite(packed.extent[:n])
            & np.isfinite(packed.size[:n])
        )
    if not fine.all():
        i = int(np.flatnonzero(~fine)[0])
        raise ValueError(
            f"{describe(i)}: its mass properties are beyond what the solver can use (mass "
            f"{packed.mass[i]:.4g} kg, moment of inertia {packed.inertia[i]:.4g} kg m^2, extent "
            f"{packed.extent[i]:.4g} m; both must lie in [{lo:g}, {hi:g}]): its size or density "
            f"is too extreme; scale the scene"
        )


@contextlib.contextmanager
def _deferred_sigint():
    """Within: Ctrl-C (SIGINT) is recorded, not raised; yields a function saying whether it came.
    Raised inside the compiled step loop, KeyboardInterrupt surfaced only when the call returned,
    as "SystemError: CPUDispatcher(run) returned a result with an exception set". Only the main
    thread can take signals, and a handler the program installed itself is left alone."""
    if (
        threading.current_thread() is not threading.main_thread()
        or signal.getsignal(signal.SIGINT) is not signal.default_int_handler
    ):
        yield lambda: False
        return
    came = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: came.append(signum))
    try:
        yield lambda: bool(came)
    finally:
        signal.signal(signal.SIGINT, previous)


def _aligned(shape, dtype=np.float64):
    """A zeroed array whose data starts on a 64-byte boundary (a solver row is one cache line)."""
    n = int(np.prod(shape))
    itemsize = np.dtype(dtype).itemsize
    raw = np.zeros(n * itemsize + 64, np.uint8)
    offset = (-raw.ctypes.data) % 64
    return raw[offset : offset + n * itemsize].view(dtype).reshape(shape)


def _mixed_masses(inv_mass):
    """Can any contact be "hard" (soft_step.HARD_RATIO)? Only if two dynamic bodies' masses
    differ by more than the ratio: a freeze policy only ever zeroes solver masses (immovable
    bodies are never hard), so this holds for the World's life and the colouring skips the
    search for hard contacts in uniform scenes."""
    movable = inv_mass[inv_mass > 0.0]
    return bool(movable.size and movable.max() > soft_step.HARD_RATIO * movable.min())


class World:
    """A running simulation of a ``sim.Scene``.

    The World keeps a copy of the scene as it was when built (``world.scene``, array-backed):
    edits to the scene afterwards do not reach the run; build a new World to run an edited scene.

    Parameters (SI units)
      dt                    time step, s (default 1/60)
      substeps              soft-step substeps per step (default 4): the knob that trades speed
                            for stiffness and accuracy (``sim.soft_step``)
      iterations            biased solve sweeps per substep (default 1)
      relax_iterations      unbiased sweeps per substep (default 1)
      freeze                "off" | "sleep" | "paper" | "extended" (see ``sim.freeze``)
      slop                  m, contact tolerance cap (default 0.005, pymunk's collision_slop):
                            points within a pair's slop count as touching; pairs of small bodies
                            use a fraction of their size instead (``sim.tolerances``)
      speculative_distance  m, cap of the distance at which contacts are made before touching
                            (default 0.02); grows with the bodies' speeds
      contact_hertz         Hz, stiffness of a contact between moving bodies (default None: an
                            eighth of the substep rate, 30 Hz at 4 substeps of 1/60 s; raised for
                            small bodies; never above that eighth; doubled against immovable
                            bodies)
      damping_ratio         of the soft contact (default 30)
      push_speed            m/s, fastest a contact pushes overlapping bodies apart (default 3)
      load_time             s, how fast a contact's carried load (held rigidly: resting stacks do
                            not sink) follows the impulse it applies (default 1/3; 0: at once)
      restitution_threshold impacts slower than this do not bounce, m/s (default 1.0)
      warm_starting         start each step from last step's impulses (default True)
      continuous            sweep fast bodies against static and frozen ones (bullets: against
                            every body) so they cannot pass through in one step (default True)
      overlap_tolerance     initial overlap allowed between bodies / with the floor, m (default
      0.01)
      initial_iterations    most sweeps spent once, before step 1, solving the initial contact
                            impulses to convergence (nothing moves; stops early when converged;
                            default 5000, 0 disables): a scene placed at rest starts in
                            equilibrium. Needs warm_starting.
      fast_paths            True (default), False, or a collection of names from FAST_PATHS:
                            work skipped when the scene does not need it ("friction": no
                            friction rows for batches of frictionless contacts, which is exact).
                            False exists to measure the saving (experiments/bench_fast_paths.py).
      **policy_parameters   the freeze policy's own parameters (e.g. impulse_threshold)

    Arrays read from a World are copies: positions (N,2) m (centres of mass), angles (N,) rad,
    velocities (N,2) m/s, angular_velocities (N,) rad/s, states (N,) int8 ``sim.State``.
    ``inspect()`` gives a read-only view of the contacts and the solver; ``profile(n)`` runs
    steps with every stage timed.
    """

    def __init__(
        self,
        scene,
        dt=1 / 60,
        iterations=1,
        freeze="off",
        *,
        substeps=4,
        relax_iterations=1,
        slop=0.005,
        speculative_distance=0.02,
        contact_hertz=None,
        damping_ratio=soft_step.DAMPING_RATIO,
        push_speed=soft_step.PUSH_SPEED,
        load_time=soft_step.LOAD_TIME,
        restitution_threshold=1.0,
        warm_starting=True,
        continuous=True,
        overlap_tolerance=0.01,
        initial_iterations=5000,
        fast_paths=True,
        **policy_parameters,
    ):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a sim.Scene, got {type(scene).__name__}")
        for name in sorted(set(policy_parameters) & set(REMOVED)):
            raise ValueError(f"World does not take {name}: {REMOVED[name]}")
        # A copy taken now (validated): the steps, the reports (potential_energy, the names in
        # messages) and ``world.scene`` all see the scene as it was when the World was built.
        # Holding the caller's object, a later edit was half-seen: potential_energy() used the
        # new gravity while the steps kept the old.
        self.scene = scene = scene.snapshot()
        self._gravity = np.array(scene.gravity, dtype=np.float64)  # (2,) m/s^2
        self._names = (
            scene.body_arrays.body_name,
            tuple(b.name or f"static body {j}" for j, b in enumerate(scene.static_bodies)),
        )
        self.dt = positive(dt, "dt")
        self.substeps = count(substeps, "substeps", 1, MAX_SUBSTEPS, LIMITS_WHY)
        self.iterations = count(iterations, "iterations", 1, MAX_SWEEPS, LIMITS_WHY)
        self.relax_iterations = count(
            relax_iterations, "relax_iterations", 0, MAX_SWEEPS, LIMITS_WHY
        )
        self.slop = positive(slop, "slop", allow_zero=True)
        self.speculative_distance = positive(
            speculative_distance, "speculative_distance", allow_zero=True
        )
        self.contact_hertz = (
            None if contact_hertz is None else positive(contact_hertz, "contact_hertz")
        )
        self.damping_ratio = positive(damping_ratio, "damping_ratio", allow_zero=True)
        self.push_speed = positive(push_speed, "push_speed")
        self.load_time = positive(load_time, "load_time", allow_zero=True)
        self.restitution_threshold = positive(
            restitution_threshold, "restitution_threshold", allow_zero=True
        )
        self.warm_starting = flag(warm_starting, "warm_starting")
        self.continuous = flag(continuous, "continuous")
        self.fast_paths = _fast_paths(fast_paths)
        self.overlap_tolerance = positive(overlap_tolerance, "overlap_tolerance", allow_zero=True)
        self.initial_iterations = count(
            initial_iterations, "initial_iterations", 0, MAX_INITIAL_ITERATIONS, LIMITS_WHY
        )
        self.freeze = freeze
        self.policy, self.policy_parameters = resolve(freeze, policy_parameters)

        packed = pack(scene)
        self.n_bodies = packed.n_dynamic
        self.masses = packed.mass  # (N,) kg
        self.inertias = packed.inertia  # (N,) kg m^2 about the COM
        self.extents = packed.extent  # (M,) m, COM to farthest vertex
        self.sizes = packed.size  # (M,) m, thinnest width
        _check_mass_properties(packed, self._describe)
        g = float(np.hypot(*scene.gravity))
        check_step(packed.size[: self.n_bodies], self._describe, self.dt, self.substeps, g)
        self._build(scene, packed)
        self.events = []  # (step, body, from_state, to_state, cause)
        self.max_penetration = 0.0  # m, deepest contact penetration seen since the start
        self.penetration = 0.0  # m, after the last step
        self._step_s = None  # s, wall time of a step, as last measured (sizes the pieces)
        self._diverged = None  # why the World cannot step any more, once it diverged
        self._detect()
        self._check_initial_overlap()
        if self.initial_iterations and self.warm_starting:
            while K.presolve(self.initial_iterations, INITIAL_TOLERANCE, *self._state()) == K.GROW:
                self._grow()

    # ---- set-up -----------------------------------------------------------------------------
    def _build(self, scene, p):
        n = p.n_dynamic
        m = len(p.angle)
        self._bodies = D.Bodies(
            position=p.position,
            angle=p.angle,
            velocity=p.velocity,
            angular_velocity=p.angular_velocity,
            inv_mass=p.inv_mass,
            inv_inertia=p.inv_inertia,
            friction=p.friction,
            restitution=p.restitution,
            vert_start=p.vert_start,
            local_verts=p.local_verts,
            local_normals=p.local_normals,
            extent=p.extent,
            size=p.size,
            slop=body_slop(p.size, self.slop),
            speculative=body_speculative(p.size, self.speculative_distance),
            margin=body_margin(p.size, self.speculative_distance),
            bullet=p.bullet,
        )
        v_total = len(p.local_verts)
        fat = np.empty((m, 4))
        fat[:, :2] = np.inf  # an empty box: every body's first box refits it
        fat[:, 2:] = -np.inf
        self._geometry = D.Geometry(
            rotation=np.empty((m, 2)),
            world_verts=np.empty((v_total, 2)),
            world_normals=np.empty((v_total, 2)),
            aabb=np.empty((m, 4)),
            fat=fat,
            moved=np.zeros(n, np.int64),
            moved_flag=np.zeros(n, bool),
            toi_scratch=toi_scratch(int(np.diff(p.vert_start).max())),
        )
        # Grid cell, m: about two typical bodies wide, but large enough that the biggest body (a
        # long wall, a plank) covers at most ~32 cells per axis.
        typical = float(np.quantile(p.extent[:n], 0.9))
        cell_size = max(
            2.0 * typical + 2.0 * self.speculative_distance, float(p.extent.max()) / 16.0
        )
        g = scene.gravity
        has_floor = scene.floor_y is not None
        params = self.policy_parameters
        self._settings = D.Settings(
            dt=self.dt,
            substeps=self.substeps,
            iterations=self.iterations,
            relax_iterations=self.relax_iterations,
            gravity_x=float(g[0]),
            gravity_y=float(g[1]),
            has_floor=has_floor,
            floor_y=float(scene.floor_y) if has_floor else 0.0,
            floor_friction=float(scene.floor_friction),
            floor_restitution=float(scene.floor_restitution),
            slop=self.slop,
            speculative_distance=self.speculative_distance,
            contact_hertz=self.contact_hertz or 0.0,
            damping_ratio=self.damping_ratio,
            push_speed=self.push_speed,
            load_rate=min(1.0, self.dt / self.load_time) if self.load_time > 0 else 1.0,
            restitution_threshold=self.restitution_threshold,
            warm_starting=self.warm_starting,
            fast_friction="friction" in self.fast_paths,
            continuous=self.continuous,
            cell_size=cell_size,
            n_dynamic=n,
            policy=POLICY_NAMES.index(self.freeze),
            impulse_threshold=float(params.get("impulse_threshold", 0.0)),
            sleep_speed=float(params.get("sleep_speed", 0.0)),
            sleep_time=float(params.get("sleep_time", 0.0)),
            rest_speed=float(params.get("rest_speed", 0.0)),
            rest_acceleration=float(params.get("rest_acceleration", 0.0)),
            rest_steps=int(params.get("rest_steps", 1)),
            slip_speed=float(params.get("slip_speed", 0.0)),
            friction_margin=float(params.get("friction_margin", 0.0)),
            tip_margin=float(params.get("tip_margin", 0.0)),
            mixed_masses=_mixed_masses(p.inv_mass[:n]),
            profile=False,
        )
        self._counters = np.zeros(D.N_COUNTERS, np.int64)
        self._counters[D.N_AWAKE] = n  # every body starts awake
        self._counters[D.FREE_HEAD] = -1
        self._counters[D.RESTING_DIRTY] = 1
        self._activity = initial_activity(n, m, p.inv_mass, p.inv_inertia, self.policy)
        k = INITIAL_CAPACITY
        small = k < 4  # tests: no minimum either
        self._awake_grid = grid_buffers(
            k * n + (0 if small else 64), k if small else max(4 * k * n, 4096)
        )
        self._resting_grid = grid_buffers(
            k * m + (0 if small else 64), k if small else max(4 * k * m, 4096)
        )
        self._scratch = np.zeros(m, np.int64)
        self._contacts = self._new_contacts(k if small else max(64, k * m), n)
        self._solver = self._new_solver(len(self._contacts.awake), 1 if small else 4)
        self._regrown = 0

    @staticmethod
    def _new_contacts(capacity, n):
        return D.Contacts(
            contact_int=np.zeros((capacity, D.CONTACT_INT), np.int64),
            contact_float=np.zeros((capacity, D.CONTACT_FLOAT)),
            point_float=np.zeros((capacity, 2, D.POINT_FLOAT)),
            point_id=np.full((capacity, 2), -1, np.int64),
            head=np.full(n, -1, np.int64),
            degree=np.zeros(n, np.int64),
            awake=np.zeros(capacity, np.int64),
            active=np.zeros(capacity, np.int64),
            scratch_points=np.zeros((2, 2)),
            scratch_separations=np.zeros(2),
            scratch_ids=np.zeros(2, np.int64),
            scratch_normal=np.zeros(2),
        )

    def _new_solver(self, n_contacts, max_degree):
        n = self.n_bodies
        batches = soft_step.capacity(n_contacts, max_degree)
        words = soft_step.mask_words(max_degree)
        old = getattr(self, "_solver", None)
        return D.Solver(
            state=_aligned((n + 1, D.STATE_COLUMNS)),
            colour_mask=np.zeros((n + 1, words), np.uint64),
            colour_batches=np.zeros(64 * words + 1, np.int64),
            colour_cursor=np.zeros(64 * words, np.int64),
            order=np.zeros(n_contacts, np.int64),
            wide=_aligned((batches * soft_step.STRIDE,)),
            lane_row=np.zeros(batches * 2 * soft_step.LANES, np.uint64),
            lane_slot=np.full(batches * soft_step.LANES, -1, np.int64),
            batch_hard=np.zeros(batches, bool),
            row_mark=np.zeros(n + 1, bool),
            profile=old.profile if old is not None else np.zeros(D.N_STAGES, np.int64),
            steps_profiled=(old.steps_profiled if old is not None else np.zeros(1, np.int64)),
        )

    def _state(self, settings=None):
        """The arguments every step-level kernel in ``sim.kernel`` takes."""
        return (
            settings or self._settings,
            self._counters,
            self._bodies,
            self._geometry,
            self._awake_grid,
            self._resting_grid,
            self._contacts,
            self._solver,
            self._activity,
            self._scratch,
        )

    def _grow(self):
        """Grow what the kernel reported too small (counters[GROW_NEEDED]); it then retries."""
        self._regrown += 1
        need = int(self._counters[D.GROW_NEEDED])
        self._counters[D.GROW_NEEDED] = 0
        c = self._counters
        if need & D.GROW_CONTACTS:
            old = self._contacts
            cap = 2 * len(old.awake)
            new = self._new_contacts(cap, self.n_bodies)
            k = int(c[D.N_SLOTS])
            for name in ("contact_int", "contact_float", "point_float", "point_id"):
                getattr(new, name)[:k] = getattr(old, name)[:k]
            new.head[:] = old.head
            new.degree[:] = old.degree
            na = int(c[D.N_AWAKE_CONTACTS])
            new.awake[:na] = old.awake[:na]
            self._contacts = new
        if need & (D.GROW_CONTACTS | D.GROW_SOLVER):
            self._solver = self._new_solver(
                len(self._contacts.awake), 2 * max(1, int(c[D.MAX_DEGREE]))
            )
        for bit, attr in (
            (D.GROW_AWAKE_GRID, "_awake_grid"),
            (D.GROW_RESTING_GRID, "_resting_grid"),
        ):
            if need & bit:
                info = getattr(self, attr).info
                setattr(
                    self,
                    attr,
                    grid_buffers(2 * int(info[D.NEEDED_ENTRIES]), 2 * int(info[D.NEEDED_BUCKETS])),
                )
        if not need:
            raise AssertionError("the kernel asked to grow but named no buffer")

    def _detect(self):
        """Pairs and manifolds of the start poses (the first step would make the same)."""
        while not K.broadphase(*self._state()):
            self._grow()
        sort_awake(len(self._bodies.angle), self._contacts, self._counters)
        update_manifolds(
            self._settings, self._bodies, self._geometry, self._contacts, self._counters
        )

    def _check_initial_overlap(self):
        """Refuse scenes whose bodies start interpenetrated beyond ``overlap_tolerance``: the
        contacts would launch them apart and the run would measure nothing real."""
        points = self._points()
        if not len(points["separation"]):
            return
        k = int(np.argmin(points["separation"]))
        depth = -float(points["separation"][k])
        if depth > self.overlap_tolerance:
            a, b = int(points["body_a"][k]), int(points["body_b"][k])
            what_b = self._describe(b)
            what = (
                f"{what_b} starts {depth:.4g} m below the floor"
                if a < 0
                else f"{self._describe(a)} and {what_b} start overlapping by {depth:.4g} m"
            )
            raise ValueError(f"{what} (overlap_tolerance is {self.overlap_tolerance} m)")

    def _describe(self, i):
        dynamic, static = self._names
        return dynamic(i) if i < self.n_bodies else static[i - self.n_bodies]

    # ---- stepping ---------------------------------------------------------------------------
    def step(self, n=1):
        """Advance ``n`` steps (default 1). Raises SimulationError if a body goes non-finite."""
        return self._run(count(n, "n", 0), self._settings)

    def _run(self, n, settings):
        if n == 0:
            return self
        if self._diverged:
            raise SimulationError(
                f"{self._diverged}; this World cannot step any further: build a "
                f"new one (from the scene, or from poses saved before step "
                f"{self.step_count})"
            )
        done = 0
        with _deferred_sigint() as interrupted:
            while done < n:
                chunk = n - done
                chunk = min(
                    chunk,
                    FIRST_CHUNK
                    if self._step_s is None
                    else max(1, int(CHUNK_S / max(self._step_s, 1e-9))),
                )
                min_sep = np.zeros(chunk)
                start = time.perf_counter()
                status, steps = K.run(chunk, *self._state(settings), min_sep)
                if steps:
                    self._step_s = (time.perf_counter() - start) / steps
                done += steps
                self._flush_events()
                self._record_penetration(min_sep[:steps])
                if status == K.GROW:
                    self._grow()
                elif status == K.NON_FINITE:
                    i = int(self._counters[D.BAD_BODY])
                    self._diverged = (
                        f"step {self.step_count}: {self._describe(i)} diverged (non-finite, or "
                        f"farther than {K.MAX_COORDINATE:g} m) "
                        f"(position {self._bodies.position[i].tolist()}, angle "
                        f"{self._bodies.angle[i]}, velocity {self._bodies.velocity[i].tolist()}, "
                        f"angular velocity {self._bodies.angular_velocity[i]})"
                    )
                    raise SimulationError(
                        f"{self._diverged}; try a smaller dt, more substeps, or check the scene"
                    )
                if interrupted():
                    raise KeyboardInterrupt(
                        f"World.step interrupted after {done} of {n} steps; the World is whole, "
                        f"at step {self.step_count}, and can step on"
                    )
        return self

    def profile(self, n=1):
        """Run ``n`` steps with every stage timed; returns {stage: ms per step} (``data.STAGES``)
        for these steps, plus "total"."""
        n = count(n, "n", 1)
        self._solver.profile[:] = 0
        self._solver.steps_profiled[0] = 0
        self._run(n, self._settings._replace(profile=True))
        rate = ticks_per_second()
        steps = max(1, int(self._solver.steps_profiled[0]))
        out = {
            name: 1e3 * float(t) / rate / steps for name, t in zip(D.STAGES, self._solver.profile)
        }
        out["total"] = sum(out.values())
        return out

    def _flush_events(self):
        """Move the kernel's event buffer into ``self.events`` as (step, body, from, to, cause)."""
        k = int(self._counters[D.N_EVENTS])
        if k:
            rows = self._activity.events[:k].tolist()
            self.events.extend(
                (step, body, State(a), State(b), CAUSES[cause]) for step, body, a, b, cause in rows
            )
            self._counters[D.N_EVENTS] = 0

    def _record_penetration(self, min_sep):
        """Penetration after the last of these steps, and the deepest over them (m)."""
        if len(min_sep):
            self.penetration = max(0.0, -float(min_sep[-1]))
            self.max_penetration = max(self.max_penetration, -float(min_sep.min()))

    # ---- observables (copies, so callers cannot corrupt the state) ---------------------------
    @property
    def positions(self):
        return self._bodies.position[: self.n_bodies].copy()

    @property
    def angles(self):
        return self._bodies.angle[: self.n_bodies].copy()

    @property
    def velocities(self):
        return self._bodies.velocity[: self.n_bodies].copy()

    @property
    def angular_velocities(self):
        return self._bodies.angular_velocity[: self.n_bodies].copy()

    @property
    def states(self):
        return self._activity.states.copy()

    @property
    def frozen(self):
        """(N,) bool: bodies out of the awake list this step: not integrated, not solved, not
        collided against each other (what "frozen" costs nothing means). Under ``paper`` a body
        can be VERTICAL_STABLE or a sliding ROTATION_STABLE and still be awake."""
        return self._activity.awake_slot[: self.n_bodies] < 0

    @property
    def n_awake(self):
        """Number of bodies in the awake list."""
        return int(self._counters[D.N_AWAKE])

    @property
    def step_count(self):
        return int(self._counters[D.STEP_COUNT])

    @property
    def time(self):
        """Simulated time, s."""
        return self.step_count * self.dt

    def kinetic_energy(self):
        """Total kinetic energy, J (translational + rotational)."""
        v = self._bodies.velocity[: self.n_bodies]
        w = self._bodies.angular_velocity[: self.n_bodies]
        return 0.5 * float(self.masses @ np.einsum("ij,ij->i", v, v) + self.inertias @ (w * w))

    def potential_energy(self):
        """Gravitational potential energy relative to the origin, J."""
        return -float(self.masses @ (self._bodies.position[: self.n_bodies] @ self._gravity))

    def vertices(self, i):
        """World vertices (K,2) of dynamic body ``i`` at the current pose, m."""
        b = self._bodies
        c, s = math.cos(b.angle[i]), math.sin(b.angle[i])
        local = b.local_verts[b.vert_start[i] : b.vert_start[i + 1]]
        return local @ np.array([[c, s], [-s, c]]) + b.position[i]

    def _points(self):
        """Every point of this step's active contacts (see ``contacts``)."""
        c = self._contacts
        slots = c.active[: int(self._counters[D.N_ACTIVE])]
        n_pts = c.contact_int[slots, D.POINT_COUNT]
        rows = np.repeat(slots, n_pts)
        cols = np.concatenate([np.arange(k) for k in n_pts]) if len(slots) else np.zeros(0, int)
        b = c.contact_int[rows, D.BODY_B]
        pf = c.point_float[rows, cols]
        return {
            "body_a": c.contact_int[rows, D.BODY_A].copy(),
            "body_b": b.copy(),
            "point": pf[:, [D.ANCHOR_BX, D.ANCHOR_BY]] + self._bodies.position[b],
            "normal": c.contact_float[rows][:, [D.NORMAL_X, D.NORMAL_Y]].copy(),
            "separation": pf[:, D.SEPARATION].copy(),
            "end_separation": pf[:, D.END_SEPARATION].copy(),
            "slop": c.contact_float[rows, D.SLOP].copy(),
            "normal_impulse": pf[:, D.NORMAL_IMPULSE].copy(),
            "tangent_impulse": pf[:, D.TANGENT_IMPULSE].copy(),
        }

    def contacts(self):
        """The contact points of the last step: dict of arrays over points —
        body_a, body_b (-1 = floor) (P,) int; point (P,2) m (on B's surface at the start of the
        step); normal (P,2) A->B; separation (P,) m at the start of the step, end_separation (P,)
        m at its end; slop (P,) m, the pair's contact tolerance (points within it touch,
        ``sim.tolerances``); normal_impulse, tangent_impulse (P,) N s applied over the whole
        step."""
        return self._points()

    def inspect(self):
        """A read-only snapshot of the solver's bookkeeping (copies), for tests, benchmarks and
        recordings: see ``Inspection``."""
        return Inspection(self)

    def __repr__(self):
        return (
            f"World(scene={self.scene.name!r}, bodies={self.n_bodies}, dt={self.dt}, "
            f"substeps={self.substeps}, iterations={self.iterations}, "
            f"freeze={self.freeze!r}, step={self.step_count})"
        )


def _pair_colours(solver, contact_int, n_colours):
    out = {}
    for colour in range(n_colours):
        lanes = solver.lane_slot[
            solver.colour_batches[colour] * soft_step.LANES : solver.colour_batches[colour + 1]
            * soft_step.LANES
        ]
        for slot in lanes[lanes >= 0]:
            out[(int(contact_int[slot, D.BODY_A]), int(contact_int[slot, D.BODY_B]))] = colour
    return out


class Inspection:
    """What a World's solver holds after its last step, as plain copies (changing them changes
    nothing in the World).

      contacts             the active contacts' points (``World.contacts()``)
      n_contacts           live contact slots: pairs whose fat boxes overlap
      n_awake_contacts     of those, the ones with an awake body (looked at every step)
      n_active             of those, the ones with points this step (solved)
      n_refreshed          of the awake ones, refreshed from their stored points last step
      n_skipped            of the awake ones, skipped last step: apart by more than they could
                           close (``contacts.update_manifolds``)
      awake                (n_awake,) indices of the awake bodies
      solver_inv_mass      (N,) 1/kg the solver used (0 for frozen and held bodies)
      n_colours, n_batches the last step's constraint colours and batches of ``LANES``
      pair_colour          {(body_a, body_b): colour} of the last step's active contacts, in the
                           order the sweeps solve them (body_a = -1: the floor)
      lanes                soft_step.LANES
      batch_fill           fraction of the batch lanes that hold a contact
      resting_rebuilds     how many times the resting grid was rebuilt since the start
      presolve_sweeps      sweeps the initial-impulse solve took
      regrown              how many times a buffer the step loop outgrew was grown
      sweeps, impacts      fast bodies swept (stage ``continuous``), and cut back to an impact
      n_hard_batches       batches that got soft_step.HARD_SWEEPS extra relax sweeps (they hold a
                           contact touching a body in a contact of mass ratio > HARD_RATIO)
      certificates         rest certificates tried since the start (extended:
                           ``sim.freeze.certificate``; one per candidate body per step)
    """

    def __init__(self, world):
        c = world._counters
        self.contacts = world.contacts()
        self.n_contacts = int(c[D.N_LIVE])
        self.n_awake_contacts = int(c[D.N_AWAKE_CONTACTS])
        self.n_active = int(c[D.N_ACTIVE])
        self.n_refreshed = int(c[D.N_REFRESHED])
        self.n_skipped = int(c[D.N_SKIPPED])
        self.awake = world._activity.awake[: int(c[D.N_AWAKE])].copy()
        self.solver_inv_mass = world._activity.solver_inv_mass[: world.n_bodies].copy()
        self.n_colours = int(c[D.N_COLOURS])
        self.n_batches = int(c[D.N_BATCHES])
        self.pair_colour = _pair_colours(world._solver, world._contacts.contact_int, self.n_colours)
        self.lanes = soft_step.LANES
        self.batch_fill = self.n_active / (self.n_batches * self.lanes) if self.n_batches else 1.0
        self.resting_rebuilds = int(c[D.N_REBUILDS])
        self.presolve_sweeps = int(c[D.PRESOLVE_SWEEPS])
        self.regrown = world._regrown
        self.sweeps = int(c[D.N_SWEPT])
        self.impacts = int(c[D.N_IMPACTS])
        self.n_hard_batches = int(c[D.N_HARD])
        self.certificates = int(c[D.N_CERTIFICATES])

    def __repr__(self):
        return (
            f"Inspection(contacts={self.n_contacts}, awake_contacts={self.n_awake_contacts}, "
            f"active={self.n_active}, colours={self.n_colours}, batches={self.n_batches})"
        )
