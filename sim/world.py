"""``sim.World``: the Python facade. It validates a Scene and the settings, packs the bodies into
struct-of-arrays (``sim.packing``), builds the named state the kernels share (``sim.data``), and
hands whole runs of steps to the compiled step loop (``sim.kernel.run``).

This module is the facade as a caller sees it: construction, stepping, and the observables. What
it delegates, by job: ``sim.validation`` what a World refuses (and why), ``sim.buffers`` the
arrays the step loop works in (their sizes, and their growth when a step outgrows them),
``sim.reports`` the read-only reports (``contacts()``, ``inspect()``), ``sim.calls`` the call into
the compiled step loop (Ctrl-C deferred, Numba's type dispatch skipped)."""

import time

import numpy as np

from . import data as D
from . import kernel as K
from . import soft_step
from .arguments import count, flag, positive
from .activity import CAUSES, initial_activity
from .broadphase import grid_buffers
from .calls import Compiled, Deferred
from . import geometry, presolve
from .buffers import grown, new_bodies, new_contacts, new_geometry, new_solver
from .clock import ticks_per_second
from .contacts import sort_awake
from .freeze import POLICY_NAMES, resolve
from .freeze.extended_layout import TESTED, WAIT_NAMES, WAIT_NONE, WAITING
from .narrowphase import update_manifolds
from .packing import pack
from .reports import Inspection, contact_points, deepest_point
from .scene import Scene
from .state import State
from .tolerances import check_softness, check_step
from .validation import (
    check_policy_gravity,
    limits_why,
    initial_sweeps,
    MAX_SUBSTEPS,
    MAX_SWEEPS,
    REMOVED,
    check_initial_overlap,
    check_mass_properties,
    check_policy_arguments,
    check_range,
    fast_path_names,
    mixed_masses,
)

#: Room for this many contacts per body (and grid entries per body) when a World is built; the
#: step loop reports a buffer it outgrows and the World grows it (tests set it small).
INITIAL_CAPACITY = 4


class SimulationError(RuntimeError):
    """A run that cannot go on: a body's state became NaN or infinite, or flew out of range."""


#: s: ``step(n)`` calls the compiled step loop in pieces of about this long. Ctrl-C cannot stop
#: compiled code, and is seen between the pieces: a long ``step`` stops within about this long, at
#: a step boundary (the pieces are the same steps: the run is bit-identical however it is cut).
CHUNK_S = 0.05
#: steps of the first piece, before the World has measured how long a step takes
FIRST_CHUNK = 64


class World:
    """A running simulation of a ``sim.Scene``.

    The World keeps a copy of the scene as it was when built (``world.scene``, array-backed):
    edits to the scene afterwards do not reach the run; build a new World to run an edited scene.

    Parameters (SI units)
      dt                    time step, s (default 1/60)
      substeps              soft-step substeps per step (default 4): the knob that trades speed
                            for stiffness and accuracy (``sim.soft_step``)
      iterations            biased solve sweeps per substep (default 1)
      relax_iterations      unbiased sweeps per substep (default 1). Not an accuracy knob:
                            more make landings worse (a box dropped across a gap moves 0.04 mm
                            sideways with 1, 0.8-1.2 mm with 2-16; fig_tradeoff's landing 0.57 mm
                            from its rest pose with 1, 2.2-17 mm with 2-16; 2026-12-05). Raise
                            ``iterations`` instead (fig_tradeoff of 2026-12-07: 0.66 mm at the
                            defaults; iterations 2-8: 0.27-0.55 mm; ``substeps`` 8: 0.35 mm, but
                            16: 5.8 mm; docs/ARCHITECTURE.md section 2.3)
      impact_iterations     more biased sweeps per substep, with friction rows, for the contacts
                            around an impact, in a step with one (a contact point approaching
                            faster than soft_step.IMPACT_SWEEP_SPEED, 1 m/s; default 8, 0
                            disables): a landing converged, not left to slide sideways
      freeze                "off" | "sleep" | "paper" | "extended" (see ``sim.freeze``);
                            "paper" only under gravity straight down (the seed's floor test)
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
      continuous            the speculative contacts' backstop: a fast body left deep in or past
                            a static or frozen one (bullet: any) goes back to the impact (True)
      overlap_tolerance     initial overlap allowed between bodies / with the floor, m (default
      0.01)
      initial_iterations    most sweeps spent once, before step 1, solving the initial contact
                            impulses to convergence (nothing moves; stops early when converged;
                            0 disables; default 5000, or 0 without warm_starting, which it
                            needs): a scene placed at rest starts in equilibrium. The default
                            also spends at most ``sim.presolve.WORK`` contact-sweeps (1-2 s),
                            and warns if that leaves it unconverged (tall stacks of
                            10^5 bodies); ``inspect()`` reports the sweeps and convergence.
      fast_paths            True (default), False, or a collection of names from
                            ``sim.validation.FAST_PATHS``: work skipped when the scene does not
                            need it, each exact ("friction": no friction rows for batches of
                            frictionless contacts; "quiet": once a step has begun and ended
                            with every body frozen, the steps after it only count, for they
                            would change nothing). False exists to measure the saving
                            (experiments/bench_fast_paths.py).
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
        impact_iterations=soft_step.IMPACT_ITERATIONS,
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
        initial_iterations=None,
        fast_paths=True,
        **policy_parameters,
    ):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a sim.Scene, got {type(scene).__name__}")
        for name in sorted(set(policy_parameters) & set(REMOVED)):
            raise ValueError(f"World does not take {name}: {REMOVED[name]}")
        check_policy_arguments(freeze, policy_parameters, World.__init__)
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
        self.substeps = count(substeps, "substeps", 1, MAX_SUBSTEPS, limits_why("MAX_SUBSTEPS"))
        self.iterations = count(iterations, "iterations", 1, MAX_SWEEPS, limits_why("MAX_SWEEPS"))
        self.relax_iterations = count(
            relax_iterations, "relax_iterations", 0, MAX_SWEEPS, limits_why("MAX_SWEEPS")
        )
        self.impact_iterations = count(
            impact_iterations, "impact_iterations", 0, MAX_SWEEPS, limits_why("MAX_SWEEPS")
        )
        self.slop = positive(slop, "slop", allow_zero=True)
        self.speculative_distance = positive(
            speculative_distance, "speculative_distance", allow_zero=True
        )
        self.contact_hertz = (
            None if contact_hertz is None else positive(contact_hertz, "contact_hertz")
        )
        self.damping_ratio = positive(damping_ratio, "damping_ratio", allow_zero=True)
        check_softness(self.dt, self.substeps, self.damping_ratio, self.contact_hertz)
        self.push_speed = positive(push_speed, "push_speed")
        self.load_time = positive(load_time, "load_time", allow_zero=True)
        self.restitution_threshold = positive(
            restitution_threshold, "restitution_threshold", allow_zero=True
        )
        self.warm_starting = flag(warm_starting, "warm_starting")
        self.continuous = flag(continuous, "continuous")
        self.fast_paths = fast_path_names(fast_paths)
        self.overlap_tolerance = positive(overlap_tolerance, "overlap_tolerance", allow_zero=True)
        self.initial_iterations = initial_sweeps(initial_iterations, self.warm_starting)
        self.freeze = freeze
        self.policy, self.policy_parameters = resolve(freeze, policy_parameters)
        check_policy_gravity(freeze, self._gravity)

        packed = pack(scene)
        self.n_bodies = packed.n_dynamic
        # read-only: the energies are computed from them (a -1 written into masses made
        # kinetic_energy() negative)
        self.masses = _read_only(packed.mass)  # (N,) kg
        self.inertias = _read_only(packed.inertia)  # (N,) kg m^2 about the COM
        # read-only copies: the solver's own, handed out, let a write change the run
        self.extents = _read_only(packed.extent.copy())  # (M,) m, COM to farthest vertex
        self.sizes = _read_only(packed.size.copy())  # (M,) m, thinnest width
        check_mass_properties(packed, self._describe)
        check_range(packed, self._describe)
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
        n_contacts = int(self._counters[D.N_ACTIVE])
        cap = presolve.sweep_cap(self.initial_iterations, initial_iterations is None, n_contacts)
        while cap and K.presolve(cap, presolve.TOLERANCE, *self._state()) == K.GROW:
            self._grow()
        c = self._counters
        presolve.warn_if_cut(
            self.initial_iterations, cap, c[D.PRESOLVE_SWEEPS], c[D.PRESOLVE_CONVERGED], n_contacts
        )

    # ---- set-up -----------------------------------------------------------------------------
    def _build(self, scene, p):
        n = p.n_dynamic
        m = len(p.angle)
        self._bodies = new_bodies(p, self.slop, self.speculative_distance)
        self._geometry = new_geometry(p)
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
            impact_iterations=self.impact_iterations,
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
            fast_quiet="quiet" in self.fast_paths,
            continuous=self.continuous,
            cell_size=cell_size,
            n_dynamic=n,
            policy=POLICY_NAMES.index(self.freeze),
            impulse_threshold=float(params.get("impulse_threshold", 0.0)),
            impact_speed=float(params.get("impact_speed", 0.0)),
            sleep_speed=float(params.get("sleep_speed", 0.0)),
            sleep_time=float(params.get("sleep_time", 0.0)),
            rest_speed=float(params.get("rest_speed", 0.0)),
            rest_acceleration=float(params.get("rest_acceleration", 0.0)),
            rest_steps=int(params.get("rest_steps", 1)),
            slip_speed=float(params.get("slip_speed", 0.0)),
            opening_speed=float(params.get("opening_speed", 0.0)),
            closing_speed=float(params.get("closing_speed", 0.0)),
            friction_margin=float(params.get("friction_margin", 0.0)),
            tip_margin=float(params.get("tip_margin", 0.0)),
            mixed_masses=mixed_masses(p.inv_mass[:n]),
            profile=False,
        )
        self._counters = np.zeros(D.N_COUNTERS, np.int64)
        self._counters[D.N_AWAKE] = n  # every body starts awake
        self._counters[D.FREE_HEAD] = -1
        self._counters[D.RESTING_DIRTY] = 1
        self._activity = initial_activity(
            n, m, p.inv_mass, p.inv_inertia, self.policy, p.velocity, p.angular_velocity
        )
        k = INITIAL_CAPACITY
        small = k < 4  # tests: no minimum either
        self._awake_grid = grid_buffers(
            k * n + (0 if small else 64), k if small else max(4 * k * n, 4096)
        )
        self._resting_grid = grid_buffers(
            k * m + (0 if small else 64), k if small else max(4 * k * m, 4096)
        )
        self._scratch = np.zeros(m, np.int64)
        self._contacts = new_contacts(k if small else max(64, k * m), n)
        self._solver = new_solver(n, len(self._contacts.awake), 1 if small else 4)
        self._regrown = 0
        # the step loop, called without Numba's type dispatch while the state is the same objects
        self._run_kernel = Compiled(K.run)

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
        self._contacts, self._solver, self._awake_grid, self._resting_grid = grown(
            need,
            self._counters,
            self.n_bodies,
            self._contacts,
            self._solver,
            self._awake_grid,
            self._resting_grid,
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
        deepest = deepest_point(self._contacts, self._counters)
        check_initial_overlap(deepest, self._describe, self.overlap_tolerance)

    def __reduce_ex__(self, protocol):
        # copy.copy shared the World's arrays (stepping the copy moved the original) and
        # pickle/deepcopy failed on a module inside it ("cannot pickle 'module' object")
        raise TypeError(
            "a sim.World cannot be copied or pickled: build another from world.scene (the scene it "
            "was built from), or from its state (positions, angles, velocities, "
            "angular_velocities) put into a new sim.Scene"
        )

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
        with Deferred() as sigint:
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
                status, steps = self._run_kernel(chunk, *self._state(settings), min_sep)
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
                if sigint.came:
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

    #: what ``why_awake`` can say of an awake body, in the order of the rest test's stages
    AWAKE_REASONS = WAIT_NAMES[1:2] + ("untouched",) + WAIT_NAMES[2:]

    def why_awake(self):
        """(N,) str: why each body is awake after the last step, the first stage of ``extended``'s
        rest test that refused it ('' for a frozen body): "moving" (|v| + |w| extent at or above
        rest_speed), "untouched" (slower, but with no contact, no pair whose fat boxes overlap:
        nothing near it can hold it, and the rest test does not look at it), "changing" (slow, but
        its velocity changed by more than rest_acceleration dt, or it was not tested in the step
        before), "counting" (slow and steady for fewer than rest_steps steps), "sliding" (a contact
        at its friction limit while its surfaces slip), "closing" (a point apart, within slop, whose
        gap is still closing), "deep" (a contact deeper than twice its slop, still being pushed
        open), "neighbour" (it touches an awake body in motion), "uncertified" (no contact forces
        hold it still with margin, alone or with the bodies it touches), "on_awake" (certified, but
        resting on, or braced by, an awake body that does not freeze with it); "untested" before the
        first step. What a pile is still waiting for, which its velocities do not say. Only
        ``extended`` has a rest test of stages: any other policy raises ValueError."""
        if self.freeze != "extended":
            raise ValueError(
                f"why_awake: only freeze='extended' records why a body is awake (its rest test "
                f"has stages); this World has freeze={self.freeze!r}"
            )
        codes = self._activity.body_int[: self.n_bodies, WAITING]
        names = np.array(WAIT_NAMES, dtype="U16")[codes]  # wide enough for "untested"
        frozen = self.frozen
        names[(codes == WAIT_NONE) & ~frozen] = "untested"
        if self.step_count > 0:
            # the rest test looks only at bodies with a contact: one without keeps the
            # reason of its last test, and is moving or touches nothing
            tested = self._activity.body_int[: self.n_bodies, TESTED] == self.step_count
            extent = self.extents[: self.n_bodies]
            speed = np.hypot(*self.velocities.T) + np.abs(self.angular_velocities) * extent
            alone = ~frozen & ~tested
            fast = speed >= self._settings.rest_speed
            names[alone & fast] = "moving"
            names[alone & ~fast] = "untouched"
        names[frozen] = ""
        return names

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
        # numpy's sums, not BLAS dots: the same bits on every CPU (geometry.mass_properties)
        v2 = v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1]
        return 0.5 * float((self.masses * v2).sum() + (self.inertias * (w * w)).sum())

    def potential_energy(self):
        """Gravitational potential energy relative to the origin, J."""
        p = self._bodies.position[: self.n_bodies]
        g = self._gravity
        return -float((self.masses * (p[:, 0] * g[0] + p[:, 1] * g[1])).sum())

    def vertices(self, i):
        """World vertices (K,2) of dynamic body ``i`` (0 <= i < n_bodies) at the current pose, m:
        the polygon the solver uses, which is the body's own less any collinear vertex
        (``polygons.drop_collinear``)."""
        n = self.n_bodies
        why = f"its dynamic bodies are 0 to {n - 1}" if n else "the World has no dynamic body"
        i = count(i, "body index", 0, n - 1, why)
        b = self._bodies
        local = b.local_verts[b.vert_start[i] : b.vert_start[i + 1]]
        return geometry.place(local, b.position[i], b.angle[i])

    def _points(self):
        """Every point of this step's active contacts (see ``contacts``)."""
        return contact_points(self._contacts, self._counters, self._bodies.position)

    def contacts(self):
        """The contact points of the last step: dict of arrays over points — body_a, body_b (-1 =
        floor) (P,) int; point (P,2) m (found on B's surface at the start of the step and carried
        with B's centre to where it ended the step, so that it is drawn on B as B is reported; B's
        turn over the step is not applied); normal (P,2) A->B; separation (P,) m at the start of the
        step, end_separation (P,) m at its end; slop (P,) m, the pair's contact tolerance (points
        within it touch, ``sim.tolerances``); normal_impulse, tangent_impulse (P,) N s applied over
        the whole step."""
        return self._points()

    def inspect(self):
        """A read-only snapshot of the solver's bookkeeping (copies), for tests, benchmarks and
        recordings: see ``Inspection``."""
        return Inspection(
            self._points(),
            self._counters,
            self._activity,
            self._solver,
            self._contacts,
            self.n_bodies,
            self._regrown,
        )

    def __repr__(self):
        return (
            f"World(scene={self.scene.name!r}, bodies={self.n_bodies}, dt={self.dt}, "
            f"substeps={self.substeps}, iterations={self.iterations}, "
            f"freeze={self.freeze!r}, step={self.step_count})"
        )


def _read_only(array):
    """``array`` marked read-only (numpy then refuses writes into it), returned."""
    array.setflags(write=False)
    return array
