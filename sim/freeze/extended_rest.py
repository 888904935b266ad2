"""The ``extended`` policy's rest test: the stages that judge whether a still body is at rest,
beyond its own speed (``sim.freeze.extended`` runs them in ``after_solve``; the certificate of
static equilibrium is ``certificate.py``).

  unsettled     a contact still working: sliding at its friction limit, or deep and opening
  whole_groups  a candidate touching an awake body in motion is no candidate (to a fixed point)

Split from ``extended.py`` by job: these judge contacts and groups of bodies, once per step,
while the hook that calls them moves data (freezes bodies, records the support graph); the
wake rules are ``extended_wake.py``.
"""

from ..data import (
    ANCHOR_BX,
    ANCHOR_BY,
    BODY_A,
    BODY_B,
    END_SEPARATION,
    FRICTION,
    NORMAL_IMPULSE,
    NORMAL_X,
    NORMAL_Y,
    POINT_COUNT,
    SEPARATION,
    SLOP,
    TANGENT_IMPULSE,
)
from ..jit import inline_kernel, kernel
from .contact_math import touching
from .extended_layout import MARK, is_movable


#: a contact whose friction is at this share of its Coulomb limit, or more, is sliding
SLIDING_SHARE = 0.98
#: what ``unsettled`` finds in a contact
SLIDING, DEEP = 1, 2


@kernel
def whole_groups(count, n_dyn, awake, n_awake, contacts, awake_slot, body_int):
    """Clear the mark of every candidate (MARK 1) that touches an awake body in motion (MARK 0),
    to a fixed point: an awake body that is still moving keeps its neighbours awake, so nothing
    freezes against something that pushes it. Returns whether any candidate is left."""
    ci = contacts.contact_int
    changed = True
    while changed:
        changed = False
        for kk in range(count):
            c = contacts.active[kk]
            a = ci[c, BODY_A]
            b = ci[c, BODY_B]
            if not (is_movable(a, n_dyn, awake_slot) and is_movable(b, n_dyn, awake_slot)):
                continue
            if not touching(c, contacts):
                continue  # made ahead for a fast body that did not arrive
            if body_int[a, MARK] + body_int[b, MARK] == 1:  # a candidate and a mover
                body_int[a, MARK] = 0
                body_int[b, MARK] = 0
                changed = True
    for k in range(n_awake):
        if body_int[awake[k], MARK] == 1:
            return True
    return False


@inline_kernel
def unsettled(c, slip_speed, dt, bodies, contacts):
    """Is contact c still working? ``SLIDING``: its friction at the Coulomb limit while the
    surfaces slip faster than ``slip_speed`` (m/s); else ``DEEP``: a touching point deeper than
    twice the pair's slop that opened faster than ``slip_speed`` over the step (dt, s); else 0."""
    position, velocity, angular_velocity = bodies.position, bodies.velocity, bodies.angular_velocity
    ci = contacts.contact_int
    cf = contacts.contact_float
    pf = contacts.point_float
    a = ci[c, BODY_A]
    b = ci[c, BODY_B]
    sum_pn = 0.0
    sum_pt = 0.0
    slip = 0.0
    deep = False
    for j in range(ci[c, POINT_COUNT]):
        # deep and still opening: the soft contact is pushing the bodies apart (a contact that
        # carries a load sits at a steady depth, which freezing keeps as it is)
        deep = deep or (
            pf[c, j, END_SEPARATION] < -2.0 * cf[c, SLOP]
            and pf[c, j, END_SEPARATION] - pf[c, j, SEPARATION] > slip_speed * dt
        )
        if pf[c, j, END_SEPARATION] > cf[c, SLOP]:
            continue  # not touching
        sum_pn += pf[c, j, NORMAL_IMPULSE]
        sum_pt += pf[c, j, TANGENT_IMPULSE]
        # B's surface against A's along the tangent (ny, -nx)
        wx = pf[c, j, ANCHOR_BX] + position[b, 0]
        wy = pf[c, j, ANCHOR_BY] + position[b, 1]
        vx = velocity[b, 0] - angular_velocity[b] * (wy - position[b, 1])
        vy = velocity[b, 1] + angular_velocity[b] * (wx - position[b, 0])
        if a >= 0:
            vx -= velocity[a, 0] - angular_velocity[a] * (wy - position[a, 1])
            vy -= velocity[a, 1] + angular_velocity[a] * (wx - position[a, 0])
        slip = max(slip, abs(vx * cf[c, NORMAL_Y] - vy * cf[c, NORMAL_X]))
    # at the limit: the solver clamps |pt| <= mu pn point by point, so a manifold at 98% of it
    # is sliding (a sticking contact sits well inside)
    if (
        slip > slip_speed
        and sum_pn > 0.0
        and abs(sum_pt) >= SLIDING_SHARE * cf[c, FRICTION] * sum_pn
    ):
        return SLIDING
    return DEEP if deep else 0
