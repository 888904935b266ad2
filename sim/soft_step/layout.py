"""The layout of the solver's constraint batches (``SolverData.wide``): LANES contacts per batch,
stored field by field, so that one field of a whole batch is one contiguous run of LANES float64
(a packed vector register). Each contact has its shared fields, then the same fields once per
point (point 2's POINT2 past point 1's). Offsets are unsigned (U64): no sign checks in the packed
loops."""

import numpy as np

#: constraints per batch: 8 float64 fill one 512-bit register (AVX-512) or two 256-bit ones (AVX2)
LANES = 8
U64 = np.uint64
LANES_U = U64(LANES)
#: a contact's fields: its normal, friction and restitution, the inverse masses and inertias of A
#: and B, its softness (packing.prepare), the share of the normal's line shift that is A's
#: (TOWARD, arms.line_arms); per point: the anchors (m), the separation at the start
#: of the step (m), the normal mass at the start (kg), whether the point exists, the accumulated
#: impulses (N s; warm start), the step's totals, the approach velocity (m/s) and the carried
#: load, then what depends on the poses only (arms.arms, once per pose, not once per sweep):
#: each body's lever arm crossed with the normal (RNA, RNB; m) and with the tangent (RTA, RTB; m)
#: and the current separation (SEP; m); last, GATHER_FIELDS scratch fields for the two bodies'
#: rows gathered from the state (see GATHERED)
FIELD_NAMES = (
    "NX NY MU E MA IA MB IB BIAS_RATE MASS_SCALE IMPULSE_SCALE TOWARD "
    "RAX1 RAY1 RBX1 RBY1 BASE1 NMASS1 ON1 PN1 PT1 TN1 TT1 RELV1 LN1 "
    "RNA1 RNB1 RTA1 RTB1 SEP1 "
    "RAX2 RAY2 RBX2 RBY2 BASE2 NMASS2 ON2 PN2 PT2 TN2 TT2 RELV2 LN2 "
    "RNA2 RNB2 RTA2 RTB2 SEP2 "
    "G0 G1 G2 G3 G4 G5 G6 G7"
).split()
#: number of fields of a batch; field F of lane l of batch b is wide[b * STRIDE + F + l]
N_FIELDS = len(FIELD_NAMES)
STRIDE = N_FIELDS * LANES
(
    NX,
    NY,
    MU,
    E,
    MA,
    IA,
    MB,
    IB,
    BIAS_RATE,
    MASS_SCALE,
    IMPULSE_SCALE,
    TOWARD,
    RAX1,
    RAY1,
    RBX1,
    RBY1,
    BASE1,
    NMASS1,
    ON1,
    PN1,
    PT1,
    TN1,
    TT1,
    RELV1,
    LN1,
    RNA1,
    RNB1,
    RTA1,
    RTB1,
    SEP1,
    RAX2,
    RAY2,
    RBX2,
    RBY2,
    BASE2,
    NMASS2,
    ON2,
    PN2,
    PT2,
    TN2,
    TT2,
    RELV2,
    LN2,
    RNA2,
    RNB2,
    RTA2,
    RTB2,
    SEP2,
    G0,
    G1,
    G2,
    G3,
    G4,
    G5,
    G6,
    G7,
) = [U64(k * LANES) for k in range(N_FIELDS)]
#: GATHERED: the two bodies' rows, gathered from the state into the batch so that the lanes
#: compute on consecutive addresses (packed). A batch holds either its velocities (the sweeps:
#: gathered, changed, scattered back) or its displacements and rotations so far (the arms pass:
#: gathered, read), never both at once, so both share the same scratch fields: 8 fields a batch
#: fewer to stream through memory in every pass (rest_row(5000)'s batches do not fit the L2
#: cache). They must stay in the batch's own run of fields: a second array, or one run shared by
#: all batches, might alias the batch's fields for LLVM, which then keeps the scalar code.
GATHER_FIELDS = 8
VAX, VAY, WA, VBX, VBY, WB = G0, G1, G2, G3, G4, G5
DPAX, DPAY, QCA, QSA, DPBX, DPBY, QCB, QSB = G0, G1, G2, G3, G4, G5, G6, G7
#: restitution's approach speed of each point (m/s, ``batches._approaches``), in the two gather
#: fields the velocities leave free
APPROACH1, APPROACH2 = G6, G7
#: A batch's kind (``Solver.batch_kind``, set by ``packing.prepare``): FIXED_A when body A of
#: every lane is one the solver cannot move (its row is the dummy row 0, its inverse mass and
#: inertia zero: the floor, which is A of its pairs, or a frozen body), else MOVABLE. The sweeps
#: and the arms pass of a FIXED_A batch leave A's (zero) terms out and never touch its fields
#: (``batches``, FIXED SIDE): the same numbers with fewer operations and fewer fields streamed
#: through memory
MOVABLE, FIXED_A = 0, 1

#: offset of point 2's fields from point 1's, and the number of fields per point
POINT2 = U64((RAX2 - RAX1))
POINT_FIELDS = int(RAX2 - RAX1) // LANES
STRIDE_U = U64(STRIDE)
