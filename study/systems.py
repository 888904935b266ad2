"""The registry of the study's systems: one record per system, the single place to add one.

A system is an engine (sim, or a peer behind study.peers) and how it rests bodies: sim's freeze
policies (off, sleep, paper, extended) or a peer's sleeping (on or off). Everything else is read
from here: the names experiments loop over (``SYSTEMS``), each system's reference (the same engine
with nothing frozen), which systems freeze (``FREEZING``), the peers, and how figures draw a system
(``style``). Adding a peer is its runner (study/peers/, registered in ``make_runner``), its
comparable settings (``study.common.SYSTEM_SETTINGS``) and two entries here: ``<engine>`` and
``<engine>-sleep``. Every experiment that compares systems then runs it.
"""

from dataclasses import dataclass


@dataclass(frozen=True)
class System:
    """One system of the study."""

    name: str  # "sim-extended", "pymunk-sleep": what runners, tables and figures call it
    engine: str  # "sim", "pymunk", "pybullet", "box2d"
    rests: str  # how it rests bodies: sim's freeze policy, or "sleep" / "off" for a peer
    color: str  # the figures' colour (Okabe-Ito palette, colour-blind safe), one per engine
    marker: str  # matplotlib marker
    linestyle: str  # peers: dotted without sleeping, dashed with it

    @property
    def freezes(self):
        """Does the system stop solving bodies at rest (its outcome may differ from the
        reference's because of it)?"""
        return self.rests != "off"

    @property
    def reference(self):
        """The same engine with nothing frozen: what freezing is compared against."""
        return "sim-off" if self.engine == "sim" else self.engine


def _peer(engine, color, marker):
    return (
        System(engine, engine, "off", color, marker, ":"),
        System(f"{engine}-sleep", engine, "sleep", color, marker, "--"),
    )


#: every system, sim's policies first, then each peer without and with sleeping
REGISTRY = (
    System("sim-off", "sim", "off", "#000000", "o", "-"),
    System("sim-sleep", "sim", "sleep", "#56B4E9", "s", "-"),
    System("sim-paper", "sim", "paper", "#E69F00", "^", "-"),
    System("sim-extended", "sim", "extended", "#009E73", "D", "-"),
    *_peer("pymunk", "#CC79A7", "v"),
    *_peer("pybullet", "#D55E00", "P"),
    *_peer("box2d", "#0072B2", "X"),
)
#: systems only the benchmarks run (experiments/bench_step): timed against sim, but outside the
#: study's comparisons (no figure or table of outcomes loops over them). Box2D v3 is the solver
#: sim's soft step follows; its runner is study/peers/box2d3_runner.py.
BENCH_ONLY = (System("box2d3", "box2d3", "off", "#0072B2", "*", "-."),)
BY_NAME = {s.name: s for s in (*REGISTRY, *BENCH_ONLY)}
#: every system name of the study's comparisons, in the registry's order
SYSTEMS = tuple(s.name for s in REGISTRY)
#: the engines, sim first
ENGINES = tuple(dict.fromkeys(s.engine for s in REGISTRY))
#: the benchmarks' systems beyond the study's (BENCH_ONLY)
BENCH_SYSTEMS = tuple(s.name for s in BENCH_ONLY)
#: the peers' engines
PEERS = tuple(e for e in ENGINES if e != "sim")
#: system -> its reference (the same engine, nothing frozen)
REFERENCE = {s.name: s.reference for s in REGISTRY}
#: engine -> its system with nothing frozen
OFF = {s.engine: s.name for s in REGISTRY if not s.freezes}
#: the systems that freeze (sim's policies but off, each peer's sleeping)
FREEZING = tuple(s.name for s in REGISTRY if s.freezes)
#: each peer's sleeping system
SLEEPING_PEERS = tuple(s.name for s in REGISTRY if s.engine != "sim" and s.freezes)


def get(name):
    """The System called ``name``; a clear error for an unknown one."""
    try:
        return BY_NAME[name]
    except KeyError:
        raise ValueError(
            f"unknown system {name!r}; choose one of {', '.join((*SYSTEMS, *BENCH_SYSTEMS))}"
        ) from None


def engine_of(name):
    """ "sim", "pymunk", "pybullet", "box2d" (or "box2d3", benchmarks only) for a system name;
    ValueError for an unknown one."""
    return get(name).engine


# ---- variants: a sim system run without an advantage only sim has ---------------------------
#: sim's presolve (``World(initial_iterations=...)``) solves the start pose's contact impulses to
#: convergence before step 1, so a scene placed at rest starts in equilibrium; no peer has one.
#: Where that start matters (scenes placed at rest), the sim systems run again without it, named
#: "sim-off (no presolve)" etc., and are reported beside the others, never instead of them.
NO_PRESOLVE = " (no presolve)"
NO_PRESOLVE_SETTINGS = {"initial_iterations": 0}
NO_PRESOLVE_SYSTEMS = tuple(s.name + NO_PRESOLVE for s in REGISTRY if s.engine == "sim")


def no_presolve(name):
    """The no-presolve variant of the sim system ``name`` ("sim-extended" -> "sim-extended (no
    presolve)"); ValueError for a peer's (a peer has no presolve to leave out)."""
    if engine_of(name) != "sim":
        raise ValueError(f"{name} has no presolve: only sim's systems have a no-presolve variant")
    return name + NO_PRESOLVE


def runner_system(system):
    """The runner's system name of a system or a variant ("sim-off (no presolve)" -> "sim-off")."""
    return system[: -len(NO_PRESOLVE)] if system.endswith(NO_PRESOLVE) else system


def system_settings(system):
    """The runner settings that make ``system`` (a system or a variant) what it is, beyond its
    runner's name."""
    return dict(NO_PRESOLVE_SETTINGS) if system.endswith(NO_PRESOLVE) else {}


def style(name):
    """Matplotlib style of a system: color, marker, linestyle (grey dots for a name not in the
    registry, e.g. a derived row)."""
    s = BY_NAME.get(name)
    if s is None:
        return {"color": "#777777", "marker": ".", "linestyle": "-"}
    return {"color": s.color, "marker": s.marker, "linestyle": s.linestyle}
