"""Broadphase: bounding boxes, uniform grids, and the pairs the contact store keeps.

Pairs persist (``sim.contacts``): a pair is made when two *fat* boxes start to overlap and freed
when they stop. A body's fat box is its bounding box grown by a margin (``sim.tolerances``); it is
refitted only when the body's current box leaves it, and only a refitted ("moved") body looks for
new partners or loses old ones. A resting pile refits nothing and costs one box test per body.

Bodies are indexed 0..M-1, the N dynamic ones first. Awake bodies are found through a grid of their
fat boxes, rebuilt in a step in which any of them moved; static and frozen bodies through the
*resting grid*, rebuilt only when the frozen set changes (ARCHITECTURE §3: frozen bodies cost
nothing per
step). Grids live in preallocated buffers (``data.Grid``): a build that does not fit reports the
sizes it needs, and the step returns GROW before anything else has changed.
"""

import numpy as np

from .contacts import create, destroy, find
from .data import (
    Grid,
    BODY_A,
    BODY_B,
    DENSE,
    GRID_INFO,
    HEIGHT,
    NEXT_A,
    NEXT_B,
    LO_CX,
    LO_CY,
    MASK,
    MAX_X,
    MAX_Y,
    MIN_X,
    MIN_Y,
    N_BUCKETS,
    N_ENTRIES,
    N_MOVED,
    NEEDED_BUCKETS,
    NEEDED_ENTRIES,
    WIDTH,
)
from .jit import inline_kernel, lean_kernel
from .tolerances import turn_reach

#: a box covering more grid cells than this is a *large* box: entered once, in a list every query
#: tests, instead of in each cell (a body moving 1.7e6 m in a step, 1e8 m/s, asked for 1e10 grid
#: entries; a long static floor would fill thousands of cells)
LARGE_CELLS = 256
#: a refitted fat box also reaches this many steps of the body's travel ahead of it: a falling or
#: sliding body then refits every few steps instead of every step (each refit rebuilds the awake
#: grid and looks for new pairs)
LOOKAHEAD_STEPS = 3.0
#: cells beyond this index (either sign) are clamped (see ``_cell``)
CELL_LIMIT = 2.0**40


@inline_kernel
def _transform(
    i, position, angle, vert_start, local_verts, local_normals, rotation, world_verts, world_normals
):
    """World vertices and normals of body i; returns its tight box (lo_x, lo_y, hi_x, hi_y)."""
    c = np.cos(angle[i])
    s = np.sin(angle[i])
    rotation[i, 0] = c
    rotation[i, 1] = s
    px = position[i, 0]
    py = position[i, 1]
    lo_x = np.inf
    lo_y = np.inf
    hi_x = -np.inf
    hi_y = -np.inf
    for v in range(vert_start[i], vert_start[i + 1]):
        x = local_verts[v, 0]
        y = local_verts[v, 1]
        wx = c * x - s * y + px
        wy = s * x + c * y + py
        world_verts[v, 0] = wx
        world_verts[v, 1] = wy
        nx = local_normals[v, 0]
        ny = local_normals[v, 1]
        world_normals[v, 0] = c * nx - s * ny
        world_normals[v, 1] = s * nx + c * ny
        lo_x = min(lo_x, wx)
        lo_y = min(lo_y, wy)
        hi_x = max(hi_x, wx)
        hi_y = max(hi_y, wy)
    return lo_x, lo_y, hi_x, hi_y


@lean_kernel
def update_geometry(which, count, dt, bodies, geometry, counters):
    """World vertices and boxes of bodies which[0..count-1] at their current poses.

    ``aabb`` is the tight box grown by the body's resting speculative reach and swept along its
    velocity over one step (plus what its rotation can reach): every contact the body can make in
    the step lies inside it. ``fat`` is refitted (the box grown by the body's margin) when ``aabb``
    has left it, and the body is added to ``geometry.moved`` (counters[N_MOVED] of them)."""
    aabb = geometry.aabb
    fat = geometry.fat
    n_moved = counters[N_MOVED]
    for k in range(count):
        i = which[k]
        lo_x, lo_y, hi_x, hi_y = _transform(
            i,
            bodies.position,
            bodies.angle,
            bodies.vert_start,
            bodies.local_verts,
            bodies.local_normals,
            geometry.rotation,
            geometry.world_verts,
            geometry.world_normals,
        )
        grow = bodies.speculative[i] + turn_reach(bodies.angular_velocity[i], bodies.extent[i], dt)
        sweep_x = bodies.velocity[i, 0] * dt
        sweep_y = bodies.velocity[i, 1] * dt
        aabb[i, MIN_X] = lo_x - grow + min(sweep_x, 0.0)
        aabb[i, MIN_Y] = lo_y - grow + min(sweep_y, 0.0)
        aabb[i, MAX_X] = hi_x + grow + max(sweep_x, 0.0)
        aabb[i, MAX_Y] = hi_y + grow + max(sweep_y, 0.0)
        if (
            aabb[i, MIN_X] < fat[i, MIN_X]
            or aabb[i, MIN_Y] < fat[i, MIN_Y]
            or aabb[i, MAX_X] > fat[i, MAX_X]
            or aabb[i, MAX_Y] > fat[i, MAX_Y]
        ):
            m = bodies.margin[i]
            ahead_x = LOOKAHEAD_STEPS * sweep_x
            ahead_y = LOOKAHEAD_STEPS * sweep_y
            fat[i, MIN_X] = aabb[i, MIN_X] - m + min(ahead_x, 0.0)
            fat[i, MIN_Y] = aabb[i, MIN_Y] - m + min(ahead_y, 0.0)
            fat[i, MAX_X] = aabb[i, MAX_X] + m + max(ahead_x, 0.0)
            fat[i, MAX_Y] = aabb[i, MAX_Y] + m + max(ahead_y, 0.0)
            if i < geometry.moved_flag.shape[0] and not geometry.moved_flag[i]:
                geometry.moved_flag[i] = True
                geometry.moved[n_moved] = i
                n_moved += 1
    counters[N_MOVED] = n_moved


@inline_kernel
def _cell(x, inv_cell):
    # clamped: converting a float beyond the int64 range is undefined (a body flung 1e19 m in a
    # step made the cell loops read outside the table); 2**40 cells is far beyond any scene
    return np.int64(np.floor(min(max(x * inv_cell, -CELL_LIMIT), CELL_LIMIT)))


@inline_kernel
def _cells(boxes, i, inv_cell):
    """The cell range (c0, c1, r0, r1) that box i covers."""
    return (
        _cell(boxes[i, MIN_X], inv_cell),
        _cell(boxes[i, MAX_X], inv_cell),
        _cell(boxes[i, MIN_Y], inv_cell),
        _cell(boxes[i, MAX_Y], inv_cell),
    )


@inline_kernel
def _is_large(c0, c1, r0, r1):
    # in floats: the product of two clamped ranges can exceed int64
    return float(c1 - c0 + 1) * float(r1 - r0 + 1) > LARGE_CELLS


@inline_kernel
def _bucket(cx, cy, info):
    if info[DENSE] == 1:
        return (cy - info[LO_CY]) * info[WIDTH] + (cx - info[LO_CX])
    # multiplicative hash of the cell coordinates into a power-of-two table
    return ((cx * 73856093) ^ (cy * 19349663)) & info[MASK]


@lean_kernel
def build_grid(which, count, boxes, cell_size, grid):
    """Enter the boxes of bodies which[0..count-1] into ``grid``: each box in every cell it
    covers, or, if large (``LARGE_CELLS``), once in the large bucket; cells map to buckets of a
    table filled by counting sort (dense when the occupied cells are compact, hashed otherwise).
    Returns False, with the sizes it needs in info[NEEDED_ENTRIES] and info[NEEDED_BUCKETS], when
    the buffers are too small."""
    info = grid.info
    inv_cell = 1.0 / cell_size
    n_entries = 0
    n_large = 0
    lo_cx = lo_cy = np.int64(2**62)
    hi_cx = hi_cy = -np.int64(2**62)
    for k in range(count):
        c0, c1, r0, r1 = _cells(boxes, which[k], inv_cell)
        if _is_large(c0, c1, r0, r1):
            n_large += 1
            continue
        n_entries += (c1 - c0 + 1) * (r1 - r0 + 1)
        lo_cx = min(lo_cx, c0)
        hi_cx = max(hi_cx, c1)
        lo_cy = min(lo_cy, r0)
        hi_cy = max(hi_cy, r1)
    if n_entries == 0:  # no box in cells: a one-cell table, never matched
        lo_cx = hi_cx = lo_cy = hi_cy = 0
    width = hi_cx - lo_cx + 1
    height = hi_cy - lo_cy + 1
    # A compact set gets a dense table, one bucket per cell (no hash collisions); a sparse one
    # (bodies flung far apart) a hash table twice the entry count.
    if float(width) * float(height) <= max(4 * n_entries, 4096):
        dense = 1
        size = width * height
    else:
        dense = 0
        size = 1
        while size < 2 * n_entries:
            size *= 2
    total = n_entries + n_large
    # buckets 0..size-1 hold cells, bucket ``size`` the large boxes: start has size + 2 entries
    if total > grid.entry_body.shape[0] or size + 2 > grid.start.shape[0]:
        info[NEEDED_ENTRIES] = total
        info[NEEDED_BUCKETS] = size + 1
        return False
    info[LO_CX] = lo_cx
    info[LO_CY] = lo_cy
    info[WIDTH] = width
    info[HEIGHT] = height
    info[DENSE] = dense
    info[MASK] = size - 1
    info[N_ENTRIES] = total
    info[N_BUCKETS] = size
    start = grid.start
    for h in range(size + 2):
        start[h] = 0
    for k in range(count):
        c0, c1, r0, r1 = _cells(boxes, which[k], inv_cell)
        if _is_large(c0, c1, r0, r1):
            start[size + 1] += 1
            continue
        for cx in range(c0, c1 + 1):
            for cy in range(r0, r1 + 1):
                start[_bucket(cx, cy, info) + 1] += 1
    for h in range(size + 1):
        start[h + 1] += start[h]
    # start[h + 1] is now the end of bucket h. Fill each bucket from its end down, with start[h + 1]
    # as the cursor (no second array): afterwards start[h + 1] holds the start of bucket h.
    for k in range(count - 1, -1, -1):
        i = which[k]
        c0, c1, r0, r1 = _cells(boxes, i, inv_cell)
        if _is_large(c0, c1, r0, r1):
            e = start[size + 1] - 1
            grid.entry_body[e] = i
            grid.entry_cx[e] = 0
            grid.entry_cy[e] = 0
            start[size + 1] = e
            continue
        for cx in range(c1, c0 - 1, -1):
            for cy in range(r1, r0 - 1, -1):
                h = _bucket(cx, cy, info)
                e = start[h + 1] - 1
                grid.entry_body[e] = i
                grid.entry_cx[e] = cx
                grid.entry_cy[e] = cy
                start[h + 1] = e
    for h in range(size + 1):  # shift back: start[h] = start of bucket h
        start[h] = start[h + 1]
    start[size + 1] = total
    return True


@inline_kernel
def _overlap(boxes, i, other_boxes, j):
    return not (
        boxes[i, MIN_X] > other_boxes[j, MAX_X]
        or boxes[i, MAX_X] < other_boxes[j, MIN_X]
        or boxes[i, MIN_Y] > other_boxes[j, MAX_Y]
        or boxes[i, MAX_Y] < other_boxes[j, MIN_Y]
    )


@inline_kernel
def query_box(grid, boxes, lo_x, lo_y, hi_x, hi_y, cell_size, out):
    """Write into ``out`` each body of ``grid`` whose box (rows of ``boxes``) overlaps the box
    (lo_x, lo_y, hi_x, hi_y), once each; returns how many. A body met in several cells is
    reported from the cell of the lower-left corner of the overlap only. The cost is bounded by
    the grid, not by the query: a query box reaching beyond a dense table is cut to it, and one
    covering more cells of a hashed table than it has entries scans the entries instead."""
    info = grid.info
    if info[N_ENTRIES] == 0:
        return 0
    start = grid.start
    inv_cell = 1.0 / cell_size
    n_buckets = info[N_BUCKETS]
    n = 0
    for e in range(start[n_buckets], start[n_buckets + 1]):  # the large boxes
        j = grid.entry_body[e]
        if not (
            lo_x > boxes[j, MAX_X]
            or hi_x < boxes[j, MIN_X]
            or lo_y > boxes[j, MAX_Y]
            or hi_y < boxes[j, MIN_Y]
        ):
            out[n] = j
            n += 1
    c0 = _cell(lo_x, inv_cell)
    c1 = _cell(hi_x, inv_cell)
    r0 = _cell(lo_y, inv_cell)
    r1 = _cell(hi_y, inv_cell)
    scan = False
    if info[DENSE] == 1:
        c0 = max(c0, info[LO_CX])
        c1 = min(c1, info[LO_CX] + info[WIDTH] - 1)
        r0 = max(r0, info[LO_CY])
        r1 = min(r1, info[LO_CY] + info[HEIGHT] - 1)
    else:
        scan = float(c1 - c0 + 1) * float(r1 - r0 + 1) > start[n_buckets]
    if c1 < c0 or r1 < r0:
        return n
    if scan:
        for e in range(start[n_buckets]):
            n = _report(grid, e, boxes, lo_x, lo_y, hi_x, hi_y, c0, c1, r0, r1, inv_cell, out, n)
        return n
    for cx in range(c0, c1 + 1):
        for cy in range(r0, r1 + 1):
            h = _bucket(cx, cy, info)
            for e in range(start[h], start[h + 1]):
                if grid.entry_cx[e] == cx and grid.entry_cy[e] == cy:  # else: a cell sharing h
                    n = _report(
                        grid, e, boxes, lo_x, lo_y, hi_x, hi_y, c0, c1, r0, r1, inv_cell, out, n
                    )
    return n


@inline_kernel
def _report(grid, e, boxes, lo_x, lo_y, hi_x, hi_y, c0, c1, r0, r1, inv_cell, out, n):
    """Report the body of entry e (into out[n]) if its box overlaps the query box and e is the
    entry of the cell holding the lower-left corner of the overlap; returns the new count."""
    cx = grid.entry_cx[e]
    cy = grid.entry_cy[e]
    if cx < c0 or cx > c1 or cy < r0 or cy > r1:
        return n
    j = grid.entry_body[e]
    if (
        lo_x > boxes[j, MAX_X]
        or hi_x < boxes[j, MIN_X]
        or lo_y > boxes[j, MAX_Y]
        or hi_y < boxes[j, MIN_Y]
    ):
        return n
    if (
        _cell(max(lo_x, boxes[j, MIN_X]), inv_cell) != cx
        or _cell(max(lo_y, boxes[j, MIN_Y]), inv_cell) != cy
    ):
        return n
    out[n] = j
    return n + 1


@inline_kernel
def _mark_partners(i, value, contacts, partner):
    """partner[j] = value for every body j that has a contact with body i (the floor aside)."""
    ci = contacts.contact_int
    s = contacts.head[i]
    while s >= 0:
        a = ci[s, BODY_A]
        if a == i:
            partner[ci[s, BODY_B]] = value
            s = ci[s, NEXT_A]
        else:
            if a >= 0:
                partner[a] = value
            s = ci[s, NEXT_B]


@inline_kernel
def _query(i, fat, grid, cell_size, n_dynamic, bodies, contacts, counters, found, partner):
    """Make a contact for every body in ``grid`` whose fat box overlaps body i's and that has
    none with i yet (partner[j] False; set for the ones made). ``found``: scratch, one slot per
    body. Returns False when the store is full."""
    n = query_box(
        grid, fat, fat[i, MIN_X], fat[i, MIN_Y], fat[i, MAX_X], fat[i, MAX_Y], cell_size, found
    )
    for k in range(n):
        j = found[k]
        if j == i or partner[j]:
            continue
        a = min(i, j)
        b = max(i, j)
        if create(a, b, n_dynamic, bodies.slop, bodies.speculative, contacts, counters) < 0:
            return False
        partner[j] = True
    return True


@lean_kernel
def find_new_pairs(settings, bodies, geometry, awake_grid, resting_grid, contacts, counters, found):
    """Contacts for the moved bodies' new partners: awake ones (``awake_grid``), resting ones
    (``resting_grid``) and the floor. ``found``: scratch (M,). Returns False when the contact
    store is full (the contacts made so far stay; a retry skips them).

    Whether a found body already has a contact with the moved one is read from marks
    (``geometry.partner``: one walk of the moved body's list sets them, one clears them), not
    looked up per found body (``contacts.find`` walks a list each time): while drop(200) lands,
    ~57 bodies a step refit, each finding ~10 others with ~8 contacts each."""
    fat = geometry.fat
    partner = geometry.partner
    n_dyn = settings.n_dynamic
    for k in range(counters[N_MOVED]):
        i = geometry.moved[k]
        if settings.has_floor and fat[i, MIN_Y] <= settings.floor_y:
            floor = np.int64(-1)  # body A of a floor pair; not a literal (sim/jit, LITERALS)
            if find(floor, i, n_dyn, contacts) < 0:
                if create(floor, i, n_dyn, bodies.slop, bodies.speculative, contacts, counters) < 0:
                    return False
        _mark_partners(i, True, contacts, partner)
        made = True
        for grid in (awake_grid, resting_grid):
            made = made and _query(
                i, fat, grid, settings.cell_size, n_dyn, bodies, contacts, counters, found, partner
            )
        _mark_partners(i, False, contacts, partner)  # (the new contacts are in i's list now)
        if not made:
            return False
    return True


@lean_kernel
def drop_stale_pairs(settings, geometry, contacts, counters):
    """Free the contacts of moved bodies whose fat boxes no longer overlap; clear the moved list."""
    fat = geometry.fat
    ci = contacts.contact_int
    n_dyn = settings.n_dynamic
    for k in range(counters[N_MOVED]):
        i = geometry.moved[k]
        s = contacts.head[i]
        while s >= 0:
            a = ci[s, BODY_A]
            b = ci[s, BODY_B]
            nxt = ci[s, NEXT_A] if a == i else ci[s, NEXT_B]  # read before freeing
            if a < 0:
                keep = fat[b, MIN_Y] <= settings.floor_y
            else:
                keep = _overlap(fat, a, fat, b)
            if not keep:
                destroy(s, n_dyn, contacts, counters)
            s = nxt
        geometry.moved_flag[i] = False
    counters[N_MOVED] = 0


def grid_buffers(entries, buckets):
    """A ``data.Grid`` with room for ``entries`` entries and ``buckets`` buckets."""
    return Grid(
        start=np.zeros(buckets + 1, np.int64),
        entry_body=np.zeros(entries, np.int64),
        entry_cx=np.zeros(entries, np.int64),
        entry_cy=np.zeros(entries, np.int64),
        info=np.zeros(GRID_INFO, np.int64),
    )
