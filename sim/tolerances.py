"""Length tolerances that scale with the bodies, and the limit of what a time step can resolve.

The solver's length tolerances were absolute (5 mm slop, 2 cm speculative distance): fine for 1 m
boxes, 50-200 times a 0.1 mm box. Each is now a fraction of the *smaller* body's size (its thinnest
width), with the World's setting as the cap, so a 1 m box sees exactly the old values and a 1 mm box
a thousandth of them:

  contact slop        min(slop, SLOP_FRACTION * size)         touching within this counts as
  touching
  speculative reach   min(speculative_distance, SPECULATIVE_FRACTION * size)
                      + the distance the pair can close in one step (the sum of the bodies'
                      speeds * dt, each turn's reach at most its width: ``narrowphase
                      ._closing_reach``): a contact exists before bodies meet, however fast
                      they approach
  face-choice bias    FACE_FRACTION * contact slop            (reference face kept unless the other
                                                              polygon's face is better by this)
  fat-box margin      min(speculative_distance, MARGIN_FRACTION * size)   a pair persists while the
                                                              boxes grown by this overlap

What no tolerance can fix is a body too small for the step: its contacts must be stiff relative to
gravity at its size, and a contact's stiffness is bounded by the substep rate (``soft_step``).
``check_step`` refuses such a scene, naming the body and the substeps or dt that would resolve it.
"""

import math

import numpy as np

from .jit import inline_kernel

SLOP_FRACTION = 0.005  # of size: 5 mm at 1 m (the cap)
SPECULATIVE_FRACTION = 0.02  # of size: 2 cm at 1 m (the cap)
FACE_FRACTION = 0.02  # of the pair slop: 1e-4 m at 5 mm, today's value
MARGIN_FRACTION = 0.02  # of size: 2 cm at 1 m (the cap)


@inline_kernel
def pair_size(size, a, b):
    """The size that sets a pair's tolerances: the smaller body's (a = -1 is the floor)."""
    if a < 0:
        return size[b]
    return min(size[a], size[b])


def body_slop(size, slop):
    """(M,) m: each body's own contact slop (vectorised; the pair takes the smaller)."""
    return np.minimum(slop, SLOP_FRACTION * np.asarray(size))


def body_speculative(size, speculative_distance):
    """(M,) m: each body's resting speculative reach."""
    return np.minimum(speculative_distance, SPECULATIVE_FRACTION * np.asarray(size))


def body_margin(size, speculative_distance):
    """(M,) m: each body's fat-box margin."""
    return np.minimum(speculative_distance, MARGIN_FRACTION * np.asarray(size))


def check_step(sizes, names, dt, substeps, gravity):
    """Raise ValueError if the smallest dynamic body is too small for the step: its contacts
    must be stiff relative to gravity at its size (omega^2 >= STIFFNESS_RATIO g / size, see
    ``soft_step``) and no stiffer than DYNAMIC_CAP of the substep rate. ``names(i)`` names body
    i; the message says which substeps (or dt) would resolve it."""
    from .soft_step import DYNAMIC_CAP, STIFFNESS_RATIO
    from .validation import MAX_SUBSTEPS

    if len(sizes) == 0 or gravity == 0.0:
        return
    i = int(np.argmin(sizes))
    need = math.sqrt(STIFFNESS_RATIO * gravity / sizes[i]) / (2.0 * math.pi)  # Hz
    rate = substeps / dt  # Hz
    if need > DYNAMIC_CAP * rate:
        substeps_needed = need / DYNAMIC_CAP * dt
        if not math.isfinite(substeps_needed):  # gravity near float64's limit
            fix = f"No step can: gravity {gravity:.3g} m/s^2 is beyond what float64 can resolve"
        elif substeps_needed > MAX_SUBSTEPS:  # an 80-digit count helped no one
            fix = (
                f"No substep count up to {MAX_SUBSTEPS} can (it would take {substeps_needed:.3g}): "
                f"use dt <= {substeps * DYNAMIC_CAP / need:.3g} s, or larger bodies"
            )
        else:
            fix = (
                f"Use substeps >= {math.ceil(substeps_needed)} (or dt <= "
                f"{substeps * DYNAMIC_CAP / need:.3g} s), or larger bodies"
            )
        raise ValueError(
            f"{names(i)} is {sizes[i]:.3g} m thick: its contacts would need {need:.3g} Hz "
            f"of stiffness to hold it up without rocking, and at dt={dt:.4g} s with {substeps} "
            f"substeps a contact can be at most {DYNAMIC_CAP * rate:.3g} Hz stiff (1/"
            f"{1 / DYNAMIC_CAP:.0f} of the substep rate). {fix}"
        )


@inline_kernel
def turn_reach(angular_velocity, extent, dt):
    """m: how far a body's turn over a step of dt s can carry any of its points toward something:
    its farthest point's arc, |w| extent dt, but never more than the body's width across its
    centre, 2 extent (a point on a circle moves at most a diameter). Uncapped, a 1 m box spinning
    at 2000 rad/s without gravity, 4.3 m above the floor, reached 23 m: contacts were made with a
    floor it could never touch, and their rows, linearised about a turn of 8 rad per substep,
    threw it upward at 45 m/s."""
    return min(abs(angular_velocity) * extent * dt, 2.0 * extent)


def check_softness(dt, substeps, damping_ratio, contact_hertz=None):
    """Raise ValueError if the soft contacts' coefficients (``soft_step.softness``) are not
    finite at these settings, naming the setting to change. Each setting alone was accepted
    (any positive float), but a contact's stiffness is set relative to the substep rate
    substeps/dt and its damping enters as 2 damping_ratio: a subnormal dt (1e-310 s) made the
    rate infinite and damping_ratio=1e308 overflowed 2 damping_ratio, so the first step's
    coefficients were NaN and the World blamed a body at rest ("body 0 diverged ... try a
    smaller dt"). The stiffest contact (STATIC_CAP of the substep rate), the default rule
    (DYNAMIC_CAP) and a ``contact_hertz`` given are checked: a contact is no stiffer than the
    first and, without gravity, as soft as the last (undamped, 1e-323 Hz underflowed h omega
    to 0 and the bias rate to inf)."""
    from .soft_step import DYNAMIC_CAP, STATIC_CAP, softness

    rate = substeps / dt  # Hz
    h = dt / substeps  # s
    if not math.isfinite(rate) or h <= 0.0:
        raise ValueError(
            f"dt={dt!r} s is too small for float64: {substeps} substeps of it are a substep rate "
            f"of {rate:.3g} Hz, and the contacts' stiffness is set relative to that rate. Use a "
            f"dt above 1e-300 s"
        )
    with np.errstate(all="ignore"):  # an overflow is reported below, by name
        # a given contact_hertz above the cap is capped (``pair_hertz``): checked as used
        given = None if contact_hertz is None else min(contact_hertz, DYNAMIC_CAP * rate)
        for hertz in (STATIC_CAP * rate, DYNAMIC_CAP * rate, given):
            if hertz is None:
                continue
            coefficients = softness.py_func(np.float64(hertz), damping_ratio, np.float64(h))
            if not np.all(np.isfinite(coefficients)) and hertz is given:
                raise ValueError(
                    f"contact_hertz={contact_hertz!r} is too small for float64 with "
                    f"damping_ratio={damping_ratio!r}: the soft contacts' bias rate overflows at "
                    f"dt={dt:.4g} s with {substeps} substeps. Use a larger contact_hertz (or some "
                    f"damping)"
                )
            if not np.all(np.isfinite(coefficients)):
                raise ValueError(
                    f"damping_ratio={damping_ratio!r} is too large for float64: the soft "
                    f"contacts' coefficients overflow (2 damping_ratio + stiffness x substep) at "
                    f"dt={dt:.4g} s with {substeps} substeps. A ratio above 1 is already "
                    f"overdamped; use one below 1e300"
                )
