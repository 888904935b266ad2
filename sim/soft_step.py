"""The contact solver: soft step (Box2D v3's solver; Catto's Solver2D compares it with the
sequential impulses and position correction this project used before), solved in wide batches.

One step of dt is ``substeps`` substeps of h = dt / substeps, each:

  integrate velocities   v += h g
  warm start             apply each contact's accumulated impulse from the last substep
  solve                  ``iterations`` sweeps with a *soft* bias computed from the current
                         separation (normal rows only)
  integrate positions    dp += h v, rotation likewise (bodies keep their start pose; the solver
                         tracks the displacement dp, dq so far)
  relax                  ``relax_iterations`` sweeps without bias (normal and friction rows): the
                         velocity the bias added to push bodies apart is taken out again

then one restitution pass, and the impulses are stored for the next step's warm start and for the
freeze policies (which read, per point, the total impulse applied over the whole step: N s).

The soft contact (Catto's "soft step"): a touching point (s <= 0) solves
    impulse = -m_n * (mass_scale * vn + bias) - impulse_scale * accumulated,
    bias = max(mass_scale * bias_rate * s, -push_speed),
the implicit-Euler form of a spring-damper of stiffness ``hertz`` and damping ratio ``zeta``: stable
at any stiffness, and the stiffness is bounded by the substep rate instead of by iterations. A
point still apart (s > 0) is speculative: bias = s / h, the bodies may close the gap, not more.
Contacts against an immovable body (static, frozen, the floor) are twice as stiff, so a pile does
not sink into its support. The steady sink of a contact is (load / effective mass) g / omega^2;
``contact_hertz`` is therefore raised for small bodies (``tolerances``: the sink stays a fixed
fraction of the size) up to its cap, a fraction of the substep rate.

Wide batches. Every step the active contacts are coloured (``colour``): no two contacts of one
colour share a body that can move (static and frozen bodies and the floor are a dummy row that
nothing writes, and use no colour). Each colour is cut into batches of LANES contacts, stored
field by field in one flat array (``wide``): the solver gathers the batch's body rows into the
batch, computes all lanes at once (packed vector instructions), and scatters the velocities back.
"""
import numpy as np
from numba.cpython.unsafe.numbers import trailing_zeros

from .data import (ANCHOR_AX, ANCHOR_AY, ANCHOR_BX, ANCHOR_BY, BODY_A, BODY_B, CARRIED, DPX, DPY,
                   DQC, DQS, END_SEPARATION,
                   FRICTION, N_ACTIVE, N_AWAKE, N_BATCHES, N_COLOURS, N_HARD, NORMAL_IMPULSE,
                   NORMAL_VELOCITY, NORMAL_X, NORMAL_Y, POINT_COUNT, RESTITUTION, SEPARATION,
                   TANGENT_IMPULSE, TURN, VX, VY, W, WARM_NORMAL, WARM_TANGENT)
from .jit import inline_kernel, lean_kernel, wide_inline, wide_kernel

#: constraints per batch: 8 float64 fill one 512-bit register (AVX-512) or two 256-bit ones (AVX2)
LANES = 8
#: Default soft-contact parameters. The damping ratio is three times Box2D's 10: with contacts that
#: carry their load (see LOAD_TIME), a 50-box column started without any initial solve oscillated
#: and buckled at 10 and settles at 30 (experiments/tune_soft_step.py). push_speed is Box2D's.
DAMPING_RATIO = 30.0
PUSH_SPEED = 3.0
#: Stiffness caps as fractions of the substep rate: hertz * h. A contact stiffer than 1/8 of the
#: substep rate (Box2D's cap) made a 20-high pyramid jitter and grow a rocking mode; against an
#: immovable body twice that. The default stiffness is the cap itself ("as stiff as the substep
#: allows": 30 Hz at 4 substeps of 1/60 s, Box2D's default), so more substeps give stiffer
#: contacts.
DYNAMIC_CAP = 0.125
STATIC_CAP = 0.25
#: A contact must be stiff relative to gravity at the size of its bodies, omega^2 >= STIFFNESS_RATIO
#: g / size, or a small body rocks on it (a column of 1 mm boxes fell over at a ratio of 4, rocked
#: slowly at 15 and stood at 36 and above). Small bodies get stiffer contacts up to the cap; a body
#: too small even at the cap is refused (``tolerances.check_step``).
STIFFNESS_RATIO = 25.0
#: Time constant (s) with which a contact's carried load follows the impulse it applies. A soft
#: contact is a spring: it carries a load L by sinking L / (m omega^2), and in a stack every
#: contact sinks by what it carries (a 10-box column sank 3 cm, a 50-box one 0.7 m). Here the
#: spring only acts on the *change* of load: the load the contact has carried for a while is held
#: rigidly (``_normal_rows``: the leak is impulse_scale * (impulse - carried)), so a resting
#: stack does not sink at all. Followed instantly the carried load becomes an integrator that
#: makes tall columns oscillate; followed over a third of a second, the spring damps first.
LOAD_TIME = 1.0 / 3.0
#: A two-point manifold is solved as one 2x2 block unless K's condition number is worse than this
#: (the points nearly coincide): then point by point.
MAX_CONDITION = 1000.0
#: A contact between movable bodies whose masses differ more than this is "hard": Gauss-Seidel
#: converges on it at ~M/(M+m) per sweep (a heavy box on a light one sinks into it while the
#: light one is pushed into the floor). HARD_SWEEPS more relax sweeps per substep go to the batches
#: that touch a body in such a contact, and only to them: a 1000:1 stack dropped onto the floor
#: toppled with one relax sweep and stands with three (final overlap 4 mm), at no cost to scenes
#: without mass ratios.
HARD_RATIO = 10.0
HARD_SWEEPS = 2
#: m/s: a contact point that approached faster than this at the start of a step was an impact,
#: and its impulse is not warm-started into the next step (see ``store``). With the restitution
#: threshold (1 m/s) instead, a settling pile of 30 polygons kept 1.7 cm of overlap (under 1 cm with
#: every point warm-started): ordinary landings need their warm start.
IMPACT_SPEED = 10.0
#: Restitution sweeps after the substeps (see ``restitution``).
RESTITUTION_SWEEPS = 4
_U = np.uint64
_L = _U(LANES)
_FIELDS = ("NX NY MU E MA IA MB IB BIAS_RATE MASS_SCALE IMPULSE_SCALE "
           "RAX1 RAY1 RBX1 RBY1 BASE1 NMASS1 ON1 PN1 PT1 TN1 TT1 RELV1 LN1 "
           "RAX2 RAY2 RBX2 RBY2 BASE2 NMASS2 ON2 PN2 PT2 TN2 TT2 RELV2 LN2 "
           "VAX VAY WA DPAX DPAY QCA QSA VBX VBY WB DPBX DPBY QCB QSB").split()
#: number of fields of a batch; field F of lane l of batch b is wide[b * STRIDE + F + l]
N_FIELDS = len(_FIELDS)
STRIDE = N_FIELDS * LANES
(NX, NY, MU, E, MA, IA, MB, IB, BIAS_RATE, MASS_SCALE, IMPULSE_SCALE,
 RAX1, RAY1, RBX1, RBY1, BASE1, NMASS1, ON1, PN1, PT1, TN1, TT1, RELV1, LN1,
 RAX2, RAY2, RBX2, RBY2, BASE2, NMASS2, ON2, PN2, PT2, TN2, TT2, RELV2, LN2,
 VAX, VAY, WA, DPAX, DPAY, QCA, QSA, VBX, VBY, WB, DPBX, DPBY, QCB, QSB) = [
    _U(k * LANES) for k in range(N_FIELDS)]
#: offset of point 2's fields from point 1's, and the number of fields per point
_P2 = _U((RAX2 - RAX1))
_POINT_FIELDS = int(RAX2 - RAX1) // LANES
_STRIDE = _U(STRIDE)


@inline_kernel
def max_colours(max_degree):
    """Colours ``colour`` may use when no body has more than ``max_degree`` contacts: greedy
    colouring of the contacts between movable bodies uses at most 2 max_degree - 1, and the
    contacts with an immovable body, coloured after those, at most max_degree more."""
    return 3 * max(1, max_degree)


def capacity(n_contacts, max_degree):
    """Batches the solver may need for ``n_contacts`` contacts when no body has more than
    ``max_degree``: every colour may end in one part-filled batch."""
    return -(-n_contacts // LANES) + max_colours(max_degree) + 1


def mask_words(max_degree):
    """uint64 words of colour bits per body row."""
    return max(1, -(-max_colours(max_degree) // 64))


# ---- softness --------------------------------------------------------------------------------
@inline_kernel
def softness(hertz, zeta, h):
    """(bias_rate 1/s, mass_scale, impulse_scale) of a soft constraint (Catto)."""
    if hertz <= 0.0:
        return 0.0, 1.0, 0.0
    omega = 2.0 * np.pi * hertz
    a1 = 2.0 * zeta + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return omega / a1, a2 * a3, a3


@inline_kernel
def pair_hertz(base_hertz, size, gravity, h, immovable):
    """Hz: the stiffness of a contact whose bodies' smaller size is ``size`` m, at substep h s.

    ``base_hertz`` (the World's contact_hertz; 0 = the cap), raised for small bodies so that
    omega^2 >= STIFFNESS_RATIO g / size, doubled against an immovable body (so a pile does not sink
    into its support), and capped at DYNAMIC_CAP (STATIC_CAP) of the substep rate."""
    cap = (STATIC_CAP if immovable else DYNAMIC_CAP) / h
    hertz = base_hertz if base_hertz > 0.0 else DYNAMIC_CAP / h
    if gravity > 0.0 and size > 0.0:
        hertz = max(hertz, np.sqrt(STIFFNESS_RATIO * gravity / size) / (2.0 * np.pi))
    if immovable:
        hertz *= 2.0
    return min(hertz, cap)


# ---- rows of the solver's body state ------------------------------------------------------------
@inline_kernel
def row_of(i, n_dynamic, awake_slot):
    """The solver row of body i: its awake slot + 1, or the dummy row 0 (floor, static, frozen)."""
    if 0 <= i < n_dynamic and awake_slot[i] >= 0:
        return awake_slot[i] + 1
    return 0


@lean_kernel
def load_bodies(counters, bodies, activity, solver):
    """The awake bodies' velocities into their solver rows, displacements zeroed; the dummy row."""
    state = solver.state
    for c in range(state.shape[1]):
        state[0, c] = 0.0
    state[0, DQC] = 1.0
    for k in range(counters[N_AWAKE]):
        i = activity.awake[k]
        r = k + 1
        state[r, VX] = bodies.velocity[i, 0]
        state[r, VY] = bodies.velocity[i, 1]
        state[r, W] = bodies.angular_velocity[i]
        state[r, TURN] = 0.0
        state[r, DPX] = 0.0
        state[r, DPY] = 0.0
        state[r, DQC] = 1.0
        state[r, DQS] = 0.0


@lean_kernel
def integrate_velocities(n_awake, state, awake, solver_inv_mass, gx, gy, h):
    """Gravity over one substep, for every awake body the solver can move (a body a freeze
    policy holds awake but immovable, as ``paper``'s sliding ROTATION_STABLE, is kinematic:
    gravity would carry it away from what rests on it within the step)."""
    for r in range(1, n_awake + 1):
        if solver_inv_mass[awake[r - 1]] > 0.0:
            state[r, VX] += h * gx
            state[r, VY] += h * gy


@lean_kernel
def integrate_positions(n_awake, state, h):
    """Displacement and rotation over one substep. The rotation so far is kept as an angle (the
    body's final angle) and as (cos, sin), advanced without trigonometry and renormalised, which
    the solver uses to rotate anchors."""
    for r in range(1, n_awake + 1):
        w = state[r, W]
        state[r, DPX] += h * state[r, VX]
        state[r, DPY] += h * state[r, VY]
        state[r, TURN] += h * w
        c = state[r, DQC]
        s = state[r, DQS]
        c2 = c - h * w * s
        s2 = s + h * w * c
        inv = 1.0 / np.sqrt(c2 * c2 + s2 * s2)
        state[r, DQC] = c2 * inv
        state[r, DQS] = s2 * inv


# ---- colouring and packing -----------------------------------------------------------------------
@inline_kernel
def _movable(i, n_dynamic, activity):
    """Does the solver change body i's velocity (so two contacts on it must not share a batch)?"""
    return (0 <= i < n_dynamic and activity.awake_slot[i] >= 0
            and (activity.solver_inv_mass[i] > 0.0 or activity.solver_inv_inertia[i] > 0.0))


@inline_kernel
def _solver_row(i, n_dynamic, activity):
    """Body i's solver row if the solver moves it, else the dummy row 0."""
    return row_of(i, n_dynamic, activity.awake_slot) if _movable(i, n_dynamic, activity) else 0


@inline_kernel
def _first_free_colour(masks, ra, rb, lowest, n_words):
    """The first colour >= ``lowest`` used by neither row (row 0, immovable, uses none), marked
    used at both; -1 if none is free."""
    for q in range(lowest // 64, n_words):
        used = _U(0)
        if ra > 0:
            used |= masks[ra, q]
        if rb > 0:
            used |= masks[rb, q]
        if q == lowest // 64:
            used |= (_U(1) << _U(lowest % 64)) - _U(1)    # the colours below ``lowest``
        free = ~used
        if free != _U(0):
            bit = trailing_zeros(free)
            one = _U(1) << _U(bit)
            if ra > 0:
                masks[ra, q] |= one
            if rb > 0:
                masks[rb, q] |= one
            return q * 64 + bit
    return -1


@inline_kernel
def _mark_hard_rows(n_active, n_dynamic, contacts, activity, solver):
    """Mark (solver.row_mark) the rows of both bodies of every active contact whose movable
    bodies' masses differ by more than HARD_RATIO; returns whether any was."""
    ci = contacts.contact_int
    inv_mass = activity.solver_inv_mass
    found = False
    for k in range(n_active):
        s = contacts.active[k]
        ra = _solver_row(ci[s, BODY_A], n_dynamic, activity)
        rb = _solver_row(ci[s, BODY_B], n_dynamic, activity)
        if ra > 0 and rb > 0:
            ma = inv_mass[ci[s, BODY_A]]
            mb = inv_mass[ci[s, BODY_B]]
            if ma > HARD_RATIO * mb or mb > HARD_RATIO * ma:
                solver.row_mark[ra] = True
                solver.row_mark[rb] = True
                found = True
    return found


@lean_kernel
def colour(settings, counters, contacts, activity, solver):
    """Colour the active contacts greedily (first colour free at both movable bodies; those with
    an immovable body in colours after all the others, see below) and lay them out: colour c's contacts fill batches colour_batches[c] .. colour_batches[c+1]-1, in active
    order (those touching a body in a hard contact first), the last batch padded with empty lanes
    (slot -1). Returns the number of batches."""
    n_dyn = settings.n_dynamic
    ci = contacts.contact_int
    masks = solver.colour_mask
    n_words = masks.shape[1]
    n_awake = counters[N_AWAKE]
    for r in range(n_awake + 1):
        for q in range(n_words):
            masks[r, q] = _U(0)
    counts = solver.colour_batches          # first used as per-colour counts
    n_colours_max = counts.shape[0] - 1
    for c in range(n_colours_max + 1):
        counts[c] = 0
    n_active = counters[N_ACTIVE]
    order = solver.order                    # colour of each active contact (~colour: hard), for now
    # Contacts touching a body in a hard contact (HARD_RATIO) get extra relax sweeps, by batch:
    # laid out first in their colour, they fill few batches instead of tainting most (a pile of
    # random polygons, masses 0.005-0.39 kg: 41 of 51 batches were hard with them spread out).
    any_hard = settings.mixed_masses and _mark_hard_rows(n_active, n_dyn, contacts, activity,
                                                         solver)
    # Contacts between two movable bodies first, then those with an immovable one (static, frozen,
    # the floor) in colours after all of theirs: within a sweep the support is solved last, so the
    # sweep ends with every body pushed out of what cannot move, as in Box2D v3, which gives static
    # contacts the highest colours. Solved first, a support is undone by every contact above it
    # in the same sweep: a 0.5 m box landing at 26 m/s on one resting on the floor drove it 14 cm
    # into the floor.
    n_colours = 0
    for immovable in range(2):
        lowest = n_colours if immovable == 1 else 0
        for k in range(n_active):
            s = contacts.active[k]
            ra = _solver_row(ci[s, BODY_A], n_dyn, activity)
            rb = _solver_row(ci[s, BODY_B], n_dyn, activity)
            if (ra == 0 or rb == 0) != (immovable == 1):
                continue
            c = _first_free_colour(masks, ra, rb, lowest, n_words)
            # max_colours() guarantees one: each body has at most max_degree contacts
            hard = any_hard and ((ra > 0 and solver.row_mark[ra])
                                 or (rb > 0 and solver.row_mark[rb]))
            order[k] = ~c if hard else c
            counts[c] += 1
            n_colours = max(n_colours, c + 1)
    # counts -> first batch of each colour
    batch = 0
    for c in range(n_colours):
        n = counts[c]
        counts[c] = batch
        batch += (n + LANES - 1) // LANES
    counts[n_colours] = batch
    n_batches = batch
    for e in range(n_batches * LANES):
        solver.lane_slot[e] = -1
    cursor = solver.colour_cursor           # next free lane of each colour
    for c in range(n_colours):
        cursor[c] = counts[c] * LANES
    for first_pass in range(2 if any_hard else 1):     # hard contacts first, then the rest
        for k in range(n_active):
            c = order[k]
            if any_hard and (c < 0) != (first_pass == 0):
                continue
            if c < 0:
                c = ~c
            solver.lane_slot[cursor[c]] = contacts.active[k]
            cursor[c] += 1
    if any_hard:
        for r in range(n_awake + 1):
            solver.row_mark[r] = False
    counters[N_BATCHES] = n_batches
    counters[N_COLOURS] = n_colours
    return n_batches


@lean_kernel
def prepare(settings, counters, bodies, contacts, activity, solver):
    """Fill every lane of every batch from its contact: body rows, masses, anchors, softness,
    effective masses, the separation at the start of the step, the relative normal velocity
    (restitution) and the warm-start impulses. Empty lanes are all zero: no effect."""
    n_dyn = settings.n_dynamic
    h = settings.dt / settings.substeps
    g = np.hypot(settings.gravity_x, settings.gravity_y)
    ci = contacts.contact_int
    cf = contacts.contact_float
    pf = contacts.point_float
    wide = solver.wide
    inv_mass = activity.solver_inv_mass
    inv_inertia = activity.solver_inv_inertia
    awake_slot = activity.awake_slot
    velocity = bodies.velocity
    angular_velocity = bodies.angular_velocity
    warm = 1.0 if settings.warm_starting else 0.0
    for b in range(counters[N_BATCHES]):
        o = _U(b) * _STRIDE
        for lane in range(LANES):
            l = _U(lane)
            e = b * LANES + lane
            ob = _U(2 * b * LANES + lane)
            s = solver.lane_slot[e]
            if s < 0:                              # padding: every field zero, no effect
                solver.lane_row[ob] = _U(0)
                solver.lane_row[ob + _L] = _U(0)
                for f in range(N_FIELDS):
                    wide[o + _U(f) * _L + l] = 0.0
                continue
            a = ci[s, BODY_A]
            bb = ci[s, BODY_B]
            solver.lane_row[ob] = _U(row_of(a, n_dyn, awake_slot))
            solver.lane_row[ob + _L] = _U(row_of(bb, n_dyn, awake_slot))
            ma = inv_mass[a] if a >= 0 else 0.0
            ia = inv_inertia[a] if a >= 0 else 0.0
            mb = inv_mass[bb]
            ib = inv_inertia[bb]
            nx = cf[s, NORMAL_X]
            ny = cf[s, NORMAL_Y]
            wide[o + NX + l] = nx
            wide[o + NY + l] = ny
            wide[o + MU + l] = cf[s, FRICTION]
            wide[o + E + l] = cf[s, RESTITUTION]
            wide[o + MA + l] = ma
            wide[o + IA + l] = ia
            wide[o + MB + l] = mb
            wide[o + IB + l] = ib
            if a >= 0:
                vax = velocity[a, 0]
                vay = velocity[a, 1]
                wa = angular_velocity[a]
            else:
                vax = 0.0
                vay = 0.0
                wa = 0.0
            vbx = velocity[bb, 0]
            vby = velocity[bb, 1]
            wb = angular_velocity[bb]
            n_points = ci[s, POINT_COUNT]
            for j in range(2):
                p = _P2 * _U(j)
                if j >= n_points:                  # a one-point lane: its second point is void
                    for f in range(_POINT_FIELDS):
                        wide[o + p + RAX1 + _U(f) * _L + l] = 0.0
                    continue
                rax = pf[s, j, ANCHOR_AX]
                ray = pf[s, j, ANCHOR_AY]
                rbx = pf[s, j, ANCHOR_BX]
                rby = pf[s, j, ANCHOR_BY]
                wide[o + p + RAX1 + l] = rax
                wide[o + p + RAY1 + l] = ray
                wide[o + p + RBX1 + l] = rbx
                wide[o + p + RBY1 + l] = rby
                # separation = base + (dpB - dpA + rot(dqB) rB - rot(dqA) rA) . n
                wide[o + p + BASE1 + l] = (pf[s, j, SEPARATION]
                                           - ((rbx - rax) * nx + (rby - ray) * ny))
                rna = rax * ny - ray * nx
                rnb = rbx * ny - rby * nx
                k_normal = ma + mb + ia * rna * rna + ib * rnb * rnb
                # the point's mass at the start of the step (restitution's; the rows recompute
                # theirs from their arms each sweep)
                wide[o + p + NMASS1 + l] = 1.0 / k_normal if k_normal > 0.0 else 0.0
                wide[o + p + ON1 + l] = 1.0 if k_normal > 0.0 else 0.0   # the point exists
                wide[o + p + PN1 + l] = warm * pf[s, j, WARM_NORMAL]
                wide[o + p + PT1 + l] = warm * pf[s, j, WARM_TANGENT]
                wide[o + p + TN1 + l] = 0.0
                wide[o + p + TT1 + l] = 0.0
                wide[o + p + LN1 + l] = warm * pf[s, j, CARRIED]
                dvx = vbx - wb * rby - vax + wa * ray
                dvy = vby + wb * rbx - vay - wa * rax
                wide[o + p + RELV1 + l] = dvx * nx + dvy * ny
            immovable = (ma == 0.0 and ia == 0.0) or (mb == 0.0 and ib == 0.0)
            size = bodies.size[bb] if a < 0 else min(bodies.size[a], bodies.size[bb])
            hertz = pair_hertz(settings.contact_hertz, size, g, h, immovable)
            bias_rate, mass_scale, impulse_scale = softness(hertz, settings.damping_ratio, h)
            wide[o + BIAS_RATE + l] = bias_rate
            wide[o + MASS_SCALE + l] = mass_scale
            wide[o + IMPULSE_SCALE + l] = impulse_scale
    if settings.mixed_masses:
        counters[N_HARD] = _mark_hard(counters[N_BATCHES], wide, solver)
    else:                                  # no contact can be hard (World._mixed_masses)
        for b in range(counters[N_BATCHES]):
            solver.batch_hard[b] = False
        counters[N_HARD] = 0


@inline_kernel
def _mark_hard(n_batches, wide, solver):
    """Flag the batches that touch a body in a contact of mass ratio > HARD_RATIO (both bodies
    movable); returns how many."""
    found = False
    for b in range(n_batches):
        o = _U(b) * _STRIDE
        for lane in range(LANES):
            l = _U(lane)
            ma = wide[o + MA + l]
            mb = wide[o + MB + l]
            if ma > 0.0 and mb > 0.0 and (ma > HARD_RATIO * mb or mb > HARD_RATIO * ma):
                ob = _U(2 * b * LANES + lane)
                solver.row_mark[solver.lane_row[ob]] = True
                solver.row_mark[solver.lane_row[ob + _L]] = True
                found = True
    n_hard = 0
    for b in range(n_batches):
        hard = False
        if found:
            for lane in range(LANES):
                ob = _U(2 * b * LANES + lane)
                ra = solver.lane_row[ob]
                rb = solver.lane_row[ob + _L]
                hard = hard or (ra > 0 and solver.row_mark[ra]) or (rb > 0 and solver.row_mark[rb])
        solver.batch_hard[b] = hard
        n_hard += 1 if hard else 0
    if found:
        for b in range(n_batches):
            for lane in range(LANES):
                ob = _U(2 * b * LANES + lane)
                solver.row_mark[solver.lane_row[ob]] = False
                solver.row_mark[solver.lane_row[ob + _L]] = False
    return n_hard


# ---- the batch kernels --------------------------------------------------------------------------
@wide_inline
def _gather(wide, o, lane_row, ob, state):
    """The batch's body rows (velocity, displacement, rotation so far) into its fields."""
    for l in range(_L):
        ra = lane_row[ob + l]
        rb = lane_row[ob + _L + l]
        wide[o + VAX + l] = state[ra, VX]
        wide[o + VAY + l] = state[ra, VY]
        wide[o + WA + l] = state[ra, W]
        wide[o + DPAX + l] = state[ra, DPX]
        wide[o + DPAY + l] = state[ra, DPY]
        wide[o + QCA + l] = state[ra, DQC]
        wide[o + QSA + l] = state[ra, DQS]
        wide[o + VBX + l] = state[rb, VX]
        wide[o + VBY + l] = state[rb, VY]
        wide[o + WB + l] = state[rb, W]
        wide[o + DPBX + l] = state[rb, DPX]
        wide[o + DPBY + l] = state[rb, DPY]
        wide[o + QCB + l] = state[rb, DQC]
        wide[o + QSB + l] = state[rb, DQS]


@wide_inline
def _scatter(wide, o, lane_row, ob, state):
    """The batch's new velocities back into the body rows. Lanes of one colour share no movable
    body; the dummy row 0 is written by several lanes, all with its unchanged zeros (a zero mass
    never changes a velocity)."""
    for l in range(_L):
        ra = lane_row[ob + l]
        rb = lane_row[ob + _L + l]
        state[ra, VX] = wide[o + VAX + l]
        state[ra, VY] = wide[o + VAY + l]
        state[ra, W] = wide[o + WA + l]
        state[rb, VX] = wide[o + VBX + l]
        state[rb, VY] = wide[o + VBY + l]
        state[rb, W] = wide[o + WB + l]


@wide_inline
def _fmax(a, b):
    """max, as the processor's maxpd computes it (b when a is NaN): compiles to one vector
    instruction, where Python's max semantics need two. Callers put the value that must carry a
    NaN through as ``b``."""
    return a if a > b else b


@wide_inline
def _fmin(a, b):
    return a if a < b else b


@wide_inline
def _apply(wide, o, l, px, py, rax, ray, rbx, rby):
    """Impulse P on B at rB and -P on A at rA, into the batch's velocity fields."""
    wide[o + VAX + l] -= wide[o + MA + l] * px
    wide[o + VAY + l] -= wide[o + MA + l] * py
    wide[o + WA + l] -= wide[o + IA + l] * (rax * py - ray * px)
    wide[o + VBX + l] += wide[o + MB + l] * px
    wide[o + VBY + l] += wide[o + MB + l] * py
    wide[o + WB + l] += wide[o + IB + l] * (rbx * py - rby * px)


@wide_inline
def _normal_velocity(wide, o, l, nx, ny, rax, ray, rbx, rby):
    dvx = (wide[o + VBX + l] - wide[o + WB + l] * rby) - (wide[o + VAX + l] - wide[o + WA + l] * ray)
    dvy = (wide[o + VBY + l] + wide[o + WB + l] * rbx) - (wide[o + VAY + l] + wide[o + WA + l] * rax)
    return dvx * nx + dvy * ny


@wide_inline
def _arms(wide, o, l, p, nx, ny, tx, ty):
    """A point's lever arms now, for an impulse along (tx, ty), and how far B's anchor has moved
    from A's since the start of the step.

    Each anchor sits on its own body's surface (``contacts``) and has moved with its body this
    step (displacement dp, rotation dq): the separation is measured between the moved anchors.
    An impulse and its reaction change no angular momentum when they act along one line: the
    arms are the moved anchors, each shifted towards the other by half their offset *across* the
    impulse (the offset along it, a gap or a penetration, turns nothing). Box2D keeps the arms of
    the start of the step, which does not conserve angular momentum (1.9% lost in a test
    collision). The effective masses are computed from these arms where they are used
    (``_normal_rows``, ``_friction_point``). Returns (rax, ray, rbx, rby, ox, oy): the arms, and
    B's moved anchor minus A's, minus their offset at the start (its projection on the normal,
    added to the start separation, is the separation now)."""
    rax = wide[o + p + RAX1 + l]
    ray = wide[o + p + RAY1 + l]
    rbx = wide[o + p + RBX1 + l]
    rby = wide[o + p + RBY1 + l]
    qca = wide[o + QCA + l]
    qsa = wide[o + QSA + l]
    qcb = wide[o + QCB + l]
    qsb = wide[o + QSB + l]
    sax = qca * rax - qsa * ray                  # anchors turned with their bodies
    say = qsa * rax + qca * ray
    sbx = qcb * rbx - qsb * rby
    sby = qsb * rbx + qcb * rby
    ox = (wide[o + DPBX + l] - wide[o + DPAX + l]) + sbx - sax
    oy = (wide[o + DPBY + l] - wide[o + DPAY + l]) + sby - say
    # B's moved anchor minus A's: the start offset (the start separation along n) plus their
    # relative motion since
    s0 = wide[o + p + BASE1 + l] + (rbx - rax) * nx + (rby - ray) * ny
    dx = ox - (rbx - rax) + s0 * nx
    dy = oy - (rby - ray) + s0 * ny
    across = 0.5 * (dx * ty - dy * tx)
    hx = across * ty
    hy = -across * tx
    return sax + hx, say + hy, sbx - hx, sby - hy, ox, oy


@wide_inline
def _warm_point(wide, o, l, p, nx, ny):
    pn = wide[o + p + PN1 + l]
    pt = wide[o + p + PT1 + l]
    wide[o + p + TN1 + l] += pn
    wide[o + p + TT1 + l] += pt
    # the normal and the friction impulse each on its own line (see _arms)
    rax, ray, rbx, rby, _, _ = _arms(wide, o, l, p, nx, ny, nx, ny)
    _apply(wide, o, l, pn * nx, pn * ny, rax, ray, rbx, rby)
    rax, ray, rbx, rby, _, _ = _arms(wide, o, l, p, nx, ny, ny, -nx)
    _apply(wide, o, l, pt * ny, -pt * nx, rax, ray, rbx, rby)


@wide_kernel
def warm_start(n_batches, wide, lane_row, state):
    """Apply each point's accumulated impulses (normal and friction) from the last substep."""
    for b in range(_U(n_batches)):
        o = b * _STRIDE
        ob = b * _U(2) * _L
        _gather(wide, o, lane_row, ob, state)
        for l in range(_L):
            nx = wide[o + NX + l]
            ny = wide[o + NY + l]
            _warm_point(wide, o, l, _U(0), nx, ny)
            _warm_point(wide, o, l, _P2, nx, ny)
        _scatter(wide, o, lane_row, ob, state)


@wide_inline
def _bias(s, inv_h, push, use_bias, mass_scale, bias_rate, impulse_scale):
    """(bias m/s, mass scale, impulse scale) of a point at separation s: speculative while apart
    (the bodies may close the gap in this substep, not more), soft when touching and
    ``use_bias``, rigid otherwise (relax)."""
    if s > 0.0:
        return s * inv_h, 1.0, 0.0
    if use_bias:
        return _fmax(-push, mass_scale * bias_rate * s), mass_scale, impulse_scale
    return 0.0, 1.0, 0.0


@wide_inline
def _normal_rows(wide, o, l, nx, ny, inv_h, push, use_bias):
    """Both points' non-penetration rows of a lane.

    Solved point by point, the first point's impulse turns the body before the second is
    solved: a box resting on a face rocks, and the rocking grows in tall stacks. So a two-point
    lane is solved as a 2x2 block (Box2D v2's block solver, here with soft rows): both impulses at
    once, Delta = -K^-1 (mass_scale vn + bias) - impulse_scale (impulse - carried), accepted when
    both stay >= 0. Otherwise (one point lifts off, a one-point lane, a near-singular K) the points
    are solved one after the other, the second seeing the first's effect through K12. Both answers
    are computed and one is selected, so the lanes stay branch-free (vectorised)."""
    ms = wide[o + MASS_SCALE + l]
    br = wide[o + BIAS_RATE + l]
    isc = wide[o + IMPULSE_SCALE + l]
    ra1x, ra1y, rb1x, rb1y, o1x, o1y = _arms(wide, o, l, _U(0), nx, ny, nx, ny)
    ra2x, ra2y, rb2x, rb2y, o2x, o2y = _arms(wide, o, l, _P2, nx, ny, nx, ny)
    # current separations: the start separation plus how the anchors moved apart along n
    s1 = wide[o + BASE1 + l] + o1x * nx + o1y * ny
    s2 = wide[o + BASE2 + l] + o2x * nx + o2y * ny
    b1, m1, i1 = _bias(s1, inv_h, push, use_bias, ms, br, isc)
    b2, m2, i2 = _bias(s2, inv_h, push, use_bias, ms, br, isc)
    vn1 = _normal_velocity(wide, o, l, nx, ny, ra1x, ra1y, rb1x, rb1y)
    vn2 = _normal_velocity(wide, o, l, nx, ny, ra2x, ra2y, rb2x, rb2y)
    # the normal-mass matrix K of these arms (the arms move with the bodies: masses computed once
    # at the start of the step would not match them, and a fast body's collision gained energy)
    ma = wide[o + MA + l]
    mb = wide[o + MB + l]
    ia = wide[o + IA + l]
    ib = wide[o + IB + l]
    rn1a = ra1x * ny - ra1y * nx
    rn1b = rb1x * ny - rb1y * nx
    rn2a = ra2x * ny - ra2y * nx
    rn2b = rb2x * ny - rb2y * nx
    real2 = wide[o + NMASS2 + l] > 0.0         # a second point (else the lane has one)
    k11 = ma + mb + ia * rn1a * rn1a + ib * rn1b * rn1b
    k22 = ma + mb + ia * rn2a * rn2a + ib * rn2b * rn2b
    k12 = ma + mb + ia * rn1a * rn2a + ib * rn1b * rn2b
    nm1 = 1.0 / k11 if k11 > 0.0 else 0.0
    nm2 = 1.0 / k22 if (k22 > 0.0 and real2) else 0.0
    det = k11 * k22 - k12 * k12
    inv_det = 1.0 / det if det > 0.0 else 0.0
    old1 = wide[o + PN1 + l]
    old2 = wide[o + PN2 + l]
    leak1 = i1 * (old1 - wide[o + LN1 + l])
    leak2 = i2 * (old2 - wide[o + LN2 + l])
    r1 = m1 * vn1 + b1
    r2 = m2 * vn2 + b2
    # both points at once
    x1 = old1 - (k22 * r1 - k12 * r2) * inv_det - leak1
    x2 = old2 - (k11 * r2 - k12 * r1) * inv_det - leak2
    # one after the other
    y1 = _fmax(0.0, old1 - nm1 * r1 - leak1)
    r2s = m2 * (vn2 + k12 * (y1 - old1)) + b2
    y2 = _fmax(0.0, old2 - nm2 * r2s - leak2)
    block = (real2 and k11 * k11 < MAX_CONDITION * det and x1 >= 0.0 and x2 >= 0.0)
    new1 = x1 if block else y1
    new2 = x2 if block else y2
    wide[o + PN1 + l] = new1
    wide[o + PN2 + l] = new2
    d1 = new1 - old1
    d2 = new2 - old2
    wide[o + TN1 + l] += d1
    wide[o + TN2 + l] += d2
    _apply(wide, o, l, d1 * nx, d1 * ny, ra1x, ra1y, rb1x, rb1y)
    _apply(wide, o, l, d2 * nx, d2 * ny, ra2x, ra2y, rb2x, rb2y)


@wide_inline
def _friction_point(wide, o, l, p, nx, ny):
    """One point's Coulomb friction row, bounded by its current normal impulse."""
    tx = ny
    ty = -nx
    rax, ray, rbx, rby, _, _ = _arms(wide, o, l, p, nx, ny, tx, ty)
    vt = _normal_velocity(wide, o, l, tx, ty, rax, ray, rbx, rby)
    rta = rax * ty - ray * tx
    rtb = rbx * ty - rby * tx
    k = (wide[o + MA + l] + wide[o + MB + l] + wide[o + IA + l] * rta * rta
         + wide[o + IB + l] * rtb * rtb)
    tm = 1.0 / k if (k > 0.0 and wide[o + p + ON1 + l] > 0.0) else 0.0
    old = wide[o + p + PT1 + l]
    limit = wide[o + MU + l] * wide[o + p + PN1 + l]
    new = _fmin(limit, _fmax(-limit, old - tm * vt))
    wide[o + p + PT1 + l] = new
    d = new - old
    wide[o + p + TT1 + l] += d
    _apply(wide, o, l, d * tx, d * ty, rax, ray, rbx, rby)


@wide_inline
def _frictionless(wide, o):
    """Is every lane of the batch frictionless? Then its friction rows would clamp every impulse
    to zero: skipping them changes nothing (the "friction" fast path)."""
    for l in range(_L):
        if wide[o + MU + l] != 0.0:
            return False
    return True


@wide_inline
def _solve_batches(first, last, wide, lane_row, state, inv_h, push, use_bias, friction,
                   skip_frictionless, only_hard, batch_hard):
    for b in range(_U(first), _U(last)):
        if only_hard and not batch_hard[b]:
            continue
        o = b * _STRIDE
        ob = b * _U(2) * _L
        _gather(wide, o, lane_row, ob, state)
        # friction first, bounded by the normal impulses so far; the normal rows last, so that
        # the turn a friction impulse gives a body (it acts below the centre of mass) is taken out
        # before the positions move: solved after the normal rows, the impulse that stops a
        # sliding box tipped it onto its front edge, and it rocked back for a second
        if friction and not (skip_frictionless and _frictionless(wide, o)):
            for l in range(_L):
                nx = wide[o + NX + l]
                ny = wide[o + NY + l]
                _friction_point(wide, o, l, _U(0), nx, ny)
                _friction_point(wide, o, l, _P2, nx, ny)
        for l in range(_L):
            nx = wide[o + NX + l]
            ny = wide[o + NY + l]
            _normal_rows(wide, o, l, nx, ny, inv_h, push, use_bias)
        _scatter(wide, o, lane_row, ob, state)


@wide_kernel
def solve(n_colours, colour_batches, wide, lane_row, state, inv_h, push):
    """One biased sweep over every batch, colour by colour: normal rows only (friction is solved
    in the relax sweeps, as Box2D v3 does: with it here too a sweep cost ~40% more, and no
    test of the physics got better)."""
    for c in range(n_colours):
        _solve_batches(colour_batches[c], colour_batches[c + 1], wide, lane_row, state, inv_h,
                       push, True, False, False, False, lane_row)


@wide_kernel
def relax(n_colours, colour_batches, wide, lane_row, state, inv_h, skip_frictionless):
    """One unbiased sweep (normal and friction rows): removes the bias velocity.
    ``skip_frictionless``: the "friction" fast path (see ``_frictionless``)."""
    for c in range(n_colours):
        _solve_batches(colour_batches[c], colour_batches[c + 1], wide, lane_row, state, inv_h,
                       0.0, False, True, skip_frictionless, False, lane_row)


@wide_kernel
def relax_hard(n_colours, colour_batches, wide, lane_row, state, inv_h, skip_frictionless,
               batch_hard):
    """One more unbiased sweep over the batches flagged hard only (see HARD_RATIO)."""
    for c in range(n_colours):
        _solve_batches(colour_batches[c], colour_batches[c + 1], wide, lane_row, state, inv_h,
                       0.0, False, True, skip_frictionless, True, batch_hard)


@wide_inline
def _restitution_point(wide, o, l, p, nx, ny, threshold):
    """Bounce: drive the normal velocity to -e times the approach speed at the start of the step,
    for points that approached faster than ``threshold`` and carried an impulse."""
    relv = wide[o + p + RELV1 + l]
    e = wide[o + E + l]
    mass = wide[o + p + NMASS1 + l]
    if relv > -threshold or wide[o + p + TN1 + l] == 0.0 or e == 0.0:
        mass = 0.0
    rax, ray, rbx, rby, _, _ = _arms(wide, o, l, p, nx, ny, nx, ny)
    vn = _normal_velocity(wide, o, l, nx, ny, rax, ray, rbx, rby)
    old = wide[o + p + PN1 + l]
    new = _fmax(0.0, old - mass * (vn + e * relv))
    wide[o + p + PN1 + l] = new
    d = new - old
    wide[o + p + TN1 + l] += d
    _apply(wide, o, l, d * nx, d * ny, rax, ray, rbx, rby)


@wide_kernel
def restitution(n_colours, colour_batches, wide, lane_row, state, threshold):
    """Restitution after the substeps: RESTITUTION_SWEEPS sweeps (one sweep leaves a two-point
    manifold's points unequal: the first point's bounce turns the body before the second is
    solved, and a box dropped flat bounced to 3/4 of its height). Batches with no restitution
    are skipped."""
    for _ in range(RESTITUTION_SWEEPS):
        _restitution_sweep(n_colours, colour_batches, wide, lane_row, state, threshold)


@wide_inline
def _restitution_sweep(n_colours, colour_batches, wide, lane_row, state, threshold):
    for c in range(n_colours):
        for b in range(_U(colour_batches[c]), _U(colour_batches[c + 1])):
            o = b * _STRIDE
            bouncy = False
            for l in range(_L):
                bouncy = bouncy or wide[o + E + l] > 0.0
            if not bouncy:
                continue
            ob = b * _U(2) * _L
            _gather(wide, o, lane_row, ob, state)
            for l in range(_L):
                nx = wide[o + NX + l]
                ny = wide[o + NY + l]
                _restitution_point(wide, o, l, _U(0), nx, ny, threshold)
                _restitution_point(wide, o, l, _P2, nx, ny, threshold)
            _scatter(wide, o, lane_row, ob, state)


@wide_kernel
def deepest_separation(n_batches, wide, lane_row, state):
    """m: the deepest separation of any contact point at the end of the step (0 if none
    penetrates): the anchors turned and displaced by the step's motion."""
    deepest = 0.0
    for b in range(_U(n_batches)):
        o = b * _STRIDE
        ob = b * _U(2) * _L
        _gather(wide, o, lane_row, ob, state)
        for l in range(_L):
            nx = wide[o + NX + l]
            ny = wide[o + NY + l]
            for p in (_U(0), _P2):
                if wide[o + p + NMASS1 + l] == 0.0:
                    continue                      # an empty lane or point
                _, _, _, _, dx, dy = _arms(wide, o, l, p, nx, ny, nx, ny)
                deepest = min(deepest, wide[o + p + BASE1 + l] + dx * nx + dy * ny)
    return deepest


@inline_kernel
def _end_separation(wide, o, l, p, nx, ny, state, ra, rb):
    """m: point p's separation at the end of the step (the start separation, plus how the
    anchors moved apart along n with their bodies)."""
    rax = wide[o + p + RAX1 + l]
    ray = wide[o + p + RAY1 + l]
    rbx = wide[o + p + RBX1 + l]
    rby = wide[o + p + RBY1 + l]
    dx = ((state[rb, DPX] - state[ra, DPX]) + (state[rb, DQC] * rbx - state[rb, DQS] * rby)
          - (state[ra, DQC] * rax - state[ra, DQS] * ray))
    dy = ((state[rb, DPY] - state[ra, DPY]) + (state[rb, DQS] * rbx + state[rb, DQC] * rby)
          - (state[ra, DQS] * rax + state[ra, DQC] * ray))
    return wide[o + p + BASE1 + l] + dx * nx + dy * ny


@lean_kernel
def store(counters, contacts, solver, carry_rate, impact_speed):
    """Each lane's impulses back into its contact: the last substep's accumulated impulses (warm
    start), the step's totals (the freeze policies) and the approach velocity (reports); and the
    carried load follows the impulse by ``carry_rate`` of the difference.

    A point that approached faster than ``impact_speed`` m/s at the start of the step was an
    impact: its impulse stopped a motion that is now gone, so it is not warm-started (the next
    step starts the point cold, as a new contact) and is not a load to carry. Warm-started, a
    200 m/s projectile stopped by a wall was kicked to 162 rad/s a step later."""
    pf = contacts.point_float
    wide = solver.wide
    for b in range(counters[N_BATCHES]):
        o = _U(b) * _STRIDE
        for lane in range(LANES):
            s = solver.lane_slot[b * LANES + lane]
            if s < 0:
                continue
            l = _U(lane)
            ob = _U(2 * b * LANES + lane)
            ra = solver.lane_row[ob]
            rb = solver.lane_row[ob + _L]
            nx = wide[o + NX + l]
            ny = wide[o + NY + l]
            for j in range(contacts.contact_int[s, POINT_COUNT]):
                p = _P2 * _U(j)
                pf[s, j, END_SEPARATION] = _end_separation(wide, o, l, p, nx, ny, solver.state,
                                                           ra, rb)
                if wide[o + p + RELV1 + l] < -impact_speed:
                    pf[s, j, WARM_NORMAL] = 0.0
                    pf[s, j, WARM_TANGENT] = 0.0
                else:
                    pf[s, j, WARM_NORMAL] = wide[o + p + PN1 + l]
                    pf[s, j, WARM_TANGENT] = wide[o + p + PT1 + l]
                    pf[s, j, CARRIED] += carry_rate * (wide[o + p + PN1 + l] - pf[s, j, CARRIED])
                pf[s, j, NORMAL_IMPULSE] = wide[o + p + TN1 + l]
                pf[s, j, TANGENT_IMPULSE] = wide[o + p + TT1 + l]
                pf[s, j, NORMAL_VELOCITY] = wide[o + p + RELV1 + l]


@lean_kernel
def unload_bodies(counters, bodies, activity, solver):
    """The step's result into the bodies: velocities, and the start pose plus the displacement."""
    state = solver.state
    for k in range(counters[N_AWAKE]):
        i = activity.awake[k]
        r = k + 1
        bodies.velocity[i, 0] = state[r, VX]
        bodies.velocity[i, 1] = state[r, VY]
        bodies.angular_velocity[i] = state[r, W]
        bodies.position[i, 0] += state[r, DPX]
        bodies.position[i, 1] += state[r, DPY]
        bodies.angle[i] += state[r, TURN]


@inline_kernel
def lane_normal_impulse(wide, e):
    """N s: the accumulated normal impulse of lane e (both points), for convergence tests."""
    b = _U(e // LANES)
    l = _U(e % LANES)
    o = b * _STRIDE
    return wide[o + PN1 + l] + wide[o + PN2 + l]
