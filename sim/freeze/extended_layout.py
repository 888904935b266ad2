"""What the ``extended`` policy's rest test and wake rules share: the per-body state it keeps
(``activity.body_real`` and ``body_int`` columns), the states it moves bodies between, and how a
contact is read (the impulse a point applied to a body; whether a body can move).

Split from ``extended.py`` so that its stages (``extended_rest``: the rest test;
``extended_wake``: the wake rules and the support graph) can each import the layout without
importing one another or the policy's hooks: the data is named once, where every stage sees it.
"""

import numpy as np

from ..data import BODY_B, NORMAL_IMPULSE, NORMAL_X, NORMAL_Y, TANGENT_IMPULSE
from ..jit import inline_kernel
from ..state import State

# body_real columns: support summary and equilibrium load (the support graph's summary, see
# ``sim.freeze.extended``), and this step's impulses from awake bodies (scratch)
(
    SUPPORT_NX,
    SUPPORT_NY,
    SUPPORT_LO,
    SUPPORT_HI,
    SUPPORT_H,
    CONE_LO,
    LOAD_X,
    LOAD_Y,
    LOAD_M,
    PUSH_X,
    PUSH_Y,
    PUSH_M,
    PUSH_NORMAL,
    PREVIOUS_VX,
    PREVIOUS_VY,
    PREVIOUS_W,
    SUPPORT_UP,
    CONE_HI,
    EXTRA_X,
    EXTRA_Y,
    EXTRA_M,
    SEND_X,
    SEND_Y,
    SEND_M,
    BASE_X,
    BASE_Y,
    BASE_M,
) = range(27)
REAL_COLUMNS = 27
# CONE_LO, CONE_HI: the directions (rad from the support direction SUPPORT_N*, toward
# t = perp(n)) between which the supports together can push: every support point's friction cone
# about its own normal, summed (``extended_wake.balance_broken``).
# SUPPORT_UP: the part of a frozen body's support impulses against gravity (N s), the total its
# support links' shares are fractions of (``extended_wake.transmit``). BASE_*: what the body
# passed to its supports when it froze (its LOAD then, plus the pushes of the awake bodies on it
# then): their loads hold that much of it, and only a change from it reaches them. EXTRA_*: such
# a change that reached the body from what rests on it (``transmit``'s scratch, this step's
# only); SEND_*: the part not yet passed on to its own supports
# link_load columns (one row per link (support, body) of ``activity.links``): the push (N s) and
# its moment about the support's centre (N m s) that the body puts on its support, taken back
# from the support's load when the body wakes; and the body's *share*: the fraction of a load
# added to the body later that this support carries (``extended_wake.transmit``), fixed while the
# body is frozen so that taking a load back undoes adding it; and where the push acts (m, world)
LINK_FX, LINK_FY, LINK_M, LINK_SHARE, LINK_PX, LINK_PY = range(6)
LINK_COLUMNS = 6
# body_int columns
REST_COUNT, MARK, TOUCHED, WAITING, BRACED, TESTED, PASSING, REACHED = range(8)
INT_COLUMNS = 8
#: PASSING, REACHED: ``extended_wake.transmit``'s scratch (queued to pass a load on; reached by
#: one), 0 outside it
#: TESTED: the step (counters[STEP_COUNT]) of the body's last rest test (0: the World's start,
#: with its starting velocities; NEVER_TESTED once frozen, so that a woken body's first test
#: counts as changing). Only bodies with a contact are tested
#: (``extended_rest.slow_and_steady``): PREVIOUS_V* and REST_COUNT describe consecutive steps
#: only while TESTED is the previous step's number, and WAITING and MARK are this step's only
#: while it is this step's
#: BRACED: 1 when this step's certificate held the candidate only with a bracing load
#: (``certificate.holds``): then the body that braces it must be at rest too
#: (``extended_rest.on_the_awake``)
NEVER_TESTED = -1

#: WAITING: why an awake body was not frozen by the step's rest test, the first stage that
#: refused it (0 once frozen, and before the first rest test; ``sim.World.why_awake`` names
#: them). Recorded because the question "what is this pile still waiting for?" decides where time
#: to rest goes (a solver still pushing bodies apart, a body creeping at its friction limit, a
#: balance the certificate will not take) and it cannot be read from the velocities: a body
#: slower than rest_speed is held by its contacts or its neighbours, not by its own speed.
(
    WAIT_NONE,  # frozen, or no rest test yet (the World before its first step)
    WAIT_MOVING,  # |v| + |w| extent >= rest_speed
    WAIT_CHANGING,  # slow, but its velocity changed by more than rest_acceleration dt
    WAIT_COUNTING,  # slow and steady for fewer than rest_steps steps
    WAIT_SLIDING,  # a contact at its friction limit whose surfaces slip (extended_rest.unsettled)
    WAIT_DEEP,  # a contact deeper than twice its slop still opening: being pushed out
    WAIT_NEIGHBOUR,  # touches an awake body that is in motion (extended_rest.whole_groups)
    WAIT_UNCERTIFIED,  # no forces hold it in equilibrium with margin (certificate), alone or in
    # a group (extended_rest.wedges)
    WAIT_ON_AWAKE,  # certified, but rests on (or, braced, is pressed by) an awake body not
    # freezing with it
    WAIT_CLOSING,  # a point apart within its slop whose gap is still closing: moving onto it
) = range(10)
WAIT_NAMES = (
    "",
    "moving",
    "changing",
    "counting",
    "sliding",
    "deep",
    "neighbour",
    "uncertified",
    "on_awake",
    "closing",
)

#: the states the policy moves a body between
FREE = np.int8(State.FREE)
FROZEN = np.int8(State.ROTATION_STABLE)  # extended reports frozen bodies as ROTATION_STABLE


@inline_kernel
def impulse_on(body, c, j, contacts):
    """Impulse (x, y) that point j of contact c applied to ``body`` over the step (normal and
    friction, N s)."""
    nx = contacts.contact_float[c, NORMAL_X]
    ny = contacts.contact_float[c, NORMAL_Y]
    pn = contacts.point_float[c, j, NORMAL_IMPULSE]
    pt = contacts.point_float[c, j, TANGENT_IMPULSE]
    px = pn * nx + pt * ny  # tangent = (ny, -nx), as in the solver
    py = pn * ny - pt * nx
    if contacts.contact_int[c, BODY_B] == body:
        return px, py
    return -px, -py


@inline_kernel
def normal_on(body, c, contacts):
    """The unit normal (x, y) of contact c, pointing into ``body``."""
    nx = contacts.contact_float[c, NORMAL_X]
    ny = contacts.contact_float[c, NORMAL_Y]
    if contacts.contact_int[c, BODY_B] == body:
        return nx, ny
    return -nx, -ny


#: an impulse on a body is a *support* when its component against gravity exceeds this fraction
#: of its size (a contact from below or a slope); anything else is a *load* (a weight from above,
#: a push from the side)
SUPPORT_FRACTION = 0.1


@inline_kernel
def is_support(px, py, up_x, up_y):
    """Is the impulse (px, py) on a body a support (it holds the body up), not a load?"""
    return px * up_x + py * up_y > SUPPORT_FRACTION * np.hypot(px, py)


@inline_kernel
def is_movable(i, n_dyn, awake_slot):
    """An awake dynamic body (floor -1, static and frozen bodies are not)."""
    return 0 <= i < n_dyn and awake_slot[i] >= 0
