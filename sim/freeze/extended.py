"""``extended``: ours. The seed's idea — stop computing forces for bodies at rest — without its
three admitted limits (no general rest test, no way back to motion, two bodies only).

Freezing (the general rest test), checked every step for the awake bodies with a contact (a pair
whose fat boxes overlap, ``sim.broadphase``): a body with none is never certified (5 below), and
where nothing is near anything, the test costs nothing per body. A body freezes in the step it
passes, with no timer (``rest_steps`` = 1):
  1. slow: |v| + |w| * extent < ``rest_speed`` (m/s) for ``rest_steps`` consecutive steps;
  2. steady: over this step its velocity changed by less than ``rest_acceleration`` (m/s^2) times
     dt (|dv| + |dw| * extent), so the solver's impulses on it balance its weight: they are a
     witness of equilibrium (below). A body not tested in the previous step (it touched
     nothing, or was frozen) has no change to measure yet, and is not steady;
  3. settled: none of its contacts is deeper than twice its pair's slop (``sim.tolerances``)
     and still opening faster than ``opening_speed`` (m/s): the soft contact is pushing it out;
  4. not sliding: none of its contacts has friction at its Coulomb limit (98%) while the surfaces
     slip faster than ``slip_speed`` (m/s). Motion the forces explain is not rest: a box gliding
     on ice is slow long before its friction stops it. Nor closing: no point of its contacts is
     apart but within slop while its gap closes faster than ``closing_speed`` (m/s): a body
     still moving onto a surface has not met it (the certificate counts such a point as a
     support, which could "stop" a drift toward a wall before the body reached it);
  5. certified (``sim/freeze/certificate.py``): contact forces exist that hold it in static
     equilibrium with margin: its supports' forces inside their friction cones shrunk by
     ``friction_margin``, and still holding with an extra moment of ``tip_margin`` times its size
     times its load either way (the centre of pressure inside the support by that margin). A
     body held by nothing (floating free without gravity) is never certified: nothing stops its
     drift. A body on a single point (a corner, an apex) is never certified; a box on a ramp its
     friction cannot hold is not, however slowly it creeps; a plank whose centre of mass
     overhangs its support is not. A body refused alone may still be certified with the
     candidates it touches,
     as one rigid body held by what lies outside it, each refused member held with the others
     taken as immovable (``extended_rest.wedges``): two bodies that each lean on the other are
     refused one by one, since each one's support may move;
  6. whole groups only: no body it touches is awake and failing 1-4 (iterated to a fixed point),
     and nothing it rests on, nor, if only a brace held it, anything that presses on it, is awake
     and not freezing with it (``extended_rest.on_the_awake``; a frozen body's supports are at
     rest, as the wake rules assume).
     An awake body that is still moving keeps its neighbours awake, so nothing freezes against
     something that pushes it. A body that is still but not certified (on a point, at its
     friction limit) stays awake without keeping the bodies beside it awake: it pushes nothing,
     and if it starts to, the wake rules see it as they see any awake body touching frozen ones.
     What rests on it waits for it.
  Nothing in the test is about horizontal faces: a plank across two boxes, a box leaning on a wall
  or a block of an arch passes it if its contacts can hold it.

What freezing records (the support graph): for each contact whose impulse on the body points
against gravity, the partner is a *support*; a link (support, body) is stored when the support is
dynamic. From its supports the body keeps a summary for the wake test: the support direction n_s
(of their impulses on it, summed), the support points' extent
[lo, hi] along the tangent t_s = perp(n_s), the *cone* of directions its supports can push in
together (each support point's friction cone about its own normal, the span of their edges), and
the *load* it was in equilibrium under: its weight plus every non-support impulse on it (bodies
resting on it, side contacts), as a force and a moment about its centre of mass. A body freezing
onto an already frozen body adds its own push to that body's load, and the change reaches the
frozen bodies under that one too (``extended_wake.transmit``): each support link carries a fixed
share of what its body carries.

Waking (every transition back to motion), checked every step only for frozen bodies that awake
bodies touch (so resting bodies cost nothing otherwise):
  - impact: an awake body's contacts would push it with normal impulses that, were it free, would
    set it moving faster than ``impact_speed`` (m/s): impulse / its mass. A speed, not an impulse,
    so that the rule is the same at every size (with a threshold of 0.5 N s, a stack of 1 mm boxes
    was never woken by a box falling onto it, and stood where ``off``'s toppled);
  - push: the frozen body's load plus this step's impulses from awake bodies would need a
    reaction outside its supports' cone (more friction than they have, or a pull: lifted off).
    The pushes on a frozen body that holds are passed on to the frozen bodies under it, which
    are judged with them (a block landing on the end of a frozen plank tips the pedestal under
    the plate under it);
  - tipping: the resultant's line of action leaves the support extent [lo, hi] (the centre of
    pressure leaves the base, as when a weight lands on the overhanging end of a plank);
  - support removed or moved: when any body wakes, everything it supports wakes in the same step,
    transitively through the support graph (a breadth-first walk of the links).

Per-body state: body_int[:, REST_COUNT] steps slow in a row; the columns are named in
``extended_layout.py``.

This module is the policy as the dispatch sees it (NAME, PARAMETERS, the two hooks); the hooks'
stages live by job, as Box2D v3 splits its solver stages: ``extended_rest.py`` the rest test
(unsettled contacts, whole groups), ``extended_freezing.py`` freezing the certified bodies with
the summary of their supports and loads, ``extended_wake.py`` the wake rules and the support
graph, ``extended_layout.py`` the per-body state they read. The hooks keep the loops over the step's
contacts (the order in which they read and write the state is the policy); the stages are what
those loops call.
"""

import numpy as np

from ..activity import CAUSE
from ..data import (
    ANCHOR_BX,
    ANCHOR_BY,
    BODY_A,
    BODY_B,
    NORMAL_X,
    NORMAL_Y,
    N_ACTIVE,
    N_AWAKE,
    N_CERTIFICATES,
    POINT_COUNT,
    STEP_COUNT,
)
from ..jit import inline_kernel, lean_kernel
from . import certificate, extended_layout
from .contact_math import impact_impulses
from .extended_layout import (
    BRACED,
    MARK,
    PUSH_M,
    PUSH_NORMAL,
    PUSH_X,
    PUSH_Y,
    WAIT_CLOSING,
    WAIT_DEEP,
    WAIT_SLIDING,
    WAIT_UNCERTIFIED,
    WAITING,
    impulse_on,
    is_movable,
)
from .extended_freezing import freeze_certified
from .extended_rest import (
    CLOSING,
    DEEP,
    SLIDING,
    slow_and_steady,
    unsettled,
    wedges,
    whole_groups,
)
from .extended_wake import (
    judge_touched,
    touch,
)

NAME = "extended"
PARAMETERS = {
    "impact_speed": 0.5,
    "rest_speed": 0.02,
    "rest_acceleration": 0.1,
    "rest_steps": 1,
    "slip_speed": 1e-3,
    "opening_speed": 1e-3,
    "closing_speed": 1e-3,
    "friction_margin": 0.05,
    "tip_margin": 0.02,
}
INT_PARAMETERS = ("rest_steps",)
#: parameters that were replaced, and by what (a World given one says so)
RENAMED = {
    "impulse_threshold": "impact_speed (m/s: the impulses over the frozen body's mass, the same "
    "rule at every size) replaced extended's impulse_threshold (N s) in 2026-12"
}
#: parameters that must stay below a bound (exclusive): a friction cone shrunk by 100% is a line;
#: a tip margin of half the body's size or more already certifies nothing, and one of ~1e155 made
#: the certificate's moments overflow to inf, after which every body passed it (a box frozen at
#: once at tip_margin=1e300)
BELOW = {"friction_margin": 1.0, "tip_margin": 1.0}
#: the per-body state the World allocates for the policy (``activity.initial_activity``),
#: in the columns ``extended_layout`` names
REAL_COLUMNS = extended_layout.REAL_COLUMNS
INT_COLUMNS = extended_layout.INT_COLUMNS
LINK_COLUMNS = extended_layout.LINK_COLUMNS


def initial(activity, velocity, angular_velocity):
    """Per-body state of a new World: the starting velocities are the rest test's "step 0"
    (TESTED 0), so step 1's change is measured from them. Left at zero, a body started at 3 m/s
    into the floor 1 mm below it, stopped in step 1, counted as steady and was frozen in that
    step; a scene placed at rest starts at zero velocity, and still freezes in step 1."""
    real = activity.body_real
    real[:, extended_layout.PREVIOUS_VX] = velocity[:, 0]
    real[:, extended_layout.PREVIOUS_VY] = velocity[:, 1]
    real[:, extended_layout.PREVIOUS_W] = angular_velocity
    activity.body_int[:, extended_layout.TESTED] = 0


_RESTED = CAUSE["rested"]
_IMPACT = CAUSE["impact"]


@inline_kernel
def before_solve(settings, counters, bodies, contacts, activity):
    """Impacts and pushes, judged *before* the solve so that the collision is solved between
    moving bodies and momentum is passed on, not reflected off an immovable body (a body woken
    after the step would have stopped its pusher dead first).

    For each frozen body that awake bodies touch, the impulses the solve will give the contact
    points its movers reach in this step, were it immovable, are estimated from the velocities
    before gravity is applied (``contact_math.impact_impulses``; so a body merely resting on a
    frozen one contributes nothing, however heavy; its weight is judged after the solve). The
    frozen body wakes (and, through the support graph, all it carries) if the estimates, over its
    mass, add up to more than ``impact_speed`` (an impact), or if its load plus the estimated push
    breaks its equilibrium (a push, or tipping). Returns the number of bodies woken."""
    # the work arrays here; the walk over contacts in a lean kernel (no reference counting:
    # sim/jit), for a kernel that allocates counts every array its inlined helpers are passed.
    # The walk runs even when nothing is frozen (it then finds nothing). Skipping it then, and
    # after_solve's walk for touched frozen bodies, was tried (2026-12-06: 3.4 + 2.5 us of a
    # 320 us step on drift(1000), bench_freeze's in-flight overhead 1.058 -> 1.039): a step
    # with no frozen body became a few us cheaper than one with any, a step at N_frozen = 0
    # that fig_scaling's linear model (a N_awake + b N_frozen + c) reads as the frozen bodies'
    # cost (b/a 0.0042 -> 0.0079 and 0.022 in two runs). Reverted: the cost of having frozen
    # bodies at all is paid by every scene under extended, and b stays the marginal cost.
    touched = np.empty(min(2 * counters[N_ACTIVE], settings.n_dynamic) + 1, np.int64)
    queue = np.empty(settings.n_dynamic, np.int64)
    ring = np.empty(settings.n_dynamic + 1, np.int64)
    reached = np.empty(settings.n_dynamic, np.int64)
    return _impacts(settings, counters, bodies, contacts, activity, (touched, queue, ring, reached))


@lean_kernel
def _impacts(settings, counters, bodies, contacts, activity, work):
    """``before_solve``'s work, in its work arrays ``work``: (touched, queue, ring, reached)."""
    touched = work[0]
    position = bodies.position
    ci = contacts.contact_int
    cf = contacts.contact_float
    awake_slot, body_real, body_int = activity.awake_slot, activity.body_real, activity.body_int
    n_dyn = settings.n_dynamic
    count = counters[N_ACTIVE]
    n_touched = np.int64(0)  # not a literal (sim/jit, LITERALS)
    for k in range(count):
        c = contacts.active[k]
        a = ci[c, BODY_A]
        b = ci[c, BODY_B]
        for frozen_body, mover in ((a, b), (b, a)):
            if not (
                0 <= frozen_body < n_dyn
                and awake_slot[frozen_body] < 0
                and is_movable(mover, n_dyn, awake_slot)
            ):
                continue
            # read only here: most contacts touch no frozen body (a scene in flight: none)
            nx = cf[c, NORMAL_X]
            ny = cf[c, NORMAL_Y]
            n_touched = touch(frozen_body, touched, n_touched, body_real, body_int)
            # n points from a to b: a push on the frozen body is along +n if it is b, -n if a
            sign = 1.0 if frozen_body == b else -1.0
            # a point made ahead, that the mover reaches in a later step, gives nothing
            p0, p1, x0, y0, x1, y1 = impact_impulses(c, mover, settings, bodies, contacts)
            for p, wx, wy in ((p0, x0, y0), (p1, x1, y1)):
                if p > 0.0:
                    px = sign * p * nx
                    py = sign * p * ny
                    body_real[frozen_body, PUSH_X] += px
                    body_real[frozen_body, PUSH_Y] += py
                    body_real[frozen_body, PUSH_M] += (wx - position[frozen_body, 0]) * py - (
                        wy - position[frozen_body, 1]
                    ) * px
                    body_real[frozen_body, PUSH_NORMAL] += p
    impacts = np.bool_(True)  # not a literal (sim/jit, LITERALS)
    return judge_touched(n_touched, impacts, work, settings, counters, bodies, contacts, activity)


@inline_kernel
def after_solve(settings, counters, bodies, contacts, activity):
    """Loads on frozen bodies from this step's solved impulses (the weight of awake bodies
    resting on them, which the approach estimate before the solve does not see), then the rest
    test and freezing (see the module docstring)."""
    # the walks over bodies and contacts run in lean kernels (no reference counting: sim/jit);
    # this one allocates the work arrays and runs the certificate, which allocates its own
    touched = np.empty(min(2 * counters[N_ACTIVE], settings.n_dynamic) + 1, np.int64)
    queue = np.empty(settings.n_dynamic, np.int64)
    ring = np.empty(settings.n_dynamic + 1, np.int64)
    reached = np.empty(settings.n_dynamic, np.int64)
    work = (touched, queue, ring, reached)
    if not _candidates(settings, counters, bodies, contacts, activity, work):
        return
    awake, awake_slot = activity.awake, activity.awake_slot
    body_int = activity.body_int
    n_dyn = settings.n_dynamic
    count = counters[N_ACTIVE]
    n_awake = counters[N_AWAKE]
    # the certificate (sim/freeze/certificate.py): static equilibrium with margin. A body that
    # is still but not certified (MARK 2: on a point, at its friction limit) stays awake, but
    # does not keep its neighbours awake: it pushes nothing, and if it starts to, the wake rules
    # see it as they see any awake body touching frozen ones
    candidates = np.empty(n_awake, np.int64)
    n_candidates = np.int64(0)  # not a literal 0 (sim/jit, LITERALS)
    for k in range(n_awake):
        if body_int[awake[k], MARK] == 1:
            candidates[n_candidates] = awake[k]
            n_candidates += 1
    held, braced = certificate.holds(
        candidates, n_candidates, awake_slot, settings, bodies, contacts, count
    )
    # A body held only with a brace's help is judged with its brace as a group (``wedges``),
    # whose forces inside are solved for within each member's own balance: alone, the brace's
    # cone counted as a support that could push as hard as needed. A triangle on its apex, 4 mm
    # off balance, with a 1.1 g plank across it and a static block was frozen upright while
    # off's fell: the plank pressed on it with 9e-5 N s a step, and holding it took 3e-3.
    for k in range(n_candidates):
        held[k] = held[k] and not braced[k]
    counters[N_CERTIFICATES] += n_candidates
    counters[N_CERTIFICATES] += wedges(
        candidates, n_candidates, held, n_dyn, awake_slot, settings, bodies, contacts, count
    )
    for k in range(n_candidates):
        body_int[candidates[k], BRACED] = 1 if braced[k] else 0
        if not held[k]:
            body_int[candidates[k], MARK] = 2
            body_int[candidates[k], WAITING] = WAIT_UNCERTIFIED
    freeze_certified(settings, counters, bodies, contacts, activity)


@lean_kernel
def _candidates(settings, counters, bodies, contacts, activity, work):
    """``after_solve``'s first part: loads and wakes of frozen bodies, the rest test, and the
    candidates for the certificate (body_int[:, MARK] == 1). Returns whether there are any.
    ``work``: the work arrays (touched, queue, ring, reached)."""
    touched = work[0]
    position = bodies.position
    ci = contacts.contact_int
    pf = contacts.point_float
    awake, awake_slot = activity.awake, activity.awake_slot
    body_real, body_int = activity.body_real, activity.body_int
    n_dyn = settings.n_dynamic
    dt = settings.dt
    count = counters[N_ACTIVE]
    # ---- 1. pushes and tipping: frozen bodies touched by awake bodies ----------------------------
    n_touched = np.int64(0)  # not a literal (sim/jit, LITERALS)
    for kk in range(count):
        c = contacts.active[kk]
        a = ci[c, BODY_A]
        b = ci[c, BODY_B]
        for frozen_body, other in ((a, b), (b, a)):
            if not (
                0 <= frozen_body < n_dyn
                and awake_slot[frozen_body] < 0
                and is_movable(other, n_dyn, awake_slot)
            ):
                continue
            n_touched = touch(frozen_body, touched, n_touched, body_real, body_int)
            for j in range(ci[c, POINT_COUNT]):
                px, py = impulse_on(frozen_body, c, j, contacts)
                # Every impulse counts, an awake body's upward one too. A frozen body's supports
                # are at rest (extended_rest.on_the_awake), so an awake body that comes to hold it
                # up takes its load off them: the body wakes when that lifts it, and then waits to
                # freeze with that body. Skipped (bf3ecaf), a frozen body stayed on an awake one,
                # which it clamps: what on_the_awake keeps from happening at freezing.
                body_real[frozen_body, PUSH_X] += px
                body_real[frozen_body, PUSH_Y] += py
                # the anchor relative to B's centre; A's anchor is the same world point
                wx = pf[c, j, ANCHOR_BX] + position[b, 0]
                wy = pf[c, j, ANCHOR_BY] + position[b, 1]
                rx = wx - position[frozen_body, 0]
                ry = wy - position[frozen_body, 1]
                body_real[frozen_body, PUSH_M] += rx * py - ry * px
    impacts = np.bool_(False)  # not a literal (sim/jit, LITERALS)
    judge_touched(n_touched, impacts, work, settings, counters, bodies, contacts, activity)

    # ---- 2. the rest test: the awake bodies with a contact (slow_and_steady) ----------------
    # An awake body without one keeps the MARK of its last test, never 1: every body marked 1 in
    # a step is frozen or unmarked by its end. The later stages read MARK only of the bodies of
    # this step's active contacts, all tested here. (A walk over the active contacts' bodies
    # instead of the awake list, tried: the free fall's first phase 1.018-1.024 times off
    # against 1.027-1.032 here, drift(1000) from step 1000 1.042-1.045 against 1.038-1.040:
    # bench_freeze judges the worst phase.)
    n_awake = counters[N_AWAKE]
    if n_awake == 0:
        return False
    step = counters[STEP_COUNT]
    any_candidate = False
    for k in range(n_awake):
        i = awake[k]
        if contacts.head[i] < 0:
            continue  # no contact: nothing can hold it
        if slow_and_steady(i, step, settings, bodies, body_real, body_int):
            any_candidate = True
    if not any_candidate:
        return False
    # Not sliding: a candidate with a contact whose friction is at its Coulomb limit while its
    # surfaces slip faster than slip_speed is in motion the forces explain, however slow its
    # centre is (a box gliding to a stop on ice slides until its friction stops it): MARK 0,
    # in motion. Settled: a candidate with a contact deeper than twice its pair's slop may still
    # be pushed out by it (the soft contact works over many steps); frozen now, it would keep
    # that overlap for good. It is not frozen (MARK 2), but it is still: the soft contact under a
    # load small bodies press on it sits this deep for good, and must not keep a pile awake.
    for kk in range(count):
        c = contacts.active[kk]
        a = ci[c, BODY_A]
        b = ci[c, BODY_B]
        if not (
            (0 <= a < n_dyn and body_int[a, MARK] == 1)
            or (0 <= b < n_dyn and body_int[b, MARK] == 1)
        ):
            continue
        state = unsettled(c, settings, dt, bodies, contacts)
        if state == SLIDING or state == CLOSING:
            for body in (a, b):
                if 0 <= body < n_dyn:
                    if body_int[body, MARK] == 1:
                        body_int[body, WAITING] = WAIT_SLIDING if state == SLIDING else WAIT_CLOSING
                    body_int[body, MARK] = 0
        elif state == DEEP:
            for body in (a, b):
                if 0 <= body < n_dyn and body_int[body, MARK] == 1:
                    body_int[body, MARK] = 2
                    body_int[body, WAITING] = WAIT_DEEP
    if not whole_groups(count, n_dyn, awake, n_awake, contacts, awake_slot, body_int):
        return False
    return True
