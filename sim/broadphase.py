"""Broadphase: world-space geometry, bounding boxes and candidate pairs from a uniform grid.

Bodies are indexed 0..M-1 with the N dynamic bodies first and the static polygons after them.
A pair is encoded as one int64 key, ``(a + 1) * (M + 1) + b`` with a < b, and ``a = -1`` for the
floor, so that sorting keys orders pairs deterministically and the floor pairs come first.
"""
import numpy as np
from .jit import inline_kernel, kernel

# aabb columns
MIN_X, MIN_Y, MAX_X, MAX_Y = 0, 1, 2, 3


@kernel
def update_geometry(first, last, position, angle, vert_start, local_verts, local_normals,
                    rotation, world_verts, world_normals, aabb, margin):
    """World vertices, normals, rotation (cos, sin) and margin-fattened AABBs of bodies first..last-1.

    position (M,2) m, angle (M,) rad, vert_start (M+1,) offsets into local_verts/local_normals (V,2);
    outputs rotation (M,2), world_verts (V,2) m, world_normals (V,2), aabb (M,4) m.
    """
    for i in range(first, last):
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
        for k in range(vert_start[i], vert_start[i + 1]):
            x = local_verts[k, 0]
            y = local_verts[k, 1]
            wx = c * x - s * y + px
            wy = s * x + c * y + py
            world_verts[k, 0] = wx
            world_verts[k, 1] = wy
            nx = local_normals[k, 0]
            ny = local_normals[k, 1]
            world_normals[k, 0] = c * nx - s * ny
            world_normals[k, 1] = s * nx + c * ny
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


@inline_kernel
def _bucket(cx, cy, mask, dense, lo_cx, lo_cy, width):
    if dense:
        return (cy - lo_cy) * width + (cx - lo_cx)
    # multiplicative hash of the cell coordinates into a power-of-two table
    return ((cx * 73856093) ^ (cy * 19349663)) & mask


@kernel
def find_pairs(aabb, n_dynamic, has_floor, floor_y, cell_size, pair_keys):
    """Candidate pairs from a uniform grid, written sorted into ``pair_keys`` (P,).

    Each box is entered in every cell it covers (a table of cells, filled by counting sort),
    boxes sharing a cell are tested, and a pair is reported only from the cell holding the
    lower-left corner of the two boxes' intersection, so each pair once. The cost is linear in the
    bodies for scenes of similar sizes (stacks and pyramids, where sweeping along one axis tests
    whole columns against each other). Static-static pairs are skipped; a dynamic body whose box
    reaches below the floor plane pairs with the floor.
    Returns the pair count, or ``-needed`` when ``pair_keys`` is too small.
    """
    m = aabb.shape[0]
    stride = m + 1
    cap = pair_keys.shape[0]
    inv_cell = 1.0 / cell_size
    count = 0
    if has_floor:
        for i in range(n_dynamic):
            if aabb[i, MIN_Y] <= floor_y:
                if count < cap:
                    pair_keys[count] = i          # (a + 1) * stride + b with a = -1
                count += 1
    # count grid entries and the extent of the occupied cells
    n_entries = 0
    lo_cx = lo_cy = np.int64(2 ** 62)
    hi_cx = hi_cy = -np.int64(2 ** 62)
    for i in range(m):
        c0 = _cell(aabb[i, MIN_X], inv_cell)
        c1 = _cell(aabb[i, MAX_X], inv_cell)
        r0 = _cell(aabb[i, MIN_Y], inv_cell)
        r1 = _cell(aabb[i, MAX_Y], inv_cell)
        n_entries += (c1 - c0 + 1) * (r1 - r0 + 1)
        lo_cx = min(lo_cx, c0)
        hi_cx = max(hi_cx, c1)
        lo_cy = min(lo_cy, r0)
        hi_cy = max(hi_cy, r1)
    width = hi_cx - lo_cx + 1
    # A compact scene gets a dense table, one bucket per cell (no hash collisions); a sparse one
    # (bodies flung far apart) gets a hash table twice the entry count.
    dense = width * (hi_cy - lo_cy + 1) <= max(4 * n_entries, 4096)
    if dense:
        size = width * (hi_cy - lo_cy + 1)
        mask = 0
    else:
        size = 1
        while size < 2 * n_entries:
            size *= 2
        mask = size - 1
    start = np.zeros(size + 1, np.int64)
    entry_body = np.empty(n_entries, np.int64)
    entry_cx = np.empty(n_entries, np.int64)
    entry_cy = np.empty(n_entries, np.int64)
    for i in range(m):
        for cx in range(_cell(aabb[i, MIN_X], inv_cell), _cell(aabb[i, MAX_X], inv_cell) + 1):
            for cy in range(_cell(aabb[i, MIN_Y], inv_cell), _cell(aabb[i, MAX_Y], inv_cell) + 1):
                start[_bucket(cx, cy, mask, dense, lo_cx, lo_cy, width) + 1] += 1
    for k in range(size):
        start[k + 1] += start[k]
    fill = start[:-1].copy()
    for i in range(m):           # bodies in increasing index within each bucket: deterministic
        for cx in range(_cell(aabb[i, MIN_X], inv_cell), _cell(aabb[i, MAX_X], inv_cell) + 1):
            for cy in range(_cell(aabb[i, MIN_Y], inv_cell), _cell(aabb[i, MAX_Y], inv_cell) + 1):
                h = _bucket(cx, cy, mask, dense, lo_cx, lo_cy, width)
                e = fill[h]
                entry_body[e] = i
                entry_cx[e] = cx
                entry_cy[e] = cy
                fill[h] = e + 1
    for h in range(size):
        for e1 in range(start[h], start[h + 1]):
            i = entry_body[e1]
            cx = entry_cx[e1]
            cy = entry_cy[e1]
            for e2 in range(e1 + 1, start[h + 1]):
                j = entry_body[e2]
                if entry_cx[e2] != cx or entry_cy[e2] != cy:
                    continue             # another cell that hashed to the same bucket
                if i >= n_dynamic and j >= n_dynamic:
                    continue
                lo_x = max(aabb[i, MIN_X], aabb[j, MIN_X])
                lo_y = max(aabb[i, MIN_Y], aabb[j, MIN_Y])
                if lo_x > min(aabb[i, MAX_X], aabb[j, MAX_X]):
                    continue
                if lo_y > min(aabb[i, MAX_Y], aabb[j, MAX_Y]):
                    continue
                if _cell(lo_x, inv_cell) != cx or _cell(lo_y, inv_cell) != cy:
                    continue             # reported from the cell of the overlap's corner
                if count < cap:
                    pair_keys[count] = (i + 1) * stride + j      # i < j: entries are in order
                count += 1
    if count > cap:
        return -count
    pair_keys[:count].sort()
    return count
