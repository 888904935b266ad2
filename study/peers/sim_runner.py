"""``sim.World`` behind the peers' interface (``study.peers.Runner``), one freeze policy per
runner, so that experiments loop over systems without special cases.

The runner adds nothing to the physics: it passes dt, iterations, the freeze policy and every
other ``sim.World`` setting (substeps, slop, restitution_threshold, the policy's own parameters...)
through, and reads the World's observables. Settings not given are sim.World's own defaults
(``DEFAULT_ITERATIONS``, ``DEFAULT_SUBSTEPS``: read from its signature, so the runner can never
drift from the solver). ``settings`` records every one of them as the World holds it (after
validation), so a results file says which solver configuration produced it.

``asleep`` is ``world.frozen``: the body is out of the awake list, so nothing is computed for it
(SLEEPING under ``sleep``, frozen ROTATION_STABLE under ``extended`` and ``paper``, held
VERTICAL_STABLE under ``paper``). A ``paper`` body that is VERTICAL_STABLE and pivoting, or
ROTATION_STABLE and still sliding, is awake: ``states`` says which.
"""

import inspect

import sim
from sim.soft_step import DYNAMIC_CAP

from .lifetime import ClosesOnExit
from .bullets import bullets

_DEFAULTS = inspect.signature(sim.World).parameters
#: sim.World's default biased solve sweeps per substep (Box2D v3's: 1).
DEFAULT_ITERATIONS = _DEFAULTS["iterations"].default
#: sim.World's default substeps per step (4).
DEFAULT_SUBSTEPS = _DEFAULTS["substeps"].default

#: sim.World's settings recorded in ``settings`` (besides dt, iterations, freeze), as the World
#: holds them: the soft step's knobs (substeps, relax and impact sweeps, contact stiffness and
#: damping, push speed, load time), the contact tolerances, and the switches.
_WORLD_SETTINGS = (
    "substeps",
    "relax_iterations",
    "impact_iterations",
    "contact_hertz",
    "damping_ratio",
    "push_speed",
    "load_time",
    "slop",
    "speculative_distance",
    "restitution_threshold",
    "warm_starting",
    "continuous",
    "overlap_tolerance",
    "initial_iterations",
    "fast_paths",
)


class SimRunner(ClosesOnExit):
    """Run ``scene`` in ``sim.World(scene, dt, iterations, freeze, **world_settings)``;
    ``iterations=None`` is the World's default."""

    def __init__(self, scene, dt=1 / 60, iterations=None, freeze="off", **world_settings):
        if iterations is None:
            iterations = DEFAULT_ITERATIONS
        self.world = sim.World(scene, dt=dt, iterations=iterations, freeze=freeze, **world_settings)
        self.scene = self.world.scene
        self.freeze = freeze
        w = self.world
        self.settings = {
            "engine": "sim",
            "system": self.name,
            "dt": w.dt,
            "iterations": w.iterations,
            "freeze": w.freeze,
            "policy_parameters": dict(w.policy_parameters),
            "solver": "soft step (Box2D v3): iterations are biased sweeps per substep",
            **{k: getattr(w, k) for k in _WORLD_SETTINGS},
            # Hz before the per-pair rules (raised for small bodies, doubled
            # against immovable ones, capped: sim.soft_step.pair_hertz); None
            # above means the cap, DYNAMIC_CAP of the substep rate
            "contact_hertz_base": (
                w.contact_hertz if w.contact_hertz is not None else DYNAMIC_CAP * w.substeps / w.dt
            ),
            "bullets": bullets(
                self.scene,
                w.continuous,
                "swept against every body"
                if w.continuous
                else "ordinary bodies: continuous collision is off",
            ),
        }

    @property
    def name(self):
        return f"sim-{self.freeze}"

    @property
    def dt(self):
        return self.world.dt

    def step(self, n=1):
        """Advance ``n`` steps of ``dt``."""
        self.ensure_open()
        self.world.step(n)
        return self

    @property
    def step_count(self):
        return self.world.step_count

    @property
    def time(self):
        """Simulated time, s."""
        return self.world.time

    @property
    def positions(self):
        """(N,2) m, centres of mass."""
        self.ensure_open()
        return self.world.positions

    @property
    def angles(self):
        """(N,) rad, CCW."""
        self.ensure_open()
        return self.world.angles

    @property
    def velocities(self):
        """(N,2) m/s."""
        self.ensure_open()
        return self.world.velocities

    @property
    def angular_velocities(self):
        """(N,) rad/s."""
        self.ensure_open()
        return self.world.angular_velocities

    @property
    def asleep(self):
        """(N,) bool: the body is frozen (out of sim's awake list: no work is done for it)."""
        self.ensure_open()
        return self.world.frozen

    def contacts(self):
        """The contact points of the last step: {"body_a", "body_b": (K,) int (scene body i,
        static body j as N + j, the floor -1), "point": (K,2) m, "normal": (K,2) unit, A to B,
        "normal_impulse": (K,) N s pushing B along the normal over the whole step}
        (World.contacts)."""
        self.ensure_open()
        c = self.world.contacts()
        keys = ("body_a", "body_b", "point", "normal", "normal_impulse")
        return {k: c[k] for k in keys}

    def close(self):
        """Nothing to release; here so every runner can be closed alike."""
        self.closed = True

    def __repr__(self):
        return f"SimRunner({self.world!r})"
