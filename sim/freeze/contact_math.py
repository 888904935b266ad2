"""Small contact computations the policies share."""

from ..data import (
    ANCHOR_BX,
    ANCHOR_BY,
    BODY_A,
    BODY_B,
    END_SEPARATION,
    NORMAL_X,
    NORMAL_Y,
    POINT_COUNT,
    RESTITUTION,
    SEPARATION,
    SLOP,
    SPECULATIVE,
)
from ..jit import inline_kernel


@inline_kernel
def _closing(c, j, mover, bodies, contacts):
    """Point j of contact c as ``mover`` meets it: (vn, rn, wx, wy): its normal velocity towards
    the partner (m/s, < 0 closing), the mover's lever arm crossed with the normal (m) and the
    point's world position (m)."""
    position, velocity, angular_velocity = bodies.position, bodies.velocity, bodies.angular_velocity
    b = contacts.contact_int[c, BODY_B]
    nx = contacts.contact_float[c, NORMAL_X]
    ny = contacts.contact_float[c, NORMAL_Y]
    wx = contacts.point_float[c, j, ANCHOR_BX] + position[b, 0]
    wy = contacts.point_float[c, j, ANCHOR_BY] + position[b, 1]
    rx = wx - position[mover, 0]
    ry = wy - position[mover, 1]
    vn = (velocity[mover, 0] - angular_velocity[mover] * ry) * nx + (
        velocity[mover, 1] + angular_velocity[mover] * rx
    ) * ny
    if mover != b:
        vn = -vn  # n points from a to b: a approaches its partner when v.n > 0
    return vn, rx * ny - ry * nx, wx, wy


@inline_kernel
def approach_impulses(c, mover, settings, bodies, contacts):
    """The normal impulses (N s, >= 0) that stop ``mover``'s approach at the points of contact c
    it reaches in this step (``arrives``), were its partner immovable: a two-point contact as one
    2x2 problem (``stopping_impulses``). Returns (p0, p1, v0, v1): each point's impulse and
    closing velocity (m/s, <= 0; 0 for a point that does not arrive or opens)."""
    inv_m = bodies.inv_mass[mover]
    inv_i = bodies.inv_inertia[mover]
    v0, r0, _, _ = _closing(c, 0, mover, bodies, contacts)
    second = min(1, contacts.contact_int[c, POINT_COUNT] - 1)
    v1, r1, _, _ = _closing(c, second, mover, bodies, contacts)
    if not arrives(c, 0, settings, bodies, contacts):
        v0 = 0.0
    if contacts.contact_int[c, POINT_COUNT] < 2 or not arrives(c, 1, settings, bodies, contacts):
        v1 = 0.0
    v0 = min(v0, 0.0)
    v1 = min(v1, 0.0)
    p0, p1 = stopping_impulses(v0, v1, r0, r1, inv_m, inv_i)
    return p0, p1, v0, v1


@inline_kernel
def impact_impulses(c, mover, settings, bodies, contacts):
    """The normal impulses (N s, >= 0) the solve will give the points of contact c that
    ``mover`` reaches in this step (``arrives``), were its partner immovable: what stops the
    mover at all of them at once (a two-point contact as the solver's 2x2 block; either point
    alone where the block would pull), times 1 + e where the approach is fast enough to bounce
    (``restitution_threshold``). Returns (p0, p1, x0, y0, x1, y1): each point's impulse and world
    position (m).

    Each point judged alone, a box landing flat on a frozen one took its whole momentum at each
    corner in turn: 0.23 N s each for a 0.25 kg box at 2.3 m/s, where the solver gave 0.61 each
    (0.57 to stop it, doubled by its restitution of 1)."""
    p0, p1, v0, v1 = approach_impulses(c, mover, settings, bodies, contacts)
    second = min(1, contacts.contact_int[c, POINT_COUNT] - 1)
    _, _, x0, y0 = _closing(c, 0, mover, bodies, contacts)
    _, _, x1, y1 = _closing(c, second, mover, bodies, contacts)
    bounce = 1.0 + contacts.contact_float[c, RESTITUTION]
    if -min(v0, v1) > settings.restitution_threshold:
        p0 *= bounce
        p1 *= bounce
    return p0, p1, x0, y0, x1, y1


@inline_kernel
def stopping_impulses(v0, v1, r0, r1, inv_m, inv_i):
    """The normal impulses (N s, >= 0) that stop a body closing at v0 and v1 (m/s, <= 0; 0: not
    closing) at two points of one contact, the other body immovable: the 2x2 complementarity
    problem the solver's block solves, K p = -v where both push, else the one point whose
    impulse alone leaves the other opening (at most one of the two pulls when K is positive
    definite). r0, r1: each point's arm across the normal (m); inv_m (1/kg), inv_i (1/(kg m^2)):
    the body's. Two points that nearly coincide for the body (K singular) share one row's impulse.
    """
    k00 = inv_m + inv_i * r0 * r0
    k11 = inv_m + inv_i * r1 * r1
    k01 = inv_m + inv_i * r0 * r1
    det = k00 * k11 - k01 * k01
    p0 = -v0 / k00  # each alone
    p1 = -v1 / k11
    if v0 < 0.0 and v1 < 0.0 and det > 1e-9 * k00 * k11:
        b0 = (-v0 * k11 + v1 * k01) / det  # both at once: K p = -v
        b1 = (-v1 * k00 + v0 * k01) / det
        if b0 >= 0.0 and b1 >= 0.0:
            p0 = b0
            p1 = b1
        elif b1 < 0.0:  # the block pulls at point 1: point 0 alone stops both
            p1 = 0.0
        else:  # ... at point 0: point 1 alone
            p0 = 0.0
    elif v0 < 0.0 and v1 < 0.0:  # the points nearly coincide for the mover: one row
        p0 = 0.5 * p0
        p1 = 0.5 * p1
    return p0, p1


@inline_kernel
def arrives(c, j, settings, bodies, contacts):
    """Does point j of contact c reach the surface within this step's solve: within the pair's
    slop after both bodies move at their current velocities for the step and one substep more?
    Contacts are made before bodies meet, as far ahead as a pair can close in one step
    (``sim.contacts``): a point still apart is no collision yet, and a frozen body a fast one will
    only reach next step must not be woken by it now. The substep more: the relax sweep after the
    last substep's positions stops a point that would close within the next substep (its
    speculative row), so the solve pushes a point that ends the step up to a substep's travel
    apart. Judged on the step alone, a box at 3 m/s ending the step 5 mm from a frozen one was no
    impact: the solve stopped it against the frozen box (its speed 3 -> 1.2 m/s, the frozen box
    still), which woke only afterwards, pushed, with 60% of the momentum gone."""
    dt = settings.dt * (1.0 + 1.0 / settings.substeps)
    position, velocity, angular_velocity = bodies.position, bodies.velocity, bodies.angular_velocity
    a = contacts.contact_int[c, BODY_A]
    b = contacts.contact_int[c, BODY_B]
    nx = contacts.contact_float[c, NORMAL_X]
    ny = contacts.contact_float[c, NORMAL_Y]
    wx = contacts.point_float[c, j, ANCHOR_BX] + position[b, 0]
    wy = contacts.point_float[c, j, ANCHOR_BY] + position[b, 1]
    rbx = wx - position[b, 0]
    rby = wy - position[b, 1]
    vx = velocity[b, 0] - angular_velocity[b] * rby
    vy = velocity[b, 1] + angular_velocity[b] * rbx
    if a >= 0:
        rax = wx - position[a, 0]
        ray = wy - position[a, 1]
        vx -= velocity[a, 0] - angular_velocity[a] * ray
        vy -= velocity[a, 1] + angular_velocity[a] * rax
    approach = -(vx * nx + vy * ny)  # > 0: closing (n points from a to b)
    return (
        contacts.point_float[c, j, SEPARATION] - max(approach, 0.0) * dt
        <= contacts.contact_float[c, SLOP]
    )


@inline_kernel
def arriving(c, settings, bodies, contacts):
    """Does any point of contact c reach the surface within this step's solve (``arrives``)?"""
    for j in range(contacts.contact_int[c, POINT_COUNT]):
        if arrives(c, j, settings, bodies, contacts):
            return True
    return False


@inline_kernel
def touching(c, contacts):
    """Did contact c end the step touching: a point within the pair's resting speculative reach
    (the distance at which contacts between bodies at rest are made)? A contact made far ahead
    for a fast body, that the body never reached, does not touch."""
    for j in range(contacts.contact_int[c, POINT_COUNT]):
        if contacts.point_float[c, j, END_SEPARATION] <= contacts.contact_float[c, SPECULATIVE]:
            return True
    return False
