"""``sim.World`` behind the peers' interface (``experiments.peers.Runner``), one freeze policy per
runner, so that experiments loop over systems without special cases.

The runner adds nothing to the physics: it passes dt, iterations, the freeze policy and every
other ``sim.World`` setting (slop, restitution_threshold, the policy's own parameters...) through,
and reads the World's observables. ``asleep`` is ``world.frozen``: the body is out of the awake
list, so nothing is computed for it (SLEEPING under ``sleep``, frozen ROTATION_STABLE under
``extended`` and ``paper``, held VERTICAL_STABLE under ``paper``). A ``paper`` body that is
VERTICAL_STABLE and pivoting, or ROTATION_STABLE and still sliding, is awake: ``states`` says
which.
"""
import sim

#: sim.World's keyword settings recorded in ``settings`` (besides dt, iterations, freeze).
_WORLD_SETTINGS = ("position_iterations", "slop", "speculative_distance", "baumgarte",
                   "max_correction", "restitution_threshold", "warm_starting",
                   "overlap_tolerance", "initial_iterations")


class SimRunner:
    """Run ``scene`` in ``sim.World(scene, dt, iterations, freeze, **world_settings)``."""

    def __init__(self, scene, dt=1 / 60, iterations=10, freeze="off", **world_settings):
        self.world = sim.World(scene, dt=dt, iterations=iterations, freeze=freeze,
                               **world_settings)
        self.scene = self.world.scene
        self.freeze = freeze
        w = self.world
        self.settings = {"engine": "sim", "system": self.name, "dt": w.dt,
                         "iterations": w.iterations, "freeze": w.freeze,
                         "policy_parameters": dict(w.policy_parameters),
                         **{k: getattr(w, k) for k in _WORLD_SETTINGS if hasattr(w, k)}}

    @property
    def name(self):
        return f"sim-{self.freeze}"

    @property
    def dt(self):
        return self.world.dt

    def step(self, n=1):
        """Advance ``n`` steps of ``dt``."""
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
        return self.world.positions

    @property
    def angles(self):
        """(N,) rad, CCW."""
        return self.world.angles

    @property
    def velocities(self):
        """(N,2) m/s."""
        return self.world.velocities

    @property
    def angular_velocities(self):
        """(N,) rad/s."""
        return self.world.angular_velocities

    @property
    def asleep(self):
        """(N,) bool: the body is frozen (out of sim's awake list: no work is done for it)."""
        return self.world.frozen

    def close(self):
        """Nothing to release; here so every runner can be closed alike."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        return f"SimRunner({self.world!r})"
