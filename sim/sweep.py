"""Stage ``continuous``: fast bodies swept through the step, so that none passes through a body
or buries itself in one.

Speculative contacts (``narrowphase.update_manifolds`` makes them as far ahead as a pair can close
in one step) stop most fast bodies. They can miss: a contact is made from the poses at the start
of the step, and a body that turns, or passes a corner, meets features no manifold held (a box
falling at 27 m/s onto a box spinning at 15 rad/s ended 10 cm inside it). So after the solve,
every awake body that moved more than FAST_FRACTION of its own size in the step is swept from its
start pose to its end pose (linear in position and angle) against what its swept box reaches,
each at its own end pose, and put back to the earliest time of impact
(``continuous.time_of_impact``), keeping its velocity: the next step's contact stops it there.

Only where the contact solver failed: a pair already within its slop at the start of the step
(touching, not tunnelling: the sweep would stop the body dead on every resting contact), and one
that first meets during the step but ends it touching or overlapping by less than
OVERLAP_FRACTION of the thinner body (a speculative contact stopped it: cutting it back would
leave it a slop short of where the same body lands against a body that moves), are left alone. A
body is cut back when it ends the step deeper inside another than that, or, against a static or
frozen body, apart again, having passed through it. Passing through a body that moves is caught
only for a *bullet* (``Body(bullet=True)``), as in Box2D: the sweep does not follow the other
body's own path, so "apart at the end" is not proof that they crossed. So against an awake body
only a deep overlap at the end counts, and a pair whose bounding circles do not meet at the end
poses (``surely_apart``) is not measured at all (``Inspection.toi_pairs`` counts those that are).
"""

import numpy as np

from .body import MAX_COORDINATE
from .broadphase import query_box
from .continuous import separating_gap, swept_aabb, time_of_impact
from .data import DPX, DPY, N_AWAKE, N_IMPACTS, N_SWEPT, N_TOI_PAIRS, TURN
from .jit import inline_kernel, lean_kernel

#: a body is swept when it moved more than this fraction of its size (thinnest width) in a step
FAST_FRACTION = 0.5
#: conservative-advancement iterations allowed per pair (the result is safe when they run out)
MAX_ITERATIONS = 60
#: a body that ends the step inside another by more than this fraction of the thinner body's size
#: is cut back to its time of impact (see the module docstring); a pile dropped from 35 m reached
#: 31 cm of overlap without the sweep against awake bodies, 4.9 cm with it at this fraction
OVERLAP_FRACTION = 0.1


@inline_kernel
def _pose(bodies, solver, i, row, end):
    """(x, y, angle) of body i at the start (end=0) or the end (end=1) of this step; rows of
    awake bodies hold the step's displacement (``soft_step``), resting bodies do not move."""
    x = bodies.position[i, 0]
    y = bodies.position[i, 1]
    a = bodies.angle[i]
    if end == 1 and row > 0:
        x += solver.state[row, DPX]
        y += solver.state[row, DPY]
        a += solver.state[row, TURN]
    return (x, y, a)


@inline_kernel
def surely_apart(pose_i, pose_j, reach):
    """Are two bodies whose centres of mass lie at these poses (x m, y m, ...) certainly apart?
    ``reach`` (m): the sum of their ``extent`` (centre of mass to the farthest vertex), grown by
    a round-off allowance. True when the circles of these radii about the centres do not meet,
    which no polygon leaves; False says nothing.

    Why: against an awake body that is not a bullet's target, only a deep overlap at the end of
    the step cuts a fast body back, and bodies apart cannot overlap. A block of boxes falling
    side by side, 2 m apart, each moving more than half its size a step, met its neighbours'
    boxes in every sweep, and each of them cost a time-of-impact evaluation (two polygons placed
    with a cosine and a sine each, every axis): 1.1-1.8 us a falling box a step. This test is
    one distance against a sum (no trigonometry) and gives the same answer."""
    dx = pose_i[0] - pose_j[0]
    dy = pose_i[1] - pose_j[1]
    return dx * dx + dy * dy > reach * reach


@inline_kernel
def _sweep_pair(bodies, geometry, i, j, start, end, j_end, target, iterations):
    """``time_of_impact`` of body i swept from ``start`` to ``end`` against body j held at
    ``j_end``, stopping within a quarter of ``target``: (t, separation m)."""
    vs = bodies.vert_start
    return time_of_impact(
        bodies.local_verts,
        bodies.local_normals,
        vs[i],
        vs[i + 1],
        vs[j],
        vs[j + 1],
        start,
        end,
        j_end,
        j_end,
        target,
        0.25 * target,
        iterations,
        geometry.toi_scratch,
    )


@lean_kernel
def sweep_fast_bodies(
    settings, counters, bodies, geometry, awake_grid, resting_grid, activity, solver, found
):
    """Sweep every fast awake body (see the module docstring) and cut its displacement this step
    (solver row) back to its first time of impact. Returns the number of bodies cut back."""
    state = solver.state
    vs = bodies.vert_start
    cut = 0
    for k in range(counters[N_AWAKE]):
        i = activity.awake[k]
        r = k + 1
        dx = state[r, DPX]
        dy = state[r, DPY]
        turn = state[r, TURN]
        travel = np.sqrt(dx * dx + dy * dy) + abs(turn) * bodies.extent[i]
        if not (FAST_FRACTION * bodies.size[i] < travel < MAX_COORDINATE):
            continue  # slow, or diverged (the divergence check's job)
        counters[N_SWEPT] += 1
        start = _pose(bodies, solver, i, r, 0)
        end = _pose(bodies, solver, i, r, 1)
        lo_x, lo_y, hi_x, hi_y = swept_aabb(
            bodies.local_verts, vs[i], vs[i + 1], start, end, bodies.speculative[i]
        )
        first = 1.0
        for grid_kind in range(2):
            grid = resting_grid if grid_kind == 0 else awake_grid
            n = query_box(grid, geometry.fat, lo_x, lo_y, hi_x, hi_y, settings.cell_size, found)
            for q in range(n):
                j = found[q]
                if j == i:
                    continue
                rj = 0
                if j < settings.n_dynamic and activity.awake_slot[j] >= 0:
                    rj = activity.awake_slot[j] + 1
                target = min(bodies.slop[i], bodies.slop[j])
                j_end = _pose(bodies, solver, j, rj, 1)  # where the step left it
                # only a deep overlap at the end would count against an awake body (not a
                # bullet's target): none if they are apart (the slops: round-off allowance)
                reach = bodies.extent[i] + bodies.extent[j] + bodies.slop[i] + bodies.slop[j]
                if rj > 0 and not bodies.bullet[i] and surely_apart(end, j_end, reach):
                    continue
                counters[N_TOI_PAIRS] += 1
                # Where the step left them first (a sweep of zero length measures it): it alone
                # decides whether a time of impact could matter, and costs one iteration, where
                # the sweep may take dozens. In a settling pile most fast bodies end the step
                # near, not deep inside, the bodies around them. Where only a deep overlap counts
                # (an awake partner, no bullet) the separating axes alone decide it.
                deep = OVERLAP_FRACTION * min(bodies.size[i], bodies.size[j])
                if rj > 0 and not bodies.bullet[i]:
                    apart = separating_gap(
                        bodies.local_verts,
                        bodies.local_normals,
                        vs[i],
                        vs[i + 1],
                        vs[j],
                        vs[j + 1],
                        end,
                        j_end,
                        geometry.toi_scratch,
                    )
                    if not apart < -deep:
                        continue
                else:
                    # the iteration counts: not literals (sim/jit, LITERALS)
                    _, apart = _sweep_pair(
                        bodies, geometry, i, j, end, end, j_end, target, np.int64(1)
                    )
                    if not (apart > target or apart < -deep):
                        continue
                t, _ = _sweep_pair(
                    bodies, geometry, i, j, start, end, j_end, target, np.int64(MAX_ITERATIONS)
                )
                if 0.0 < t < first:
                    first = t
        if first < 1.0:
            state[r, DPX] = first * dx
            state[r, DPY] = first * dy
            state[r, TURN] = first * turn
            counters[N_IMPACTS] += 1
            cut += 1
    return cut
