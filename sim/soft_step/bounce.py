"""What restitution bounces with (``batches.restitution``): each point's approach speed where it
bounces, carried from the start of the step in free flight, and which bodies gravity moves in the
step (those no contact holds up).

Why a module of its own: restitution is the one pass that needs where a point *started* the step
(its separation and velocity then) next to where it is after the last substep, and which of its
two bodies was held; the sweeps need neither. Split from ``batches.py`` by job, as its other
passes are.
"""

import numpy as np

from ..jit import wide_inline
from .layout import (
    BASE1,
    E,
    LANES_U,
    MA,
    MB,
    NX,
    NY,
    PN1,
    POINT2,
    RAX1,
    RAY1,
    RBX1,
    RBY1,
    SEP1,
    STRIDE_U,
    TN1,
    U64,
)


@wide_inline
def free_flight_approach(relv, start, now, acceleration):
    """m/s: the relative normal velocity of a point at separation ``now`` (m) that was ``start``
    apart moving at ``relv`` (m/s), under a constant relative normal ``acceleration`` (m/s^2):
    v^2 = relv^2 + 2 a (now - start), approaching. ``relv`` itself when the point touched already
    (start <= 0), did not close (now >= start), or never closes under that acceleration.

    Why: a point that closes during the step is accelerated by gravity until then, so its speed
    at the start of the step is not the one it arrives with, by up to g dt either way. Taken at
    the start, a box dropped onto the floor bounced 13% short of e^2 h (0.5 m; 10% from 1 m, 5%
    from 3.7 m, as the contact fell in the step), and a box thrown at a ceiling with e = 1 came
    back with up to 6% more energy. Taken at separation 0 (where free flight touches), a box the
    step's last relax sweep stopped short of the floor (speculatively: up to a substep's travel,
    1.7 mm from 0.5 m) bounced from there with the speed of the floor and gained that height.
    At the point's separation now (0 if it overlaps), a bounce with e = 1 gives back exactly the
    energy the fall had."""
    if start <= 0.0 or now >= start or acceleration == 0.0:
        return relv
    square = relv * relv + 2.0 * acceleration * (now - start)
    if square <= 0.0 or (acceleration > 0.0 and relv >= 0.0):
        return relv  # gravity parts them before the point closes
    return -np.sqrt(square)


@wide_inline
def start_separation(wide, o, l, p, nx, ny):
    """m: point p's separation at the start of the step, summed as ``packing.prepare`` sums it:
    BASE plus the start anchors' offset along n."""
    return (
        wide[o + p + BASE1 + l]
        + (wide[o + p + RBX1 + l] - wide[o + p + RAX1 + l]) * nx
        + (wide[o + p + RBY1 + l] - wide[o + p + RAY1 + l]) * ny
    )


@wide_inline
def approach(wide, o, l, p, nx, ny, acceleration, relv):
    """m/s: point p's approach speed for the bounce (``free_flight_approach``): from ``relv``, its
    velocity along the normal at the start of the step, and its separation then
    (``start_separation``) to its separation now (SEP, after the last substep; 0 if it overlaps,
    a NaN carried through)."""
    sep = wide[o + p + SEP1 + l]
    now = 0.0 if sep <= 0.0 else sep
    start = start_separation(wide, o, l, p, nx, ny)
    return free_flight_approach(relv, start, now, acceleration)


@wide_inline
def has_restitution(wide, o):
    """Has any lane of the batch at o restitution?"""
    bouncy = False
    for l in range(LANES_U):
        bouncy = bouncy or wide[o + E + l] > 0.0
    return bouncy


@wide_inline
def mark_held(n_batches, wide, lane_row, gravity_x, gravity_y, touch, held):
    """Set ``held`` for the row of every movable body that a contact held up in this step: a
    point that pushed (its step total > 0), was within ``touch`` m of touching at the start of the
    step (so not the landing one, which starts apart; ``touch`` is what gravity closes in a
    substep) and whose normal points against gravity from the body's side. Such a body does not
    fall in the step, so a bounce off it sees no gravity on it: a box dropped onto a 1000 times
    heavier box resting on the floor bounced 1-10% short of e^2 h while both were taken to fall
    alike (drops 0.25-3.7 m, e 0.5 and 0.9, dt 1/60). The caller clears ``held`` after use."""
    for b in range(n_batches):
        o = b * STRIDE_U
        ob = b * U64(2) * LANES_U
        for l in range(LANES_U):
            nx = wide[o + NX + l]
            ny = wide[o + NY + l]
            down = gravity_x * nx + gravity_y * ny  # g . n
            for p in (U64(0), POINT2):
                pushed = wide[o + p + TN1 + l] + wide[o + p + PN1 + l] > 0.0
                if not (pushed and start_separation(wide, o, l, p, nx, ny) <= touch):
                    continue
                # the impulse pushes B along n and A against it
                if down < 0.0 and wide[o + MB + l] > 0.0:
                    held[lane_row[ob + l + LANES_U]] = True
                if down > 0.0 and wide[o + MA + l] > 0.0:
                    held[lane_row[ob + l]] = True
