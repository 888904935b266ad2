"""Every system the study compares, behind one small interface: ``Runner``.

A system is named by a string (``SYSTEMS``); ``make_runner(system, scene, ...)`` builds it:

    sim-off, sim-sleep, sim-paper, sim-extended   sim.World under that freeze policy (SimRunner)
    pymunk, pymunk-sleep                         Chipmunk2D, sleeping off / on (PymunkRunner)
    pybullet, pybullet-sleep                     Bullet, 2D by planar joints (PybulletRunner)
    box2d, box2d-sleep                           Box2D 2.3 (float32), sleeping off / on
                                                 (Box2dRunner)
    box2d3                                       Box2D v3 (float32), sleeping off; benchmarks
                                                 only, outside the study's comparisons
                                                 (Box2d3Runner, study.systems.BENCH_ONLY)

Every runner has ``step(n=1)`` and the observables ``positions`` (N,2) m (centres of mass, row i =
scene body i), ``angles`` (N,) rad CCW, ``velocities`` (N,2) m/s, ``angular_velocities`` (N,)
rad/s, ``asleep`` (N,) bool (the system does not solve the body this step), plus ``name`` (the
system string), ``scene``, ``dt`` s, ``step_count``, ``time`` s, ``settings`` (a JSON-ready dict
of everything that matters: dt, iterations, sleeping and its thresholds, mixing rules...; what
experiments store in their metadata) and ``close()`` (runners are also context managers).
Every runner's ``contacts()`` gives the last step's contact points in one convention: ``body_a``,
``body_b`` (scene body i, static body j as N + j, the floor -1), ``point``, ``normal`` (unit, A to
B) and ``normal_impulse`` (N s, the impulse that pushes B along the normal); ``impulse_vectors``
turns them into the impulse each point gives the pair's dynamic body of higher index, which is
what the recordings draw (the engines' own pair orders differ: a box on the floor came out as the
floor's impulse in pymunk, the box's in sim, pybullet and Box2D).
A runner that does work of its own around the engine's steps (Box2dRunner: its motion-cap check;
PybulletRunner with sleeping: the pose before the last step) also has ``engine_seconds``, the wall
time spent inside the engine's step calls, which benchmarks time (study.timing.timed).

Peers never leak into ``sim``: this package imports sim, never the reverse.
"""

import inspect
from typing import Protocol, runtime_checkable

import numpy as np

from study import systems

from .box2d3_runner import ITERATIONS as BOX2D3_ITERATIONS
from .box2d3_runner import Box2d3Runner
from .box2d_runner import DEFAULT_ITERATIONS as BOX2D_DEFAULT_ITERATIONS
from .box2d_runner import Box2dRunner
from .pybullet_runner import DEFAULT_ITERATIONS as PYBULLET_DEFAULT_ITERATIONS
from .pybullet_runner import PybulletRunner
from .pymunk_runner import PymunkRunner
from .sim_runner import DEFAULT_ITERATIONS as SIM_DEFAULT_ITERATIONS
from .sim_runner import DEFAULT_SUBSTEPS as SIM_DEFAULT_SUBSTEPS
from .sim_runner import SimRunner

#: Every system name ``make_runner`` knows, sim's policies first (study.systems' registry).
SYSTEMS = systems.SYSTEMS

#: Solver iterations when ``make_runner`` is given none: each engine's own default, so that every
#: system runs as its authors tuned it and a comparison is fair by construction (same scene, same
#: start state, same observables; each system's full settings are in its runner's ``settings``).
#: The numbers do not mean the same thing in each engine:
#:   sim       sim.World's default: 1 biased solve sweep *per substep*, with 4 substeps per step
#:             (and 1 relax sweep per substep): Box2D v3's soft step (``sim.soft_step``)
#:   pymunk    10 iterations per step (Chipmunk's default)
#:   pybullet  50 iterations per step (Bullet's default is 10, with which a base-20 pyramid creeps
#:             and a base-40 one collapses; see ``pybullet_runner``)
#:   box2d     8 velocity iterations per step (Box2D's testbed default), plus 3 position
#:             iterations (a runner setting, ``position_iterations``)
#:   box2d3    Box2D v3: 1 biased and 1 relax sweep per substep, fixed (4 substeps, a setting)
DEFAULT_ITERATIONS = {
    "sim": SIM_DEFAULT_ITERATIONS,
    "pymunk": 10,
    "pybullet": PYBULLET_DEFAULT_ITERATIONS,
    "box2d": BOX2D_DEFAULT_ITERATIONS,
    "box2d3": BOX2D3_ITERATIONS,
}


@runtime_checkable
class Runner(Protocol):
    """What experiments may rely on, whatever the system."""

    name: str
    settings: dict

    def step(self, n: int = 1) -> "Runner": ...
    def close(self) -> None: ...

    @property
    def dt(self) -> float: ...
    @property
    def step_count(self) -> int: ...
    @property
    def time(self) -> float: ...
    @property
    def positions(self) -> np.ndarray: ...
    @property
    def angles(self) -> np.ndarray: ...
    @property
    def velocities(self) -> np.ndarray: ...
    @property
    def angular_velocities(self) -> np.ndarray: ...
    @property
    def asleep(self) -> np.ndarray: ...


def engine_of(system):
    """ "sim", "pymunk", "pybullet" or "box2d" for a system name; ValueError for an unknown
    one (study.systems.engine_of)."""
    return systems.engine_of(system)


def sim_world(runner):
    """The sim.World behind a SimRunner (its states, events, contacts), else None: a peer (Box2D's
    runner has a ``world`` of its own, a b2World, so the attribute alone does not say)."""
    return runner.world if isinstance(runner, SimRunner) else None


def impulse_vectors(contacts, n_bodies):
    """(K,2) N s: the normal impulse of each point of ``contacts`` (a runner's ``contacts()``)
    as the vector received by the pair's dynamic body of higher index, the floor and static
    bodies (index -1 and >= ``n_bodies``) ranking below every dynamic body: a box resting on the
    floor, or on another box built before it, gets an arrow pointing up, in every engine."""
    a, b = np.asarray(contacts["body_a"]), np.asarray(contacts["body_b"])
    rank_a = np.where((a >= 0) & (a < n_bodies), a, -1)
    rank_b = np.where((b >= 0) & (b < n_bodies), b, -1)
    # the impulse pushes B along the normal and A the other way (Newton's third law)
    sign = np.where(rank_b >= rank_a, 1.0, -1.0)
    return np.asarray(contacts["normal"]) * (sign * np.asarray(contacts["normal_impulse"]))[:, None]


def solver_summary(settings):
    """How much solving a runner's ``settings`` ask for per step, comparable across engines:
    {"substeps": integration substeps per step (sim's setting; 1 for the peers, which step
    once per step), "iterations": as the engine counts them (sim: biased sweeps per substep;
    the peers: per step; Box2D: velocity iterations), "relax_iterations": sim's unbiased sweeps
    per substep (0 for the peers), "contact_sweeps_per_step": passes over the contacts per step
    (sim: substeps x (iterations + relax_iterations); Box2D: iterations + its
    position_iterations; the other peers: iterations)}. Warm starting and restitution passes
    are not counted in any engine."""
    substeps = settings.get("substeps", 1)
    relax = settings.get("relax_iterations", 0)
    position = settings.get("position_iterations", 0)
    return {
        "substeps": substeps,
        "iterations": settings["iterations"],
        "relax_iterations": relax,
        "contact_sweeps_per_step": substeps * (settings["iterations"] + relax) + position,
    }


def make_runner(system, scene, dt=1 / 60, iterations=None, **settings):
    """Build ``scene`` in ``system`` (see ``SYSTEMS``) at step ``dt`` s.

    iterations  solver iterations; None = the engine's default (``DEFAULT_ITERATIONS``). For sim
                these are biased sweeps per substep; its substeps (default 4) are a setting.
    settings    passed to the runner: sim.World's keywords (slop, the policy's parameters...),
                PymunkRunner's (collision_slop, sleep_time, idle_speed), PybulletRunner's
                (sleep_threshold, restitution_threshold), Box2dRunner's
                (position_iterations, warm_starting, continuous) or Box2d3Runner's (substeps).
                Sleeping is chosen by the name; a sleep option given without it is refused (it
                would change nothing).
    """
    engine = engine_of(system)
    if "sleeping" in settings or "freeze" in settings:
        raise ValueError(
            f"choose sleeping or the freeze policy by the system name, not by a "
            f"setting (got {system!r} with {sorted(settings)})"
        )
    iterations = DEFAULT_ITERATIONS[engine] if iterations is None else iterations
    if engine == "sim":  # sim.World names what it does not know
        return SimRunner(
            scene, dt=dt, iterations=iterations, freeze=system[len("sim-") :], **settings
        )
    runner = PEER_RUNNERS[engine]
    _check_settings(system, runner, settings)
    if engine == "box2d3":
        return runner(scene, dt=dt, iterations=iterations, **settings)
    sleeping = system.endswith("-sleep")
    return runner(scene, dt=dt, iterations=iterations, sleeping=sleeping, **settings)


#: each peer engine's runner class
PEER_RUNNERS = {
    "pymunk": PymunkRunner,
    "pybullet": PybulletRunner,
    "box2d": Box2dRunner,
    "box2d3": Box2d3Runner,
}


def _check_settings(system, runner, settings):
    """ValueError naming a setting ``runner`` does not take, and those it does, as sim.World's
    (a misspelt setting raised TypeError from the runner, which callers that take a ValueError
    as "the system refuses this", such as analysis.trace, did not catch)."""
    chosen = {"self", "scene", "dt", "iterations", "sleeping"}  # by make_runner's arguments
    known = [p for p in inspect.signature(runner.__init__).parameters if p not in chosen]
    unknown = sorted(set(settings) - set(known))
    if unknown:
        raise ValueError(
            f"{system}: {', '.join(unknown)}: not a setting of {runner.__name__} (it takes "
            f"{', '.join(known) or 'none'})"
        )


__all__ = [
    "Runner",
    "SYSTEMS",
    "DEFAULT_ITERATIONS",
    "SIM_DEFAULT_SUBSTEPS",
    "make_runner",
    "engine_of",
    "sim_world",
    "impulse_vectors",
    "solver_summary",
    "SimRunner",
    "PymunkRunner",
    "PybulletRunner",
    "Box2dRunner",
    "Box2d3Runner",
]
