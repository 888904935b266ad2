"""Narrowphase: turn candidate pairs into contact manifolds and carry impulses over (warm start).

A manifold is one touching pair with one or two points. Contact data is stored row-per-manifold,
the layout a sequential-impulse solver walks, in three arrays with named columns:

  manifold_int   (C, 6) int64   BODY_A, BODY_B (-1 = floor), KEY, POINT_COUNT,
                                REFERENCE (body holding the reference face, -1 = floor), INCIDENT
  manifold_float (C, 12) float64
      NORMAL_X, NORMAL_Y         world unit normal from A to B
      FRICTION, RESTITUTION      mixed coefficients (geometric mean, max)
      LOCAL_NORMAL_X/Y           reference face normal in the reference body frame
      LOCAL_FACE_X/Y             a point of the reference face in the reference body frame, m
      K11, K12, K22              normal-mass matrix of a two-point manifold (block solver), 1/kg
      BLOCK                      1.0 when the 2x2 block solve is well conditioned
  point_float    (C, 2, 12) float64, per point:
      ANCHOR_AX/AY, ANCHOR_BX/BY  contact point relative to each centre of mass, m
      SEPARATION                 m, negative = penetration (at narrowphase time)
      NORMAL_MASS, TANGENT_MASS  effective masses, kg
      TARGET_VELOCITY            normal velocity the solver aims for, m/s (speculative / bounce)
      NORMAL_IMPULSE, TANGENT_IMPULSE  accumulated impulses, N s
      LOCAL_X/Y                  the point in the incident body frame, m (position correction)
  point_id       (C, 2) int64   feature ids (see geometry.py)

Manifolds are stored in increasing KEY order, so last step's manifolds can be matched to this
step's by a merge walk, and impulses copied where the feature ids agree.
"""
import numpy as np
from .jit import lean_kernel

from .geometry import collide_floor_rows, collide_polygon_rows

BODY_A, BODY_B, KEY, POINT_COUNT, REFERENCE, INCIDENT = range(6)
MANIFOLD_INT_COLUMNS = 6
(NORMAL_X, NORMAL_Y, FRICTION, RESTITUTION, LOCAL_NORMAL_X, LOCAL_NORMAL_Y, LOCAL_FACE_X,
 LOCAL_FACE_Y, K11, K12, K22, BLOCK) = range(12)
MANIFOLD_FLOAT_COLUMNS = 12
(ANCHOR_AX, ANCHOR_AY, ANCHOR_BX, ANCHOR_BY, SEPARATION, NORMAL_MASS, TANGENT_MASS,
 TARGET_VELOCITY, NORMAL_IMPULSE, TANGENT_IMPULSE, LOCAL_X, LOCAL_Y) = range(12)
POINT_FLOAT_COLUMNS = 12


def scratch():
    """Scratch arrays for ``collide_pairs``: points (2,2), separations (2,), ids (2,), normal (2,)."""
    return np.empty((2, 2)), np.empty(2), np.empty(2, np.int64), np.empty(2)


def allocate(capacity):
    """Empty contact storage for ``capacity`` manifolds: (manifold_int, manifold_float, point_float,
    point_id)."""
    return (np.zeros((capacity, MANIFOLD_INT_COLUMNS), np.int64),
            np.zeros((capacity, MANIFOLD_FLOAT_COLUMNS), np.float64),
            np.zeros((capacity, 2, POINT_FLOAT_COLUMNS), np.float64),
            np.zeros((capacity, 2), np.int64))


@lean_kernel
def save_for_warm_start(count, manifold_int, point_float, point_id, prev_key, prev_count,
                        prev_id, prev_impulse):
    """Copy what warm starting needs of the current manifolds: keys, ids, impulses (C,2,2)."""
    for c in range(count):
        prev_key[c] = manifold_int[c, KEY]
        n = manifold_int[c, POINT_COUNT]
        prev_count[c] = n
        for j in range(n):
            prev_id[c, j] = point_id[c, j]
            prev_impulse[c, j, 0] = point_float[c, j, NORMAL_IMPULSE]
            prev_impulse[c, j, 1] = point_float[c, j, TANGENT_IMPULSE]


@lean_kernel
def collide_pairs(n_pairs, pair_keys, n_bodies, position, rotation, vert_start, local_verts,
                  local_normals, world_verts, world_normals, friction, restitution, floor_y,
                  floor_friction, floor_restitution, margin, manifold_int, manifold_float,
                  point_float, point_id, n_prev, prev_key, prev_count, prev_id, prev_impulse,
                  warm_start, points, seps, ids, normal):
    """Narrowphase over sorted pair keys; returns the number of manifolds written.

    position (M,2) m, rotation (M,2) cos/sin, world_verts/world_normals (V,2) already updated.
    Impulses are copied from the previous step's manifold with the same key and feature id when
    ``warm_start`` is true, and zeroed otherwise. points (2,2), seps (2,), ids (2,) int64 and
    normal (2,) are scratch (``scratch()``), passed in because this kernel allocates nothing.
    """
    stride = n_bodies + 1
    count = 0
    p = 0        # merge cursor into the previous step's manifolds
    for k in range(n_pairs):
        key = pair_keys[k]
        a = key // stride - 1
        b = key - (a + 1) * stride
        vb0 = vert_start[b]
        vb1 = vert_start[b + 1]
        if a < 0:
            n_points = collide_floor_rows(world_verts, world_normals, vb0, vb1, floor_y, margin,
                                          points, seps, ids)
            flip = 0
            edge = 0
            normal[0] = 0.0
            normal[1] = 1.0
            mu = np.sqrt(floor_friction * friction[b])
            e = max(floor_restitution, restitution[b])
        else:
            va0 = vert_start[a]
            va1 = vert_start[a + 1]
            n_points, flip, edge = collide_polygon_rows(
                world_verts, world_normals, va0, va1, vb0, vb1, margin, points, seps, ids, normal)
            mu = np.sqrt(friction[a] * friction[b])
            e = max(restitution[a], restitution[b])
        if n_points == 0:
            continue
        manifold_int[count, BODY_A] = a
        manifold_int[count, BODY_B] = b
        manifold_int[count, KEY] = key
        manifold_int[count, POINT_COUNT] = n_points
        manifold_float[count, NORMAL_X] = normal[0]
        manifold_float[count, NORMAL_Y] = normal[1]
        manifold_float[count, FRICTION] = mu
        manifold_float[count, RESTITUTION] = e
        if a < 0:
            ref = -1
            inc = b
            manifold_float[count, LOCAL_NORMAL_X] = 0.0
            manifold_float[count, LOCAL_NORMAL_Y] = 1.0
            manifold_float[count, LOCAL_FACE_X] = 0.0
            manifold_float[count, LOCAL_FACE_Y] = floor_y
            ref_nx = 0.0
            ref_ny = 1.0
        else:
            if flip == 1:
                ref = b
                inc = a
            else:
                ref = a
                inc = b
            r = vert_start[ref] + edge
            manifold_float[count, LOCAL_NORMAL_X] = local_normals[r, 0]
            manifold_float[count, LOCAL_NORMAL_Y] = local_normals[r, 1]
            manifold_float[count, LOCAL_FACE_X] = local_verts[r, 0]
            manifold_float[count, LOCAL_FACE_Y] = local_verts[r, 1]
            ref_nx = world_normals[r, 0]
            ref_ny = world_normals[r, 1]
        manifold_int[count, REFERENCE] = ref
        manifold_int[count, INCIDENT] = inc
        ci = rotation[inc, 0]
        si = rotation[inc, 1]
        for j in range(n_points):
            # anchor halfway between the two surfaces, so neither body is favoured
            mx = points[j, 0] - 0.5 * seps[j] * ref_nx
            my = points[j, 1] - 0.5 * seps[j] * ref_ny
            if a >= 0:
                point_float[count, j, ANCHOR_AX] = mx - position[a, 0]
                point_float[count, j, ANCHOR_AY] = my - position[a, 1]
            else:
                point_float[count, j, ANCHOR_AX] = 0.0
                point_float[count, j, ANCHOR_AY] = 0.0
            point_float[count, j, ANCHOR_BX] = mx - position[b, 0]
            point_float[count, j, ANCHOR_BY] = my - position[b, 1]
            point_float[count, j, SEPARATION] = seps[j]
            dx = points[j, 0] - position[inc, 0]
            dy = points[j, 1] - position[inc, 1]
            point_float[count, j, LOCAL_X] = ci * dx + si * dy           # R^T (p - x)
            point_float[count, j, LOCAL_Y] = -si * dx + ci * dy
            point_float[count, j, NORMAL_IMPULSE] = 0.0
            point_float[count, j, TANGENT_IMPULSE] = 0.0
            point_id[count, j] = ids[j]
        if warm_start:
            while p < n_prev and prev_key[p] < key:
                p += 1
            if p < n_prev and prev_key[p] == key:
                for j in range(n_points):
                    for q in range(prev_count[p]):
                        if prev_id[p, q] == ids[j]:
                            point_float[count, j, NORMAL_IMPULSE] = prev_impulse[p, q, 0]
                            point_float[count, j, TANGENT_IMPULSE] = prev_impulse[p, q, 1]
                            break
        count += 1
    return count

