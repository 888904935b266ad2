"""Broadphase: world-space geometry, bounding boxes and candidate pairs from uniform grids.

Bodies are indexed 0..M-1 with the N dynamic bodies first and the static polygons after them.
Only *awake* bodies (a list of indices) move; every other body — static polygons and frozen
bodies — sits in a *resting grid* built once when that set changes and only ever queried with
awake bodies' boxes, so resting bodies cost nothing per step (DESIGN section 2).
A pair is encoded as one int64 key, ``(a + 1) * (M + 1) + b`` with a < b, and ``a = -1`` for the
floor, so that sorting keys orders pairs deterministically and the floor pairs come first.
"""
import numpy as np
from .jit import inline_kernel, kernel, lean_kernel

# aabb columns
MIN_X, MIN_Y, MAX_X, MAX_Y = 0, 1, 2, 3


@lean_kernel
def update_geometry(which, count, position, angle, vert_start, local_verts, local_normals,
                    rotation, world_verts, world_normals, aabb, margin):
    """World vertices, normals, rotation (cos, sin) and margin-fattened AABBs of bodies
    which[0..count-1].

    position (M,2) m, angle (M,) rad, vert_start (M+1,) offsets into local_verts/local_normals (V,2);
    outputs rotation (M,2), world_verts (V,2) m, world_normals (V,2), aabb (M,4) m.
    """
    for k in range(count):
        i = which[k]
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
        aabb[i, MIN_X] = lo_x - margin
        aabb[i, MIN_Y] = lo_y - margin
        aabb[i, MAX_X] = hi_x + margin
        aabb[i, MAX_Y] = hi_y + margin


@inline_kernel
def _cell(x, inv_cell):
    return np.int64(np.floor(x * inv_cell))


# grid layout (int64 array of GRID_INFO fields)
LO_CX, LO_CY, WIDTH, MASK, DENSE, INV_CELL_BITS = range(6)
GRID_INFO = 6


@inline_kernel
def _bucket(cx, cy, info):
    if info[DENSE] == 1:
        return (cy - info[LO_CY]) * info[WIDTH] + (cx - info[LO_CX])
    # multiplicative hash of the cell coordinates into a power-of-two table
    return ((cx * 73856093) ^ (cy * 19349663)) & info[MASK]


@kernel
def build_grid(which, count, aabb, cell_size):
    """A uniform grid of the boxes of bodies which[0..count-1]: each box is entered in every cell
    it covers; cells map to buckets of a table filled by counting sort (dense when the occupied
    cells are compact, hashed otherwise). Returns (start (T+1,), entry_body (E,), entry_cx (E,),
    entry_cy (E,), info (GRID_INFO,)); bucket h holds entries start[h]..start[h+1]-1."""
    inv_cell = 1.0 / cell_size
    n_entries = 0
    lo_cx = lo_cy = np.int64(2 ** 62)
    hi_cx = hi_cy = -np.int64(2 ** 62)
    for k in range(count):
        i = which[k]
        c0 = _cell(aabb[i, MIN_X], inv_cell)
        c1 = _cell(aabb[i, MAX_X], inv_cell)
        r0 = _cell(aabb[i, MIN_Y], inv_cell)
        r1 = _cell(aabb[i, MAX_Y], inv_cell)
        n_entries += (c1 - c0 + 1) * (r1 - r0 + 1)
        lo_cx = min(lo_cx, c0)
        hi_cx = max(hi_cx, c1)
        lo_cy = min(lo_cy, r0)
        hi_cy = max(hi_cy, r1)
    info = np.zeros(GRID_INFO, np.int64)
    if count == 0:
        info[DENSE] = 1
        info[WIDTH] = 1
        return (np.zeros(2, np.int64), np.empty(0, np.int64), np.empty(0, np.int64),
                np.empty(0, np.int64), info)
    width = hi_cx - lo_cx + 1
    info[LO_CX] = lo_cx
    info[LO_CY] = lo_cy
    info[WIDTH] = width
    # A compact set gets a dense table, one bucket per cell (no hash collisions); a sparse one
    # (bodies flung far apart) a hash table twice the entry count.
    if width * (hi_cy - lo_cy + 1) <= max(4 * n_entries, 4096):
        info[DENSE] = 1
        size = width * (hi_cy - lo_cy + 1)
    else:
        size = 1
        while size < 2 * n_entries:
            size *= 2
        info[MASK] = size - 1
    start = np.zeros(size + 1, np.int64)
    entry_body = np.empty(n_entries, np.int64)
    entry_cx = np.empty(n_entries, np.int64)
    entry_cy = np.empty(n_entries, np.int64)
    for k in range(count):
        i = which[k]
        for cx in range(_cell(aabb[i, MIN_X], inv_cell), _cell(aabb[i, MAX_X], inv_cell) + 1):
            for cy in range(_cell(aabb[i, MIN_Y], inv_cell), _cell(aabb[i, MAX_Y], inv_cell) + 1):
                start[_bucket(cx, cy, info) + 1] += 1
    for h in range(size):
        start[h + 1] += start[h]
    fill = start[:-1].copy()
    for k in range(count):
        i = which[k]
        for cx in range(_cell(aabb[i, MIN_X], inv_cell), _cell(aabb[i, MAX_X], inv_cell) + 1):
            for cy in range(_cell(aabb[i, MIN_Y], inv_cell), _cell(aabb[i, MAX_Y], inv_cell) + 1):
                h = _bucket(cx, cy, info)
                e = fill[h]
                entry_body[e] = i
                entry_cx[e] = cx
                entry_cy[e] = cy
                fill[h] = e + 1
    return start, entry_body, entry_cx, entry_cy, info


@inline_kernel
def _reported_here(ax0, ay0, ax1, ay1, bx0, by0, bx1, by1, cx, cy, inv_cell):
    """Do boxes a and b overlap, with (cx, cy) the cell of the lower-left corner of their overlap?
    Then this cell reports the pair, and a pair found in several shared cells is reported once.
    On scalars: an inlined helper taking the arrays costs a reference-count round trip per call,
    which tripled the sweep."""
    lo_x = max(ax0, bx0)
    lo_y = max(ay0, by0)
    if lo_x > min(ax1, bx1) or lo_y > min(ay1, by1):
        return False
    return _cell(lo_x, inv_cell) == cx and _cell(lo_y, inv_cell) == cy


@kernel
def find_pairs(awake, n_awake, aabb, has_floor, floor_y, cell_size, resting, pair_keys):
    """Candidate pairs of the awake bodies, written sorted into ``pair_keys`` (P,).

    Awake-awake pairs come from a grid of the awake boxes built here; awake-resting pairs from
    querying the ``resting`` grid (see ``build_grid``) with each awake box; resting-resting pairs are
    never looked at. An awake body whose box reaches below the floor plane pairs with the floor.
    Returns the pair count, or ``-needed`` when ``pair_keys`` is too small (nothing else changes,
    so the caller can grow the buffer and call again).
    """
    m = aabb.shape[0]
    stride = m + 1
    inv_cell = 1.0 / cell_size
    count = 0
    if has_floor:
        for k in range(n_awake):
            i = awake[k]
            if aabb[i, MIN_Y] <= floor_y:
                if count < pair_keys.shape[0]:
                    pair_keys[count] = i          # (a + 1) * stride + b with a = -1
                count += 1
    cap = pair_keys.shape[0]
    start, entry_body, entry_cx, entry_cy, info = build_grid(awake, n_awake, aabb, cell_size)
    for h in range(start.shape[0] - 1):
        for e1 in range(start[h], start[h + 1]):
            i = entry_body[e1]
            cx = entry_cx[e1]
            cy = entry_cy[e1]
            ax0 = aabb[i, MIN_X]
            ay0 = aabb[i, MIN_Y]
            ax1 = aabb[i, MAX_X]
            ay1 = aabb[i, MAX_Y]
            for e2 in range(e1 + 1, start[h + 1]):
                if entry_cx[e2] != cx or entry_cy[e2] != cy:
                    continue                 # another cell that hashed to the same bucket
                j = entry_body[e2]
                if _reported_here(ax0, ay0, ax1, ay1, aabb[j, MIN_X], aabb[j, MIN_Y],
                                  aabb[j, MAX_X], aabb[j, MAX_Y], cx, cy, inv_cell):
                    if count < cap:
                        pair_keys[count] = (min(i, j) + 1) * stride + max(i, j)
                    count += 1
    r_start, r_body, r_cx, r_cy, r_info = resting
    if r_body.shape[0] > 0:
        n_buckets = r_start.shape[0] - 1
        for k in range(n_awake):
            i = awake[k]
            ax0 = aabb[i, MIN_X]
            ay0 = aabb[i, MIN_Y]
            ax1 = aabb[i, MAX_X]
            ay1 = aabb[i, MAX_Y]
            for cx in range(_cell(ax0, inv_cell), _cell(ax1, inv_cell) + 1):
                for cy in range(_cell(ay0, inv_cell), _cell(ay1, inv_cell) + 1):
                    if r_info[DENSE] == 1:
                        if (cx < r_info[LO_CX] or cx >= r_info[LO_CX] + r_info[WIDTH]
                                or cy < r_info[LO_CY]):
                            continue
                        h = _bucket(cx, cy, r_info)
                        if h >= n_buckets:
                            continue
                    else:
                        h = _bucket(cx, cy, r_info)
                    for e in range(r_start[h], r_start[h + 1]):
                        if r_cx[e] != cx or r_cy[e] != cy:
                            continue
                        j = r_body[e]
                        if _reported_here(ax0, ay0, ax1, ay1, aabb[j, MIN_X], aabb[j, MIN_Y],
                                          aabb[j, MAX_X], aabb[j, MAX_Y], cx, cy, inv_cell):
                            if count < cap:
                                pair_keys[count] = (min(i, j) + 1) * stride + max(i, j)
                            count += 1
    if count > pair_keys.shape[0]:
        return -count
    pair_keys[:count].sort()
    return count
