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
    SEPARATION,
    SLOP,
    SPECULATIVE,
)
from ..jit import inline_kernel


@inline_kernel
def stopping_impulse(c, j, mover, bodies, contacts):
    """The normal impulse (N s, >= 0) that would stop ``mover``'s point j of contact c from
    approaching its partner, were the partner immovable, from the current velocities; and the
    point's world position (m). Policies use it to judge an impact *before* the solve, when the
    solved impulse is not known yet: for a frozen partner it is exactly what a rigid contact would
    apply at zero restitution."""
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
    if vn >= 0.0:
        return 0.0, wx, wy
    rn = rx * ny - ry * nx
    return -vn / (bodies.inv_mass[mover] + bodies.inv_inertia[mover] * rn * rn), wx, wy


@inline_kernel
def arrives(c, j, dt, bodies, contacts):
    """Does point j of contact c reach the surface within this step: within the pair's slop after
    both bodies move dt at their current velocities? Contacts are made before bodies meet, as far
    ahead as a pair can close in one step (``sim.contacts``): a point still apart is no collision
    yet, and a frozen body a fast one will only reach next step must not be woken by it now."""
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
def arriving(c, dt, bodies, contacts):
    """Does any point of contact c reach the surface within this step (``arrives``)?"""
    for j in range(contacts.contact_int[c, POINT_COUNT]):
        if arrives(c, j, dt, bodies, contacts):
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
