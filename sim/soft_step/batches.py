"""The batch kernels: the arms pass (once per pose), warm start, the biased solve, the relax
sweeps, restitution, each over whole batches of LANES contacts: gather the batch's body rows,
compute every lane at once (packed vector instructions), scatter the velocities back."""

from ..data import VX, VY, W
from ..jit import wide_inline, wide_kernel
from .layout import (
    APPROACH1,
    APPROACH2,
    BIAS_RATE,
    E,
    FIXED_A,
    IA,
    IB,
    IMPULSE_SCALE,
    LANES_U,
    LN1,
    LN2,
    MA,
    MASS_SCALE,
    MB,
    MU,
    NMASS1,
    NX,
    NY,
    ON1,
    ON2,
    PN1,
    PN2,
    POINT2,
    PT1,
    RNA1,
    RNA2,
    RNB1,
    RNB2,
    RTA1,
    RTB1,
    SEP1,
    SEP2,
    STRIDE_U,
    TN1,
    TN2,
    TT1,
    U64,
    VAX,
    VAY,
    VBX,
    VBY,
    WA,
    WB,
)
from .bounce import approach, has_restitution, mark_held
from .parameters import MAX_CONDITION, RESTITUTION_SWEEPS


#: FIXED SIDE. The sweeps and the arms pass take a compile-time flag ``fa``: body A of every lane
#: of the batch cannot move (``layout.FIXED_A``: the floor, which is A of its pairs). Its
#: velocity, displacement, inverse mass and inertia are exact zeros and its rotation the
#: identity, so every term they enter is an exact zero or leaves the other factor unchanged, and
#: leaving those terms out gives the same numbers (up to the sign of a zero result;
#: ``test_fixed_sides`` checks each kernel to the bit): the batch's A fields (masses, lever arms,
#: gathered rows) are then never read or written. Each such kernel is compiled twice over and
#: LLVM removes the branches on the flag. Not done for B (a static body): there the shorter sums
#: came out in another order under fused multiply-adds (the last bit of an impulse, in 1 of 8
#: lanes). The flagged sweeps and restitution keep the general rows on every batch (on a FIXED_A
#: batch they read A's arms as ``prepare`` left them, finite, times A's zero masses).


@wide_inline
def _gather_velocities(wide, o, lane_row, ob, state, fa):
    """The batch's body velocities into its fields (what the sweeps change)."""
    for l in range(LANES_U):
        if not fa:
            ra = lane_row[ob + l]
            wide[o + VAX + l] = state[ra, VX]
            wide[o + VAY + l] = state[ra, VY]
            wide[o + WA + l] = state[ra, W]
        rb = lane_row[ob + LANES_U + l]
        wide[o + VBX + l] = state[rb, VX]
        wide[o + VBY + l] = state[rb, VY]
        wide[o + WB + l] = state[rb, W]


@wide_inline
def _scatter(wide, o, lane_row, ob, state, fa):
    """The batch's new velocities back into the body rows. Lanes of one colour share no movable
    body; the dummy row 0 is written by several lanes, all with its unchanged zeros (a zero mass
    never changes a velocity)."""
    for l in range(LANES_U):
        if not fa:
            ra = lane_row[ob + l]
            state[ra, VX] = wide[o + VAX + l]
            state[ra, VY] = wide[o + VAY + l]
            state[ra, W] = wide[o + WA + l]
        rb = lane_row[ob + LANES_U + l]
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
def _apply(wide, o, l, d, dirx, diry, rca, rcb, fa):
    """Impulse d along (dirx, diry) on B and its reaction on A, at arms whose cross products with
    the direction are rca (A's) and rcb (B's), into the batch's velocity fields."""
    if not fa:
        wide[o + VAX + l] -= wide[o + MA + l] * d * dirx
        wide[o + VAY + l] -= wide[o + MA + l] * d * diry
        wide[o + WA + l] -= wide[o + IA + l] * d * rca
    wide[o + VBX + l] += wide[o + MB + l] * d * dirx
    wide[o + VBY + l] += wide[o + MB + l] * d * diry
    wide[o + WB + l] += wide[o + IB + l] * d * rcb


@wide_inline
def _relative_velocity(wide, o, l, dirx, diry, rca, rcb, fa):
    """B's contact point's velocity minus A's along (dirx, diry): (vB - vA) . dir + wB rcb - wA rca
    (w x r . dir = w (r x dir)); a fixed A's (zero) terms left out (FIXED SIDE)."""
    if fa:
        return wide[o + VBX + l] * dirx + wide[o + VBY + l] * diry + wide[o + WB + l] * rcb
    return (
        (wide[o + VBX + l] - wide[o + VAX + l]) * dirx
        + (wide[o + VBY + l] - wide[o + VAY + l]) * diry
        + wide[o + WB + l] * rcb
        - wide[o + WA + l] * rca
    )


@wide_inline
def _mass_term(wide, o, l, ra1, ra2, rb1, rb2, fa):
    """mA + mB + iA ra1 ra2 + iB rb1 rb2: with ra1 = ra2, rb1 = rb2 the inverse effective mass of
    one row (arms crossed with its direction), else the coupling of two rows; a fixed A's (zero)
    terms left out (FIXED SIDE)."""
    if fa:
        return wide[o + MB + l] + wide[o + IB + l] * rb1 * rb2
    return (
        wide[o + MA + l]
        + wide[o + MB + l]
        + wide[o + IA + l] * ra1 * ra2
        + wide[o + IB + l] * rb1 * rb2
    )


#: TOTALS. The step's total impulse of a point (what the freeze policies read, N s) is what its
#: substeps applied. A substep applies its warm start plus what its sweeps change, which is the
#: accumulated impulse at its end: the total is the sum of those over the substeps. The sweeps
#: therefore leave the totals alone. The warm start of each substep adds the impulse the substep
#: before ended with (TN, TT), ``store`` adds the last substep's, and ``prepare`` starts the totals
#: at minus the first warm start (the previous step's end, which is not a substep of this one).
#: Updated in every sweep instead, the totals cost a read and a write of four fields of every
#: batch per sweep.


@wide_inline
def _arm(wide, o, l, field, fixed):
    """A lever arm's cross product from the batch, or 0 for a fixed side (FIXED SIDE: never
    read then, as every term it enters is left out)."""
    return 0.0 if fixed else wide[o + field + l]


@wide_inline
def _warm_point(wide, o, l, p, nx, ny, fa):
    pn = wide[o + p + PN1 + l]
    pt = wide[o + p + PT1 + l]
    wide[o + p + TN1 + l] += pn  # TOTALS
    wide[o + p + TT1 + l] += pt
    # the normal and the friction impulse each on its own line (see line_arms)
    rna = _arm(wide, o, l, p + RNA1, fa)
    rnb = wide[o + p + RNB1 + l]
    rta = _arm(wide, o, l, p + RTA1, fa)
    rtb = wide[o + p + RTB1 + l]
    _apply(wide, o, l, pn, nx, ny, rna, rnb, fa)
    _apply(wide, o, l, pt, ny, -nx, rta, rtb, fa)


@wide_kernel
def warm_start(n_colours, colour_batches, wide, lane_row, state, batch_kind):
    """Apply each point's accumulated impulses (normal and friction) from the last substep,
    colour by colour (the order of the additions to a body's velocity is the batches' order:
    see _by_kind)."""
    for c in range(n_colours):
        first = U64(colour_batches[c])
        last = U64(colour_batches[c + 1])
        for b in range(first, last):
            if _of_kind(batch_kind, b, False):
                _warm_batch(wide, b, lane_row, state, False)
        for b in range(first, last):
            if _of_kind(batch_kind, b, True):
                _warm_batch(wide, b, lane_row, state, True)


@wide_inline
def _of_kind(batch_kind, b, fa):
    """Is batch b FIXED_A (``fa``) or MOVABLE (not ``fa``)?

    _by_kind. A sweep goes colour by colour, and in each colour first over the MOVABLE batches,
    then over the FIXED_A ones, each in a loop of its own: dispatched batch by batch in one loop
    instead, pyramid(40)'s step (nearly all MOVABLE) was 3-5% slower. Within a colour no two
    lanes share a body the solver moves, so the order of its batches changes no number; across
    colours the order stays the colours'."""
    return (batch_kind[b] == FIXED_A) == fa


@wide_inline
def _warm_batch(wide, b, lane_row, state, fa):
    o = b * STRIDE_U
    ob = b * U64(2) * LANES_U
    _gather_velocities(wide, o, lane_row, ob, state, fa)
    for l in range(LANES_U):
        nx = wide[o + NX + l]
        ny = wide[o + NY + l]
        _warm_point(wide, o, l, U64(0), nx, ny, fa)
        _warm_point(wide, o, l, POINT2, nx, ny, fa)
    _scatter(wide, o, lane_row, ob, state, fa)


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
def two_row_impulses(a1, a2, r1, r2, k11, k12, k22, real2):
    """The new impulses of a lane's two rows, >= 0, solved exactly as the 2x2 linear
    complementarity problem they are: with d = new - a, the residuals w = r + K d must be >= 0,
    each zero where its impulse is not (a: the impulses the rows start from, N s; r: their
    residuals before this update, m/s; K: their inverse mass matrix, 1/kg). Its four cases are
    all computed and one selected (branch-free): both pushing (the block, accepted when K is well
    conditioned and both stay >= 0); one pushing with the other released (its impulse taken
    away, and the row that is left seeing that through K12), accepted when the released row is
    not pulled (w >= 0); both as one row, where K is too near singular for the block and neither
    point alone holds (see there); neither. A one-point lane (``real2`` False, its second row
    void) is its first point's row alone.

    Solving the points one after the other instead (this module did until 2026-12) gives a
    symmetric landing unequal impulses: a column of boxes dropped onto each other rocked,
    tilting 1.6e-3 rad, and ended 8.8 mm to one side (dt 1/480), and a box dropped flat with
    restitution 0.9 bounced off turning."""
    det = k11 * k22 - k12 * k12
    inv_det = 1.0 / det if det > 0.0 else 0.0
    nm1 = 1.0 / k11 if k11 > 0.0 else 0.0
    nm2 = 1.0 / k22 if (k22 > 0.0 and real2) else 0.0
    x1 = a1 - (k22 * r1 - k12 * r2) * inv_det
    x2 = a2 - (k11 * r2 - k12 * r1) * inv_det
    d1 = nm1 * (r1 - k12 * a2)
    d2 = nm2 * (r2 - k12 * a1)
    s1 = a1 - d1
    s2 = a2 - d2
    w2 = r2 - k12 * d1 - k22 * a2
    w1 = r1 - k12 * d2 - k11 * a1
    lone = not real2
    conditioned = k11 * k11 < MAX_CONDITION * det
    block = real2 & conditioned & (x1 >= 0.0) & (x2 >= 0.0)
    only1 = (s1 >= 0.0) & ((w2 >= 0.0) | lone)
    # point 1's case wins a tie: with a near-singular K (the points nearly one) both cases can
    # hold, and taking both would apply the load twice
    only2 = real2 & (s2 >= 0.0) & (w1 >= 0.0) & (not only1)
    # Both rows as one, when K is too near singular for the block and neither point alone
    # holds: the two rows are then nearly the same row (a plank on its end, two points of a
    # many-sided polygon a few mm apart), so they share one impulse, half at each point, sized
    # so that their mean residual is zero. Answering "neither" there instead, a 0.1 x 11 m plank
    # standing on its end and a 300-sided polygon fell through the floor as if it were not
    # there: both points need to push, and each alone leaves the other pulled by round-off.
    merged = real2 & (not conditioned) & (not only1) & (not only2)
    km = k11 + 2.0 * k12 + k22  # e K e for e = (1, 1): > 0 for any two real rows
    # (km is not > 0 only when a row is NaN, which then comes through, as below)
    total = 2.0 * ((k11 + k12) * a1 + (k12 + k22) * a2 - r1 - r2) / km if km > 0.0 else 0.0 * km
    half = 0.5 * _fmax(0.0, total)
    # neither: 0, except that a NaN in the rows comes through (as _fmax carries it), for the
    # World's check of the bodies to report where it began
    none1 = 0.0 * _fmax(0.0, s1)
    none2 = 0.0 * _fmax(0.0, s2)
    new1 = x1 if block else (s1 if only1 else (half if merged else none1))
    new2 = x2 if block else (s2 if only2 else (half if merged else none2))
    return new1, new2


@wide_inline
def _normal_rows(wide, o, l, nx, ny, inv_h, push, use_bias, fa):
    """Both points' non-penetration rows of a lane.

    Solved point by point, the first point's impulse turns the body before the second is
    solved: a box resting on a face rocks, and the rocking grows in tall stacks. So a two-point
    lane is solved as one 2x2 problem (``two_row_impulses``; Box2D v2's block solver, here with
    soft rows): both impulses at once, Delta = -K^-1 (mass_scale vn + bias) - impulse_scale
    (impulse - carried) when both stay >= 0, else the exact answer with one point or neither
    pushing. The arms are those of the current poses (``arms``)."""
    ms = wide[o + MASS_SCALE + l]
    br = wide[o + BIAS_RATE + l]
    isc = wide[o + IMPULSE_SCALE + l]
    b1, m1, i1 = _bias(wide[o + SEP1 + l], inv_h, push, use_bias, ms, br, isc)
    b2, m2, i2 = _bias(wide[o + SEP2 + l], inv_h, push, use_bias, ms, br, isc)
    rn1a = _arm(wide, o, l, RNA1, fa)
    rn1b = wide[o + RNB1 + l]
    rn2a = _arm(wide, o, l, RNA2, fa)
    rn2b = wide[o + RNB2 + l]
    vn1 = _relative_velocity(wide, o, l, nx, ny, rn1a, rn1b, fa)
    vn2 = _relative_velocity(wide, o, l, nx, ny, rn2a, rn2b, fa)
    # the normal-mass matrix K of these arms (the arms move with the bodies: masses computed once
    # at the start of the step would not match them, and a fast body's collision gained energy)
    real2 = wide[o + ON2 + l] > 0.0  # a second point (else the lane has one)
    k11 = _mass_term(wide, o, l, rn1a, rn1a, rn1b, rn1b, fa)
    k22 = _mass_term(wide, o, l, rn2a, rn2a, rn2b, rn2b, fa)
    k12 = _mass_term(wide, o, l, rn1a, rn2a, rn1b, rn2b, fa)
    old1 = wide[o + PN1 + l]
    old2 = wide[o + PN2 + l]
    leak1 = i1 * (old1 - wide[o + LN1 + l])
    leak2 = i2 * (old2 - wide[o + LN2 + l])
    r1 = m1 * vn1 + b1
    r2 = m2 * vn2 + b2
    new1, new2 = two_row_impulses(old1 - leak1, old2 - leak2, r1, r2, k11, k12, k22, real2)
    wide[o + PN1 + l] = new1
    wide[o + PN2 + l] = new2
    _apply(wide, o, l, new1 - old1, nx, ny, rn1a, rn1b, fa)
    _apply(wide, o, l, new2 - old2, nx, ny, rn2a, rn2b, fa)


@wide_inline
def _friction_point(wide, o, l, p, nx, ny, fa):
    """One point's Coulomb friction row, bounded by its current normal impulse."""
    rta = _arm(wide, o, l, p + RTA1, fa)
    rtb = wide[o + p + RTB1 + l]
    vt = _relative_velocity(wide, o, l, ny, -nx, rta, rtb, fa)
    k = _mass_term(wide, o, l, rta, rta, rtb, rtb, fa)
    tm = 1.0 / k if (k > 0.0 and wide[o + p + ON1 + l] > 0.0) else 0.0
    old = wide[o + p + PT1 + l]
    limit = wide[o + MU + l] * wide[o + p + PN1 + l]
    new = _fmin(limit, _fmax(-limit, old - tm * vt))
    wide[o + p + PT1 + l] = new
    _apply(wide, o, l, new - old, ny, -nx, rta, rtb, fa)


@wide_inline
def _frictionless(wide, o):
    """Is every lane of the batch frictionless? Then its friction rows would clamp every impulse
    to zero: skipping them changes nothing (the "friction" fast path)."""
    for l in range(LANES_U):
        if wide[o + MU + l] != 0.0:
            return False
    return True


@wide_inline
def _solve_batch(wide, b, lane_row, state, inv_h, push, rows, fa):
    """One batch's rows. ``rows``: (use_bias, friction, skip_frictionless), see _sweep."""
    use_bias, friction, skip_frictionless = rows
    o = b * STRIDE_U
    ob = b * U64(2) * LANES_U
    _gather_velocities(wide, o, lane_row, ob, state, fa)
    # friction first, bounded by the normal impulses so far; the normal rows last, so that
    # the turn a friction impulse gives a body (it acts below the centre of mass) is taken out
    # before the positions move: solved after the normal rows, the impulse that stops a
    # sliding box tipped it onto its front edge, and it rocked back for a second
    if friction and not (skip_frictionless and _frictionless(wide, o)):
        for l in range(LANES_U):
            nx = wide[o + NX + l]
            ny = wide[o + NY + l]
            _friction_point(wide, o, l, U64(0), nx, ny, fa)
            _friction_point(wide, o, l, POINT2, nx, ny, fa)
    for l in range(LANES_U):
        nx = wide[o + NX + l]
        ny = wide[o + NY + l]
        _normal_rows(wide, o, l, nx, ny, inv_h, push, use_bias, fa)
    _scatter(wide, o, lane_row, ob, state, fa)


@wide_inline
def _sweep(n_colours, colour_batches, wide, lane_row, state, batch_kind, inv_h, push, rows):
    """One sweep over every batch, colour by colour, and in each colour over its MOVABLE, then
    its FIXED_A batches (_by_kind). ``rows``: (use_bias, friction, skip_frictionless): the soft
    bias, the friction rows, and the "friction" fast path (``_frictionless``)."""
    for c in range(n_colours):
        first = U64(colour_batches[c])
        last = U64(colour_batches[c + 1])
        for b in range(first, last):
            if _of_kind(batch_kind, b, False):
                _solve_batch(wide, b, lane_row, state, inv_h, push, rows, False)
        for b in range(first, last):
            if _of_kind(batch_kind, b, True):
                _solve_batch(wide, b, lane_row, state, inv_h, push, rows, True)


@wide_inline
def _flagged_sweep(n_colours, colour_batches, wide, lane_row, state, inv_h, push, rows, flags):
    """One sweep over the batches ``flags`` marks, colour by colour, all with the general rows:
    these sweeps (few batches, in a few steps) are compiled once, not once per kind."""
    for c in range(n_colours):
        for b in range(U64(colour_batches[c]), U64(colour_batches[c + 1])):
            if flags[b]:
                _solve_batch(wide, b, lane_row, state, inv_h, push, rows, False)


@wide_kernel
def solve(n_colours, colour_batches, wide, lane_row, state, batch_kind, inv_h, push):
    """One biased sweep over every batch, colour by colour: normal rows only (friction is solved
    in the relax sweeps, as Box2D v3 does: with it here too a sweep cost ~40% more, and no
    test of the physics got better)."""
    rows = (True, False, False)
    _sweep(n_colours, colour_batches, wide, lane_row, state, batch_kind, inv_h, push, rows)


@wide_kernel
def solve_impact(n_colours, colour_batches, wide, lane_row, state, inv_h, push, batch_impact):
    """One more biased sweep, with friction rows, over the batches flagged as touching a body in an
    impact (see IMPACT_SWEEP_SPEED)."""
    rows = (True, True, False)
    _flagged_sweep(
        n_colours, colour_batches, wide, lane_row, state, inv_h, push, rows, batch_impact
    )


@wide_kernel
def relax(n_colours, colour_batches, wide, lane_row, state, batch_kind, inv_h, skip_frictionless):
    """One unbiased sweep (normal and friction rows): removes the bias velocity.
    ``skip_frictionless``: the "friction" fast path (see ``_frictionless``)."""
    rows = (False, True, skip_frictionless)
    _sweep(n_colours, colour_batches, wide, lane_row, state, batch_kind, inv_h, 0.0, rows)


@wide_kernel
def relax_hard(
    n_colours, colour_batches, wide, lane_row, state, inv_h, skip_frictionless, batch_hard
):
    """One more unbiased sweep over the batches flagged hard only (see HARD_RATIO)."""
    rows = (False, True, skip_frictionless)
    _flagged_sweep(n_colours, colour_batches, wide, lane_row, state, inv_h, 0.0, rows, batch_hard)


@wide_inline
def _approaches(n_batches, wide, lane_row, gravity_x, gravity_y, held, start):
    """Each point's approach speed for the bounce into the batch's scratch fields APPROACH1 and
    APPROACH2 (free while the sweeps hold velocities), once before the sweeps (they do not change
    it): ``bounce.approach``, where the point is now, reached in free flight; gravity accelerates
    a body that is movable and not held up by another contact (``bounce.mark_held``), so two
    falling bodies fall together and a box falls onto a box resting on the floor as onto the
    floor. On rest_row(5000) with every box bouncy the restitution stage takes 0.24 ms a step (0.18
    before the approach was carried forward; 0.32 computed in every sweep instead).

    The velocity it starts from is the bodies' at the start of the step (``start``: velocity,
    angular_velocity and awake, still the step's start until the bodies are unloaded) read at
    the point's arms now (RNA, RNB), where the bounce measures and pushes: with e = 1 it gives
    back the energy it took only so (ARCHITECTURE section 2.3; at the start's arms, RELV, a
    tilted box dropped from 3 m rose to 5 m)."""
    velocity, angular_velocity, awake = start
    for b in range(n_batches):
        o = b * STRIDE_U
        if not has_restitution(wide, o):
            continue
        ob = b * U64(2) * LANES_U
        for l in range(LANES_U):
            nx = wide[o + NX + l]
            ny = wide[o + NY + l]
            row_a = lane_row[ob + l]
            row_b = lane_row[ob + l + LANES_U]
            held_a = held[row_a]
            held_b = held[row_b]
            # the start velocities (row 0: cannot move, none); B's relative to A's along n
            dvn = 0.0
            wa = 0.0
            wb = 0.0
            if row_a > U64(0):
                i = awake[row_a - U64(1)]
                dvn -= velocity[i, 0] * nx + velocity[i, 1] * ny
                wa = angular_velocity[i]
            if row_b > U64(0):
                i = awake[row_b - U64(1)]
                dvn += velocity[i, 0] * nx + velocity[i, 1] * ny
                wb = angular_velocity[i]
            relv1 = dvn + wb * wide[o + RNB1 + l]
            relv2 = dvn + wb * wide[o + POINT2 + RNB1 + l]
            if row_a > U64(0):  # (a fixed A's arms are not kept: FIXED SIDE)
                relv1 -= wa * wide[o + RNA1 + l]
                relv2 -= wa * wide[o + POINT2 + RNA1 + l]
            # m/s^2: gravity's share of the pair's relative normal acceleration (B's against A's)
            falls_b = 1.0 if (wide[o + MB + l] > 0.0 and not held_b) else 0.0
            falls_a = 1.0 if (wide[o + MA + l] > 0.0 and not held_a) else 0.0
            acceleration = (falls_b - falls_a) * (gravity_x * nx + gravity_y * ny)
            wide[o + APPROACH1 + l] = approach(wide, o, l, U64(0), nx, ny, acceleration, relv1)
            wide[o + APPROACH2 + l] = approach(wide, o, l, POINT2, nx, ny, acceleration, relv2)


@wide_inline
def _restitution_lane(wide, o, l, threshold):
    """Bounce: drive each point's normal velocity to -e times its approach speed (APPROACH1/2,
    ``_approaches``), for points that approached faster than ``threshold`` and carried an
    impulse; the other point's impulse is left as it is. Two bouncing points are one 2x2 problem
    (``two_row_impulses``), so a box landing flat bounces flat."""
    nx = wide[o + NX + l]
    ny = wide[o + NY + l]
    e = wide[o + E + l]
    relv1 = wide[o + APPROACH1 + l]
    relv2 = wide[o + APPROACH2 + l]
    # the step's totals so far (TOTALS)
    old1 = wide[o + PN1 + l]
    old2 = wide[o + PN2 + l]
    bounce1 = relv1 <= -threshold and wide[o + TN1 + l] + old1 != 0.0 and e != 0.0
    bounce2 = relv2 <= -threshold and wide[o + TN2 + l] + old2 != 0.0 and e != 0.0
    rn1a = wide[o + RNA1 + l]
    rn1b = wide[o + RNB1 + l]
    rn2a = wide[o + RNA2 + l]
    rn2b = wide[o + RNB2 + l]
    r1 = _relative_velocity(wide, o, l, nx, ny, rn1a, rn1b, False) + e * relv1
    r2 = _relative_velocity(wide, o, l, nx, ny, rn2a, rn2b, False) + e * relv2
    k11 = _mass_term(wide, o, l, rn1a, rn1a, rn1b, rn1b, False)
    k22 = _mass_term(wide, o, l, rn2a, rn2a, rn2b, rn2b, False)
    k12 = _mass_term(wide, o, l, rn1a, rn2a, rn1b, rn2b, False)
    both1, both2 = two_row_impulses(old1, old2, r1, r2, k11, k12, k22, True)
    # one point bouncing: its row alone, at its mass at the arms it pushes at
    one1 = _fmax(0.0, old1 - r1 / k11) if k11 > 0.0 else old1
    one2 = _fmax(0.0, old2 - r2 / k22) if k22 > 0.0 else old2
    both = bounce1 & bounce2
    new1 = both1 if both else (one1 if bounce1 else old1)
    new2 = both2 if both else (one2 if bounce2 else old2)
    wide[o + PN1 + l] = new1
    wide[o + PN2 + l] = new2
    _apply(wide, o, l, new1 - old1, nx, ny, rn1a, rn1b, False)
    _apply(wide, o, l, new2 - old2, nx, ny, rn2a, rn2b, False)


@wide_kernel
def restitution(
    n_colours,
    colour_batches,
    wide,
    lane_row,
    state,
    threshold,
    gravity_x,
    gravity_y,
    touch,
    held,
    start,
):
    """Restitution after the substeps: RESTITUTION_SWEEPS sweeps, for bodies with several
    contacts (a lane's two points are solved together; solved one after the other, the first
    point's bounce turned the body before the second was solved). Batches with no restitution
    are skipped, and a step without any does nothing else. ``touch`` (m) and ``held`` (the
    solver's (N+1,) bool row scratch, all False on entry and on return): see
    ``bounce.mark_held``."""
    n_batches = U64(colour_batches[n_colours])
    bouncy = False
    for b in range(n_batches):
        bouncy = bouncy or has_restitution(wide, b * STRIDE_U)
    if not bouncy:
        return
    mark_held(n_batches, wide, lane_row, gravity_x, gravity_y, touch, held)
    _approaches(n_batches, wide, lane_row, gravity_x, gravity_y, held, start)
    for _ in range(RESTITUTION_SWEEPS):
        _restitution_sweep(n_colours, colour_batches, wide, lane_row, state, threshold)
    for k in range(n_batches * U64(2) * LANES_U):
        held[lane_row[k]] = False  # every lane's rows: the scratch is all False again


@wide_inline
def _restitution_sweep(n_colours, colour_batches, wide, lane_row, state, threshold):
    for c in range(n_colours):
        for b in range(U64(colour_batches[c]), U64(colour_batches[c + 1])):
            o = b * STRIDE_U
            if not has_restitution(wide, o):
                continue
            ob = b * U64(2) * LANES_U
            _gather_velocities(wide, o, lane_row, ob, state, False)
            for l in range(LANES_U):
                _restitution_lane(wide, o, l, threshold)
            _scatter(wide, o, lane_row, ob, state, False)


@wide_kernel
def deepest_separation(n_batches, wide):
    """m: the deepest separation of any contact point at the end of the step (0 if none
    penetrates), as the last ``arms`` pass left it (after the last substep's positions)."""
    deepest = 0.0
    for b in range(U64(n_batches)):
        o = b * STRIDE_U
        for l in range(LANES_U):
            for p in (U64(0), POINT2):
                if wide[o + p + NMASS1 + l] != 0.0:  # else an empty lane or point
                    deepest = min(deepest, wide[o + p + SEP1 + l])
    return deepest
