"""What every peer runner checks around its engine, so that each refuses, or reports, what
sim.World does and in the same words: a step count that is not a count, a body whose mass the
engine cannot simulate, a state gone non-finite, a runner used after ``close()``.

Why here and not in each runner. A reviewer (2026-12-07) found the runners disagreeing on each:
pymunk stepped -1 steps (its clock went backwards) and took True for one step, Box2D's
``step_count`` became a float; Box2D and pybullet returned NaN poses without a word, and pybullet
let a 1e12 kg box fall through the floor; Box2D silently set a 1e-50 kg body to 1 kg; after
``close()`` Box2D handed out empty (0,) arrays.

The mass ranges were measured on this machine (``tests/adapters/test_guards.py``): a 1 m box
resting on the floor under a second body, 120 steps, at sizes 0.1, 1 and 10 m, against the same
scene at density 1000 (within 1% of the size):
  - Box2D 2.3 (float32) holds masses from 1e-18 to 1e19 kg; at 1e-19 kg, and from 1e20 kg (its
    square leaves float32's range), the bodies end far off or NaN; from 3.4e38 pybox2d refuses
    the number (OverflowError), and below 1.2e-38 it becomes 0, which Box2D replaces by 1 kg;
  - pybullet holds up to 1e11 kg; a 1e12 kg box sinks through the floor (3.5 m in 1 s);
  - pymunk held every mass from 1e-200 to 1e200 kg.
Every runner also keeps sim's own range (``sim.validation.MASS_RANGE``, mass and moment of
inertia): a scene sim refuses is refused by every system, and no comparison holds a body that
only some systems can run.
"""

import functools

import numpy as np

from sim import SimulationError
from sim.arguments import count
from sim.validation import MASS_RANGE

from .pose import body_label

#: kg: what Box2D 2.3's float32 solver holds (module docstring)
BOX2D_MASS = (1e-18, 1e19)
#: kg m^2: float32's normal numbers, with room (a moment outside them is rounded or refused)
BOX2D_INERTIA = (1e-37, 1e37)
#: kg: what pybullet holds (module docstring)
PYBULLET_MASS = (MASS_RANGE[0], 1e11)


def steps(n):
    """``n`` of a runner's ``step(n)`` as an int: sim.World.step's rule (an integer >= 0; True,
    -1 and 2.0 are refused with a ValueError)."""
    return int(count(n, "n", 0))


def check_mass(engine, scene, i, mass, inertia, mass_range=None, inertia_range=None):
    """ValueError, naming ``engine`` and scene body i, if its mass (kg) or moment of inertia
    about its centre of mass (kg m^2) is outside sim's range or the engine's narrower one (None:
    sim's alone)."""
    mass_range = MASS_RANGE if mass_range is None else mass_range
    inertia_range = MASS_RANGE if inertia_range is None else inertia_range
    lo_m, hi_m = max(mass_range[0], MASS_RANGE[0]), min(mass_range[1], MASS_RANGE[1])
    lo_i, hi_i = max(inertia_range[0], MASS_RANGE[0]), min(inertia_range[1], MASS_RANGE[1])
    if lo_m <= mass <= hi_m and lo_i <= inertia <= hi_i:
        return
    raise ValueError(
        f"{engine}: {body_label('body', i, scene.body_name(i))} has mass {mass:.4g} kg and "
        f"moment of inertia {inertia:.4g} kg m^2; {engine} runs masses in [{lo_m:g}, {hi_m:g}] "
        f"kg and moments in [{lo_i:g}, {hi_i:g}] kg m^2 faithfully (study.peers.guards says "
        f"what was measured)"
    )


def check_finite(engine, scene, step_count, **observables):
    """SimulationError, as sim.World raises, naming the first body with a NaN or infinite value
    in any of ``observables`` (name: (N,) or (N,2) array) after step ``step_count``."""
    for name, values in observables.items():
        values = np.asarray(values)
        bad = ~np.isfinite(values).all(axis=tuple(range(1, values.ndim)))  # per row
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise SimulationError(
                f"{engine}: {body_label('body', i, scene.body_name(i))} is non-finite after "
                f"step {step_count} ({name} {values[i].tolist()}): the run cannot go on"
            )


def finite(engine, scene, step_count, name, values):
    """``values``, an observable a runner is about to hand out, if every entry is finite; else
    ``check_finite``'s SimulationError. Where a peer's state is checked: as it is read, so that
    a NaN never leaves the runner, and a step reads nothing more than the engine's own. Checked
    after every step instead (the whole state read back), the full run took 29 min against 23:
    fig_speedup's frozen scenes, stepped once per call, paid 11 ms for 10^4 pymunk bodies' poses
    after a 0.03 ms step."""
    check_finite(engine, scene, step_count, **{name: values})
    return values


def finite_contacts(engine, scene, step_count, contacts):
    """``contacts`` (a runner's ``contacts()`` dict) if every point, normal and impulse is
    finite; else a SimulationError naming the first contact and its pair. (Checked on the
    observables only, Box2D's ``contacts()`` still handed out NaN points and normals after its
    state had gone non-finite.)"""
    for name in ("point", "normal", "normal_impulse", "tangent_impulse"):
        if name not in contacts:
            continue
        values = np.asarray(contacts[name])
        bad = ~np.isfinite(values).all(axis=tuple(range(1, values.ndim)))  # per row
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            pair = (int(contacts["body_a"][k]), int(contacts["body_b"][k]))
            raise SimulationError(
                f"{engine}: contact point {k} (bodies {pair[0]} and {pair[1]}) is non-finite "
                f"after step {step_count} ({name} {values[k].tolist()}): the run cannot go on"
            )
    return contacts


def checked_contacts(engine):
    """Decorator of a runner's ``contacts()``: its result through ``finite_contacts``."""

    def wrap(method):
        @functools.wraps(method)
        def contacts(self):
            return finite_contacts(engine, self.scene, self.step_count, method(self))

        return contacts

    return wrap
