"""What a ``sim.World`` refuses, and why: settings of the old solver, counts beyond what a step
can afford, unknown fast paths, mass properties the solver cannot use, and scenes that start
interpenetrated.

Split from ``world.py`` by job: the World's constructor reads as what it builds, and the rules
for what it accepts (each with the measurement behind it) are read here, in one place. The checks
that the peer runners share (a count, a switch, a number) are ``sim.arguments``.
"""

import difflib
import inspect

import numpy as np

from . import soft_step
from .arguments import count
from .body import MAX_COORDINATE
from .freeze import POLICY_NAMES, parameters_of, renamed_in

#: Settings of the solver before soft step, refused with the reason.
REMOVED = {
    "position_iterations": "the soft-step solver has no position-correction sweeps (the soft "
    "contact pushes bodies apart within the velocity solve); use substeps",
    "baumgarte": "the soft-step solver has no Baumgarte factor; contact stiffness is "
    "contact_hertz and damping_ratio",
    "max_correction": "the soft-step solver has no position correction; the push-out speed is "
    "push_speed (m/s)",
}

#: Caps on the solver's counts. A step is compiled code that Ctrl-C cannot stop (it is seen only
#: between steps): iterations=10**9 made one step of one box take over a minute. Far beyond any
#: accuracy the sweeps buy (fig_tradeoff: the error stops falling long before), and each step
#: still a fraction of a second on a small scene.
MAX_SUBSTEPS = 1000
MAX_SWEEPS = 1000  # iterations, and relax_iterations, per substep
MAX_INITIAL_ITERATIONS = 10**6


def limits_why(cap):
    """Why a count above ``cap`` (the name of one of the caps above) is refused."""
    return (
        "a step cannot be interrupted, and more than this buys no accuracy "
        f"(see sim.validation.{cap})"
    )


#: the initial solve's sweeps when the World is not told (and warm starts)
INITIAL_ITERATIONS = 5000


def initial_sweeps(initial_iterations, warm_starting):
    """The initial solve's sweep count: ``INITIAL_ITERATIONS`` by default with warm starting, 0
    without. Its impulses reach step 1 only as a warm start, so a count asked for with
    warm_starting=False is refused (it was once silently ignored)."""
    if initial_iterations is None:
        return INITIAL_ITERATIONS if warm_starting else 0
    sweeps = count(
        initial_iterations,
        "initial_iterations",
        0,
        MAX_INITIAL_ITERATIONS,
        "the initial solve runs before the first step, in one call that cannot be interrupted "
        "(see sim.validation.MAX_INITIAL_ITERATIONS)",
    )
    if sweeps and not warm_starting:
        raise ValueError(
            f"initial_iterations={sweeps} needs warm_starting=True: the initial solve's impulses "
            f"reach the first step only as its warm start, so without it they would be dropped "
            f"(pass initial_iterations=0, or leave it out)"
        )
    return sweeps


#: the solver's fast paths (see World's ``fast_paths``)
FAST_PATHS = ("friction", "quiet")


def fast_path_names(value):
    """The fast paths switched on, as a sorted tuple of names; ValueError for unknown names. A
    switch is True or False, numpy's too (np.True_ was refused as not a switch, while every other
    switch of the World takes it)."""
    if value is None:
        return ()
    if isinstance(value, (bool, np.bool_)):
        return tuple(sorted(FAST_PATHS)) if value else ()
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


def check_mass_properties(packed, describe):
    """ValueError naming the first dynamic body whose mass properties the solver cannot use:
    finite fields can still overflow them (vertices at 1e155 m square to inf: mass inf, inertia
    NaN), underflow them (density 1e-320 kg/m^2: a mass whose inverse is inf), or leave
    ``MASS_RANGE``. ``describe(i)`` names body i in the message."""
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


def check_range(packed, describe):
    """ValueError naming the first body whose centre of mass lies beyond MAX_COORDINATE (m) of
    the origin, where the solver stops a body as diverged. The body's position (its frame's
    origin) and its vertices are each checked on the Body, but the centre of mass is their sum:
    a box 9e11 m from its own origin, placed at 9e11 m, built a World and then "diverged" in its
    first step, at rest. ``describe(i)`` names body i."""
    far = ~(np.abs(packed.position) <= MAX_COORDINATE).all(axis=1)
    if far.any():
        i = int(np.flatnonzero(far)[0])
        x, y = packed.position[i]
        raise ValueError(
            f"{describe(i)}: its centre of mass ({x:.4g}, {y:.4g}) m is beyond {MAX_COORDINATE:g} "
            f"m of the origin, where the solver stops as diverged (its vertices lie far from its "
            f"position); place the polygon about its position"
        )


def mixed_masses(inv_mass):
    """Can any contact be "hard" (soft_step.HARD_RATIO)? Only if two dynamic bodies' masses
    differ by more than the ratio: a freeze policy only ever zeroes solver masses (immovable
    bodies are never hard), so this holds for the World's life and the colouring skips the
    search for hard contacts in uniform scenes."""
    movable = inv_mass[inv_mass > 0.0]
    return bool(movable.size and movable.max() > soft_step.HARD_RATIO * movable.min())


def check_initial_overlap(deepest, describe, overlap_tolerance):
    """Refuse scenes whose bodies start interpenetrated beyond ``overlap_tolerance`` (m): the
    contacts would launch them apart and the run would measure nothing real. ``deepest`` is the
    start poses' deepest contact point, (separation, body_a, body_b) or None
    (``reports.deepest_point``); ``describe(i)`` names body i."""
    if deepest is None:
        return
    separation, a, b = deepest
    depth = -separation
    if depth > overlap_tolerance:
        what_b = describe(b)
        what = (
            f"{what_b} starts {depth:.4g} m below the floor"
            if a < 0
            else f"{describe(a)} and {what_b} start overlapping by {depth:.4g} m"
        )
        raise ValueError(f"{what} (overlap_tolerance is {overlap_tolerance} m)")


def check_policy_arguments(freeze, policy_parameters, init):
    """ValueError for a keyword that is neither a World setting nor a parameter of the freeze
    policy, saying both (a misspelt setting, ``iteratons=3``, read as the policy's fault); the
    World's settings are the keywords of ``init`` (``World.__init__``)."""
    if not isinstance(freeze, str) or freeze not in POLICY_NAMES:
        return  # resolve names the unknown policy
    takes = parameters_of(freeze)
    unknown = sorted(set(policy_parameters) - set(takes))
    for name in unknown:
        if name in renamed_in(freeze):
            raise ValueError(f"freeze={freeze!r} does not take {name}: {renamed_in(freeze)[name]}")
    if unknown:
        settings = [
            p.name
            for p in inspect.signature(init).parameters.values()
            if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY) and p.name != "self"
        ]
        near = difflib.get_close_matches(unknown[0], settings + list(takes), n=1)
        raise ValueError(
            f"World got {', '.join(unknown)}: not a World setting "
            f"({', '.join(s for s in settings if s != 'scene')}) nor a parameter of "
            f"freeze={freeze!r} ({', '.join(takes) or 'it takes none'})"
            + (f"; did you mean {near[0]}?" if near else "")
        )


def check_policy_gravity(freeze, gravity):
    """ValueError if the policy cannot run under ``gravity`` (m/s^2, (2,)): ``paper`` needs it
    straight down. The seed's states are defined against it: a floor-like surface is one whose
    normal is within 1 degree of +y, and VERTICAL_STABLE holds a vertex's vertical motion. Under any
    other gravity they freeze what it moves (a box on the floor under gravity (0, 9.81) was held
    down, frozen, where ``off`` sends it to y = 5.4 in 1 s)."""
    gx, gy = float(gravity[0]), float(gravity[1])
    if freeze == "paper" and not (gx == 0.0 and gy < 0.0):
        raise ValueError(
            f"freeze='paper' needs gravity straight down (0, -g), g > 0: the seed's floor test and "
            f"vertical holds assume it; got gravity ({gx:g}, {gy:g}). Use freeze='extended' (any "
            f"gravity) or 'sleep'"
        )
