"""Packing: every lane of every batch filled from its contact before the substeps (``prepare``),
and the impulses stored back into the contacts after them (``store``)."""

import numpy as np

from ..data import (
    ANCHOR_AX,
    ANCHOR_AY,
    ANCHOR_BX,
    ANCHOR_BY,
    BODY_A,
    BODY_B,
    CARRIED,
    END_SEPARATION,
    FRICTION,
    NORMAL_IMPULSE,
    NORMAL_VELOCITY,
    NORMAL_X,
    NORMAL_Y,
    N_BATCHES,
    N_DEEP_BATCHES,
    N_HARD,
    N_IMPACT_BATCHES,
    POINT_COUNT,
    RESTITUTION,
    SEPARATION,
    SLOP,
    TANGENT_IMPULSE,
    WARM_NORMAL,
    WARM_TANGENT,
)
from ..jit import inline_kernel, lean_kernel
from .arms import line_arms
from .bodies import row_of
from .layout import (
    BASE1,
    BIAS_RATE,
    E,
    FIXED_A,
    IA,
    IB,
    IMPULSE_SCALE,
    LANES,
    LANES_U,
    LN1,
    MA,
    MOVABLE,
    MASS_SCALE,
    MB,
    MU,
    NMASS1,
    NX,
    NY,
    N_FIELDS,
    ON1,
    PN1,
    PN2,
    POINT2,
    POINT_FIELDS,
    PT1,
    RAX1,
    RAY1,
    RBX1,
    RBY1,
    RELV1,
    RNA1,
    RNB1,
    RTA1,
    RTB1,
    SEP1,
    TOWARD,
    STRIDE_U,
    TN1,
    TT1,
    U64,
)
from .parameters import (
    DEEP_SLOPS,
    DEEP_SWEEPS,
    HARD_RATIO,
    IMPACT_SWEEP_SPEED,
    pair_hertz,
    softness,
)


@lean_kernel
def prepare(settings, counters, bodies, contacts, activity, solver):
    """Fill every lane of every batch from its contact: body rows, masses, anchors, softness,
    effective masses, the separation at the start of the step, the relative normal velocity
    (restitution) and the warm-start impulses; and what ``arms.arms`` computes, for the start
    poses, which are the contact's own: an arms pass of its own over the batches cost more than
    these few products here (pyramid(40): 0.012 ms a step, one pass of five). Empty lanes are all
    zero: no effect."""
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
    # the lanes hold the same contacts between the same rows as the step before's (``colour``
    # kept them): what depends only on the pair (bodies, masses, materials, softness) is there
    kept = solver.colour_kept[0]
    for b in range(counters[N_BATCHES]):
        o = U64(b) * STRIDE_U
        for lane in range(LANES):
            l = U64(lane)
            e = b * LANES + lane
            ob = U64(2 * b * LANES + lane)
            s = solver.lane_slot[e]
            if s < 0:  # padding: every field zero, no effect
                solver.lane_row[ob] = U64(0)
                solver.lane_row[ob + LANES_U] = U64(0)
                for f in range(N_FIELDS):
                    wide[o + U64(f) * LANES_U + l] = 0.0
                continue
            a = ci[s, BODY_A]
            bb = ci[s, BODY_B]
            if kept:
                ma = wide[o + MA + l]
                ia = wide[o + IA + l]
                mb = wide[o + MB + l]
                ib = wide[o + IB + l]
            else:
                solver.lane_row[ob] = U64(row_of(a, n_dyn, awake_slot))
                solver.lane_row[ob + LANES_U] = U64(row_of(bb, n_dyn, awake_slot))
                ma = inv_mass[a] if a >= 0 else 0.0
                ia = inv_inertia[a] if a >= 0 else 0.0
                mb = inv_mass[bb]
                ib = inv_inertia[bb]
                wide[o + MU + l] = cf[s, FRICTION]
                wide[o + E + l] = cf[s, RESTITUTION]
                wide[o + MA + l] = ma
                wide[o + IA + l] = ia
                wide[o + MB + l] = mb
                wide[o + IB + l] = ib
            nx = cf[s, NORMAL_X]
            ny = cf[s, NORMAL_Y]
            wide[o + NX + l] = nx
            wide[o + NY + l] = ny
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
            toward = _toward(wa, wb, ia, ib)
            wide[o + TOWARD + l] = toward
            n_points = ci[s, POINT_COUNT]
            for j in range(2):
                p = POINT2 * U64(j)
                if j >= n_points:  # a one-point lane: its second point is void
                    for f in range(POINT_FIELDS):
                        wide[o + p + RAX1 + U64(f) * LANES_U + l] = 0.0
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
                wide[o + p + BASE1 + l] = pf[s, j, SEPARATION] - (
                    (rbx - rax) * nx + (rby - ray) * ny
                )
                # the arms pass of the start poses (nothing has moved: the anchors lie the start
                # separation apart along n): what the first sweeps read (arms.arms). The
                # separation is summed as that pass sums it, not taken from the contact's: the two
                # differ by rounding, and a box coming to rest on a ledge is sensitive to it at
                # s = 0, where the contact switches from soft to speculative (with the contact's
                # value it hovered 0.4 nm above the ledge after 3 s, still sinking at 1e-7 m/s)
                sep = wide[o + p + BASE1 + l] + (rbx - rax) * nx + (rby - ray) * ny
                rna, rnb = line_arms(rax, ray, rbx, rby, sep * nx, sep * ny, nx, ny, toward)
                rta, rtb = line_arms(rax, ray, rbx, rby, sep * nx, sep * ny, ny, -nx, 0.5)
                wide[o + p + RNA1 + l] = rna
                wide[o + p + RNB1 + l] = rnb
                wide[o + p + RTA1 + l] = rta
                wide[o + p + RTB1 + l] = rtb
                wide[o + p + SEP1 + l] = sep
                k_normal = ma + mb + ia * rna * rna + ib * rnb * rnb
                # the point's mass at the start of the step (restitution's; the rows recompute
                # theirs from their arms each sweep)
                wide[o + p + NMASS1 + l] = 1.0 / k_normal if k_normal > 0.0 else 0.0
                wide[o + p + ON1 + l] = 1.0 if k_normal > 0.0 else 0.0  # the point exists
                pn = warm * pf[s, j, WARM_NORMAL]
                pt = warm * pf[s, j, WARM_TANGENT]
                wide[o + p + PN1 + l] = pn
                wide[o + p + PT1 + l] = pt
                # the step's totals start at minus the first warm start, which adds it back: see
                # TOTALS in batches
                wide[o + p + TN1 + l] = -pn
                wide[o + p + TT1 + l] = -pt
                wide[o + p + LN1 + l] = warm * pf[s, j, CARRIED]
                dvx = vbx - wb * rby - vax + wa * ray
                dvy = vby + wb * rbx - vay - wa * rax
                wide[o + p + RELV1 + l] = dvx * nx + dvy * ny
            if kept:
                continue
            immovable = (ma == 0.0 and ia == 0.0) or (mb == 0.0 and ib == 0.0)
            size = bodies.size[bb] if a < 0 else min(bodies.size[a], bodies.size[bb])
            hertz = pair_hertz(settings.contact_hertz, size, g, h, immovable)
            bias_rate, mass_scale, impulse_scale = softness(hertz, settings.damping_ratio, h)
            wide[o + BIAS_RATE + l] = bias_rate
            wide[o + MASS_SCALE + l] = mass_scale
            wide[o + IMPULSE_SCALE + l] = impulse_scale
        if not kept:  # else the rows and masses are the step before's, and so is the kind
            solver.batch_kind[b] = _kind(wide, o, solver.lane_row, U64(2 * b * LANES))
    n_batches = counters[N_BATCHES]
    # no contact can be hard without mixed masses (validation.mixed_masses)
    found = settings.mixed_masses and _mark_hard_rows(n_batches, wide, solver)
    counters[N_HARD] = _flag_batches(n_batches, found, solver, solver.batch_hard)
    # the impact sweeps' batches (IMPACT_SWEEP_SPEED), hard ones left out (see there)
    found = settings.impact_iterations > 0 and _mark_impact_rows(n_batches, wide, solver)
    counters[N_IMPACT_BATCHES] = _flag_batches(n_batches, found, solver, solver.batch_impact)
    # the deep contacts' batches (DEEP_SLOPS), hard ones left out
    found = DEEP_SWEEPS > 0 and _mark_deep_rows(n_batches, wide, solver, cf)
    counters[N_DEEP_BATCHES] = _flag_batches(n_batches, found, solver, solver.batch_deep)
    if counters[N_HARD] > 0:
        counters[N_IMPACT_BATCHES] -= _unflag_hard(n_batches, solver, solver.batch_impact)
        counters[N_DEEP_BATCHES] -= _unflag_hard(n_batches, solver, solver.batch_deep)


@inline_kernel
def _fixed(wide, o, lane_row, ob, mass, inertia):
    """Is one side (its lane rows from ``ob``, its inverse mass and inertia fields ``mass``,
    ``inertia``) of every lane of the batch at ``o`` immovable: the dummy row 0, zero mass and
    inertia? (Padding lanes are.)"""
    for lane in range(LANES):
        l = U64(lane)
        if lane_row[ob + l] != 0 or wide[o + mass + l] != 0.0 or wide[o + inertia + l] != 0.0:
            return False
    return True


#: rad/s: below this, two bodies share a contact's line shift about equally (``_toward``)
SPIN_SCALE = 1.0


@inline_kernel
def _toward(wa, wb, ia, ib):
    """How far A's lever arms move across an impulse towards B's anchor (``arms.line_arms``; B's
    move the rest of the way): B's share of the turning, (|wB| + w0) / (|wA| + |wB| + 2 w0), by the
    angular velocities at the start of the step (rad/s). So a body turning fast alone keeps its own
    anchor, and a fixed body does not shift a fast-turning one's. Bodies turning slower than w0 =
    SPIN_SCALE share it about half and half, as resting ones always did: their shifts are small and
    their arms' errors too, and a share set by the noise in two nearly zero rates would change from
    step to step.

    Against a body the solver cannot turn (the floor, a static or a frozen body: inverse inertia
    0) the movable one keeps its own anchor, whatever the rates: the shift is there to keep the
    angular momentum of a pair, and an immovable body takes any impulse whole. Shared half and
    half there (until 2026-12-07), a body sliding fast along the floor had its arms moved half
    way back to where its contact began, as far as it had slid in the step: a frictionless box at
    100 m/s got 96% of its weight's support in its first step, and at 1000 m/s 27%, tilted and
    sank 14 mm in 2 s."""
    if ia <= 0.0:
        return 1.0
    if ib <= 0.0:
        return 0.0
    return (abs(wb) + SPIN_SCALE) / (abs(wa) + abs(wb) + 2.0 * SPIN_SCALE)


@inline_kernel
def _kind(wide, o, lane_row, ob):
    """The batch's kind (layout.MOVABLE, FIXED_A; see there)."""
    return FIXED_A if _fixed(wide, o, lane_row, ob, MA, IA) else MOVABLE


@inline_kernel
def _unflag_hard(n_batches, solver, flags):
    """Clear ``flags`` of the hard batches (Solver.batch_hard); returns how many were set."""
    n = 0
    for b in range(n_batches):
        if solver.batch_hard[b] and flags[b]:
            flags[b] = False
            n += 1
    return n


@inline_kernel
def _mark_lane_rows(solver, b, lane):
    """Mark (solver.row_mark) the rows of both bodies of lane ``lane`` of batch b."""
    ob = U64(2 * b * LANES + lane)
    solver.row_mark[solver.lane_row[ob]] = True
    solver.row_mark[solver.lane_row[ob + LANES_U]] = True


@inline_kernel
def _mark_hard_rows(n_batches, wide, solver):
    """Mark the rows of both bodies of every contact of mass ratio > HARD_RATIO (both bodies
    movable); returns whether any was."""
    found = False
    for b in range(n_batches):
        o = U64(b) * STRIDE_U
        for lane in range(LANES):
            l = U64(lane)
            ma = wide[o + MA + l]
            mb = wide[o + MB + l]
            if ma > 0.0 and mb > 0.0 and (ma > HARD_RATIO * mb or mb > HARD_RATIO * ma):
                _mark_lane_rows(solver, b, lane)
                found = True
    return found


@inline_kernel
def _mark_deep_rows(n_batches, wide, solver, cf):
    """Mark the rows of both bodies of every contact with a point deeper than DEEP_SLOPS times
    its pair's slop (``cf``: the contacts' floats) at the start of the step (see there); returns
    whether any was."""
    found = False
    for b in range(n_batches):
        o = U64(b) * STRIDE_U
        for lane in range(LANES):
            s = solver.lane_slot[b * LANES + lane]
            if s < 0:
                continue
            l = U64(lane)
            deep = -DEEP_SLOPS * cf[s, SLOP]
            # a void point (ON = 0) has every field zero: its separation reads 0
            if min(wide[o + SEP1 + l], wide[o + POINT2 + SEP1 + l]) < deep:
                _mark_lane_rows(solver, b, lane)
                found = True
    return found


@inline_kernel
def _mark_impact_rows(n_batches, wide, solver):
    """Mark the rows of both bodies of every contact with a point that approached faster than
    IMPACT_SWEEP_SPEED at the start of the step (see there); returns whether any did."""
    found = False
    for b in range(n_batches):
        o = U64(b) * STRIDE_U
        for lane in range(LANES):
            l = U64(lane)
            # a void point (ON = 0) has every field zero: its approach speed reads 0
            if min(wide[o + RELV1 + l], wide[o + POINT2 + RELV1 + l]) < -IMPACT_SWEEP_SPEED:
                _mark_lane_rows(solver, b, lane)
                found = True
    return found


@inline_kernel
def _flag_batches(n_batches, found, solver, flags):
    """Flag (``flags``) the batches with a lane touching a marked movable row, clear the marks;
    returns how many batches are flagged. ``found``: whether any row is marked."""
    n_flagged = 0
    for b in range(n_batches):
        flagged = False
        if found:
            for lane in range(LANES):
                ob = U64(2 * b * LANES + lane)
                ra = solver.lane_row[ob]
                rb = solver.lane_row[ob + LANES_U]
                flagged = (
                    flagged or (ra > 0 and solver.row_mark[ra]) or (rb > 0 and solver.row_mark[rb])
                )
        flags[b] = flagged
        n_flagged += 1 if flagged else 0
    if found:
        for b in range(n_batches):
            for lane in range(LANES):
                ob = U64(2 * b * LANES + lane)
                solver.row_mark[solver.lane_row[ob]] = False
                solver.row_mark[solver.lane_row[ob + LANES_U]] = False
    return n_flagged


@inline_kernel
def _split_at_once(pf, s, impulse1, impulse2):
    """A two-point manifold on an immovable body: its carried load's total keeps following
    slowly (``store``), its split between the two points follows ``impulse1 - impulse2`` (N s) at
    once.

    Why. A box sliding on the floor carries more on its front point (friction acts below its
    centre of mass and pitches it forward: 0.7 / 0.3 of its weight at mu 0.4). When it stops, a
    rigid contact shares the weight evenly at once; with the split carried slowly, the soft
    springs took the change instead, the box rocked back onto its rear point (1.8e-5 rad) and
    crept forward at 2.4e-6 m/s two seconds later, returning over LOAD_TIME (measured: 2.3e-9 m/s
    with the split at once). Only against an immovable body: between two movable bodies the split
    is a rocking mode of the pair that the soft spring damps, and followed at once there a
    dropped 100:1 stack kept 17 mm of overlap instead of 2.1 mm (and, measured by an earlier
    version away from mass ratios, pyramid(40) rocked twice as fast). The split is clamped to
    the total, so that neither point carries a negative load."""
    total = pf[s, 0, CARRIED] + pf[s, 1, CARRIED]
    split = min(total, max(-total, impulse1 - impulse2))
    pf[s, 0, CARRIED] = 0.5 * (total + split)
    pf[s, 1, CARRIED] = 0.5 * (total - split)


@lean_kernel
def store(counters, contacts, solver, carry_rate, impact_speed):
    """Each lane's impulses back into its contact: the last substep's accumulated impulses (warm
    start), the step's totals (the freeze policies) and the approach velocity (reports); and the
    carried load follows the impulse by ``carry_rate`` of the difference (on an immovable body,
    a two-point manifold's split between its points at once: ``_split_at_once``).

    A point that approached faster than ``impact_speed`` m/s at the start of the step was an
    impact: its impulse stopped a motion that is now gone, so it is not warm-started (the next
    step starts the point cold, as a new contact) and is not a load to carry. Warm-started, a
    200 m/s projectile stopped by a wall was kicked to 162 rad/s a step later."""
    pf = contacts.point_float
    wide = solver.wide
    for b in range(counters[N_BATCHES]):
        o = U64(b) * STRIDE_U
        for lane in range(LANES):
            s = solver.lane_slot[b * LANES + lane]
            if s < 0:
                continue
            l = U64(lane)
            n_points = contacts.contact_int[s, POINT_COUNT]
            for j in range(n_points):
                p = POINT2 * U64(j)
                # the last arms pass ran on the end-of-step poses (the presolve's on the start)
                pf[s, j, END_SEPARATION] = wide[o + p + SEP1 + l]
                if wide[o + p + RELV1 + l] < -impact_speed:
                    pf[s, j, WARM_NORMAL] = 0.0
                    pf[s, j, WARM_TANGENT] = 0.0
                else:
                    pf[s, j, WARM_NORMAL] = wide[o + p + PN1 + l]
                    pf[s, j, WARM_TANGENT] = wide[o + p + PT1 + l]
                    pf[s, j, CARRIED] += carry_rate * (wide[o + p + PN1 + l] - pf[s, j, CARRIED])
                # the step's totals (TOTALS in batches)
                pf[s, j, NORMAL_IMPULSE] = wide[o + p + TN1 + l] + wide[o + p + PN1 + l]
                pf[s, j, TANGENT_IMPULSE] = wide[o + p + TT1 + l] + wide[o + p + PT1 + l]
                pf[s, j, NORMAL_VELOCITY] = wide[o + p + RELV1 + l]
            if (
                n_points == 2
                and (wide[o + MA + l] == 0.0 or wide[o + MB + l] == 0.0)
                and wide[o + RELV1 + l] >= -impact_speed
                and wide[o + POINT2 + RELV1 + l] >= -impact_speed
            ):
                _split_at_once(pf, s, wide[o + PN1 + l], wide[o + POINT2 + PN1 + l])


@inline_kernel
def lane_normal_impulse(wide, e):
    """N s: the accumulated normal impulse of lane e (both points), for convergence tests."""
    b = U64(e // LANES)
    l = U64(e % LANES)
    o = b * STRIDE_U
    return wide[o + PN1 + l] + wide[o + PN2 + l]
