"""Small contact computations the policies share."""
from ..contacts import ANCHOR_BX, ANCHOR_BY, BODY_B, NORMAL_X, NORMAL_Y
from ..jit import inline_kernel


@inline_kernel
def stopping_impulse(c, j, mover, position, velocity, angular_velocity, inv_mass, inv_inertia,
                     manifold_int, manifold_float, point_float):
    """The normal impulse (N s, >= 0) that would stop ``mover``'s point j of manifold c from
    approaching its partner, were the partner immovable, from the current velocities; and the
    point's world position (m). Policies use it to judge an impact *before* the solve, when the
    solved impulse is not known yet: for a frozen partner it is exactly what the solver would
    apply at zero restitution."""
    b = manifold_int[c, BODY_B]
    nx = manifold_float[c, NORMAL_X]
    ny = manifold_float[c, NORMAL_Y]
    wx = point_float[c, j, ANCHOR_BX] + position[b, 0]
    wy = point_float[c, j, ANCHOR_BY] + position[b, 1]
    rx = wx - position[mover, 0]
    ry = wy - position[mover, 1]
    vn = ((velocity[mover, 0] - angular_velocity[mover] * ry) * nx
          + (velocity[mover, 1] + angular_velocity[mover] * rx) * ny)
    if mover != b:
        vn = -vn                # n points from a to b: a approaches its partner when v.n > 0
    if vn >= 0.0:
        return 0.0, wx, wy
    rn = rx * ny - ry * nx
    return -vn / (inv_mass[mover] + inv_inertia[mover] * rn * rn), wx, wy
