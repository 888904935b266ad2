"""The arms pass: every contact point's lever arms (crossed with the normal and the tangent)
and separation, from the poses so far, once per pose; the sweeps (``batches``) read them."""

from ..data import DPX, DPY, DQC, DQS
from ..jit import wide_inline, wide_kernel
from .layout import (
    BASE1,
    DPAX,
    DPAY,
    DPBX,
    DPBY,
    FIXED_A,
    G0,
    LANES_U,
    NX,
    NY,
    POINT2,
    QCA,
    QCB,
    QSA,
    QSB,
    RAX1,
    RAY1,
    RBX1,
    RBY1,
    RNA1,
    RNB1,
    RTA1,
    RTB1,
    SEP1,
    STRIDE_U,
    TOWARD,
    U64,
)


@wide_inline
def _gather_poses(wide, o, lane_row, ob, state, fa):
    """The batch's body displacements and rotations so far into its fields (``arms``)."""
    for l in range(LANES_U):
        if not fa:
            ra = lane_row[ob + l]
            wide[o + DPAX + l] = state[ra, DPX]
            wide[o + DPAY + l] = state[ra, DPY]
            wide[o + QCA + l] = state[ra, DQC]
            wide[o + QSA + l] = state[ra, DQS]
        rb = lane_row[ob + LANES_U + l]
        wide[o + DPBX + l] = state[rb, DPX]
        wide[o + DPBY + l] = state[rb, DPY]
        wide[o + QCB + l] = state[rb, DQC]
        wide[o + QSB + l] = state[rb, DQS]


@wide_inline
def _moved_anchors(wide, o, l, p, nx, ny, fa):
    """Point p's anchors turned with their bodies, and where B's moved anchor lies from A's.

    Each anchor sits on its own body's surface (``contacts``) and has moved with its body this
    step (displacement dp, rotation dq): the separation is measured between the moved anchors.
    Returns (sax, say, sbx, sby, ox, oy, dx, dy): the turned anchors; B's moved anchor minus A's,
    minus their offset at the start (its projection on the normal, added to the start separation,
    is the separation now); and B's moved anchor minus A's. A fixed A (``batches``, FIXED SIDE)
    has not moved: its anchor is where it was (1 rax - 0 ray is rax), its displacement zero."""
    rax = wide[o + p + RAX1 + l]
    ray = wide[o + p + RAY1 + l]
    rbx = wide[o + p + RBX1 + l]
    rby = wide[o + p + RBY1 + l]
    qcb = wide[o + QCB + l]
    qsb = wide[o + QSB + l]
    if fa:
        sax = rax
        say = ray
    else:
        qca = wide[o + QCA + l]
        qsa = wide[o + QSA + l]
        sax = qca * rax - qsa * ray  # anchors turned with their bodies
        say = qsa * rax + qca * ray
    sbx = qcb * rbx - qsb * rby
    sby = qsb * rbx + qcb * rby
    if fa:
        ox = wide[o + DPBX + l] + sbx - sax
        oy = wide[o + DPBY + l] + sby - say
    else:
        ox = (wide[o + DPBX + l] - wide[o + DPAX + l]) + sbx - sax
        oy = (wide[o + DPBY + l] - wide[o + DPAY + l]) + sby - say
    # B's moved anchor minus A's: the start offset (the start separation along n) plus their
    # relative motion since
    s0 = wide[o + p + BASE1 + l] + (rbx - rax) * nx + (rby - ray) * ny
    dx = ox - (rbx - rax) + s0 * nx
    dy = oy - (rby - ray) + s0 * ny
    return sax, say, sbx, sby, ox, oy, dx, dy


@wide_inline
def line_arms(sax, say, sbx, sby, dx, dy, tx, ty, toward):
    """The cross products with (tx, ty) of the lever arms of an impulse along it, at anchors
    (sax, say), (sbx, sby) that lie (dx, dy) apart: (r_A x t, r_B x t), with r x t = rx ty - ry tx.

    An impulse and its reaction change no angular momentum when they act along one line: the
    arms are the moved anchors, shifted across the impulse onto one line (the offset along it,
    a gap or a penetration, turns nothing), A's by the share ``toward`` of their offset across
    it and B's by the rest. Any share conserves momentum; none gives the point's velocity along
    the impulse exactly: a shifted arm reads its body's velocity at a point off its anchor, wrong
    by the body's turning rate times the shift. So the shift goes to the body that turns less
    (``packing._toward``): its error is the smaller, and a body turning fast alone, or against a
    fixed one, keeps its own anchor, whose velocity is the rate at which the separation (``arms``)
    changes. Half way each (until 2026-12), a plank spinning at 100 rad/s near a wall it never
    reached was pushed away: its corner swung up to 1.7 m across the contact in a step, and the
    arm half way read the velocity of a point of the plank in the air. Box2D keeps the arms of
    the start of the step, which does not conserve angular momentum (1.9% lost in a test
    collision). Only the cross products enter the rows (the torque of an impulse, and the
    velocity of the point along it), so only they are kept."""
    across = dx * ty - dy * tx
    hx = across * ty
    hy = -across * tx
    rest = 1.0 - toward
    rca = (sax + toward * hx) * ty - (say + toward * hy) * tx
    rcb = (sbx - rest * hx) * ty - (sby - rest * hy) * tx
    return rca, rcb


@wide_kernel
def arms(n_batches, wide, lane_row, state, batch_kind):
    """Every point's lever arms (crossed with the normal and the tangent) and separation, from
    the poses so far.

    They depend on the poses only, which change once per substep (``integrate_positions``): so
    they are computed here once per pose, before the first substep and after each integration,
    and every sweep reads them. The effective masses are not kept: their divisions cost more
    here (a pass of its own, throughput-bound) than in the sweeps, whose chains of dependent
    updates leave the divider idle (measured on pyramid(40): this pass 0.058 against 0.080 ms a
    step with the masses, the sweeps 0.163 against 0.152). Reading the poses straight from the
    state rows instead of gathering them first cost twice as much (0.11 ms: no packed code).
    Fused into the first relax sweep (each batch's arms just before it is solved), the pass
    saved nothing in wall time: the relax sweep slowed by what the pass had cost.

    A FIXED_A batch's A side has not moved and its arms are never read (``batches``, FIXED
    SIDE): its poses are not gathered and its arms not stored. They are still computed, and
    their sum kept in one scratch field: dropped, the product that A's and B's arms share was
    fused into B's alone, which changed B's arms in the last bit."""
    for b in range(U64(n_batches)):
        if batch_kind[b] != FIXED_A:
            _arms_batch(wide, b, lane_row, state, False)
    for b in range(U64(n_batches)):
        if batch_kind[b] == FIXED_A:
            _arms_batch(wide, b, lane_row, state, True)


@wide_inline
def _arms_batch(wide, b, lane_row, state, fa):
    o = b * STRIDE_U
    ob = b * U64(2) * LANES_U
    _gather_poses(wide, o, lane_row, ob, state, fa)
    for l in range(LANES_U):
        nx = wide[o + NX + l]
        ny = wide[o + NY + l]
        toward = wide[o + TOWARD + l]
        unread = 0.0  # a fixed A's arms (see above)
        for p in (U64(0), POINT2):
            sax, say, sbx, sby, ox, oy, dx, dy = _moved_anchors(wide, o, l, p, nx, ny, fa)
            rna, rnb = line_arms(sax, say, sbx, sby, dx, dy, nx, ny, toward)
            # friction's offset across its line is the gap or overlap: it acts half way
            rta, rtb = line_arms(sax, say, sbx, sby, dx, dy, ny, -nx, 0.5)
            if fa:
                unread = unread + rna + rta
            else:
                wide[o + p + RNA1 + l] = rna
                wide[o + p + RTA1 + l] = rta
            wide[o + p + RNB1 + l] = rnb
            wide[o + p + RTB1 + l] = rtb
            # the start separation plus how the anchors moved apart along n
            wide[o + p + SEP1 + l] = wide[o + p + BASE1 + l] + ox * nx + oy * ny
        if fa:
            wide[o + G0 + l] = unread
