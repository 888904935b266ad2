"""The step loop: one compiled function runs many steps, so a call from Python costs one dispatch
however many steps it covers (per-step Python overhead would dominate cheap, mostly frozen scenes).

Status codes returned by ``run``: OK, GROW (the pair buffer is too small; nothing of the current
step has been changed, grow and call again), NON_FINITE (a body's state is NaN/inf: the step and
body are returned and the run stops).
"""
import numpy as np
from .jit import kernel

from .broadphase import find_pairs, update_geometry
from .contacts import NORMAL_IMPULSE, POINT_COUNT, collide_pairs, save_for_warm_start
from .solver import (correct_positions, integrate_positions, integrate_velocities, prepare,
                     solve_velocities, update_rotation, warm_start)

OK, GROW, NON_FINITE = 0, 1, 2

# settings (float64 array) columns, so that adding a setting does not change every signature
(DT, GRAVITY_X, GRAVITY_Y, FLOOR_Y, FLOOR_FRICTION, FLOOR_RESTITUTION, SLOP, MARGIN, BAUMGARTE,
 MAX_CORRECTION, RESTITUTION_THRESHOLD, CELL_SIZE) = range(12)
N_FLOAT_SETTINGS = 12
# int settings (int64 array)
(ITERATIONS, POSITION_ITERATIONS, HAS_FLOOR, WARM_START, N_DYNAMIC) = range(5)
N_INT_SETTINGS = 5
# counters (int64 array), persistent across calls
(STEP_COUNT, N_MANIFOLDS, BAD_BODY, PRESOLVE_SWEEPS) = range(4)
N_COUNTERS = 4


@kernel
def _first_non_finite(n, position, angle, velocity, angular_velocity):
    for i in range(n):
        if not (np.isfinite(position[i, 0]) and np.isfinite(position[i, 1])
                and np.isfinite(angle[i]) and np.isfinite(velocity[i, 0])
                and np.isfinite(velocity[i, 1]) and np.isfinite(angular_velocity[i])):
            return i
    return -1


@kernel
def _detect(fsettings, isettings, counters, position, angle, vert_start, local_verts,
            local_normals, friction, restitution, rotation, world_verts, world_normals, aabb, pair_keys, manifold_int, manifold_float, point_float, point_id, prev_key,
            prev_count, prev_id, prev_impulse):
    """Collision detection on the current poses: geometry, pairs, manifolds (warm-started from the
    previous manifolds). Returns the manifold count, or -1 when ``pair_keys`` must grow (nothing
    that matters has changed then)."""
    m = position.shape[0]
    margin = fsettings[MARGIN]
    update_geometry(0, m, position, angle, vert_start, local_verts, local_normals, rotation,
                    world_verts, world_normals, aabb, margin)
    n_pairs = find_pairs(aabb, isettings[N_DYNAMIC], isettings[HAS_FLOOR] == 1,
                         fsettings[FLOOR_Y], fsettings[CELL_SIZE], pair_keys)
    if n_pairs < 0:
        return -1
    n_prev = counters[N_MANIFOLDS]
    save_for_warm_start(n_prev, manifold_int, point_float, point_id, prev_key, prev_count,
                        prev_id, prev_impulse)
    count = collide_pairs(n_pairs, pair_keys, m, position, rotation, vert_start, local_verts,
                          local_normals, world_verts, world_normals, friction, restitution,
                          fsettings[FLOOR_Y], fsettings[FLOOR_FRICTION],
                          fsettings[FLOOR_RESTITUTION], margin, manifold_int, manifold_float,
                          point_float, point_id, n_prev, prev_key, prev_count, prev_id,
                          prev_impulse, isettings[WARM_START] == 1)
    counters[N_MANIFOLDS] = count
    return count


@kernel
def presolve(n_iterations, tolerance, fsettings, isettings, counters,
             position, angle, velocity, angular_velocity,
             inv_mass, inv_inertia, friction, restitution, vert_start, local_verts, local_normals,
             rotation, world_verts, world_normals, aabb, pair_keys,
             manifold_int, manifold_float, point_float, point_id,
             prev_key, prev_count, prev_id, prev_impulse):
    """Solve the contact impulses of the initial configuration to convergence (or ``n_iterations``
    sweeps) without moving anything: velocities are restored afterwards, only the accumulated impulses are kept, to warm
    start step 1. A scene placed at rest then starts in equilibrium instead of sagging while a
    10-iteration solver builds up the pressure in a tall stack over many steps.
    Returns OK or GROW."""
    count = _detect(fsettings, isettings, counters, position, angle, vert_start, local_verts,
                    local_normals, friction, restitution, rotation, world_verts, world_normals,
                    aabb, pair_keys, manifold_int, manifold_float, point_float, point_id,
                    prev_key, prev_count, prev_id, prev_impulse)
    if count < 0:
        return GROW
    n_dyn = isettings[N_DYNAMIC]
    velocity0 = velocity.copy()
    angular_velocity0 = angular_velocity.copy()
    integrate_velocities(0, n_dyn, velocity, inv_mass, fsettings[GRAVITY_X], fsettings[GRAVITY_Y],
                         fsettings[DT])
    prepare(count, manifold_int, manifold_float, point_float, velocity, angular_velocity,
            inv_mass, inv_inertia, fsettings[DT], fsettings[RESTITUTION_THRESHOLD])
    # Sweep until no manifold's total normal impulse changes by more than `tolerance` times the
    # largest in 10 sweeps, at most n_iterations.
    before = np.empty(count)
    done = 0
    while done < n_iterations:
        for c in range(count):
            before[c] = 0.0
            for j in range(manifold_int[c, POINT_COUNT]):
                before[c] += point_float[c, j, NORMAL_IMPULSE]
        for _ in range(min(10, n_iterations - done)):
            solve_velocities(count, manifold_int, manifold_float, point_float, velocity,
                             angular_velocity, inv_mass, inv_inertia)
        done += 10
        change = 0.0
        largest = 0.0
        for c in range(count):
            total = 0.0
            for j in range(manifold_int[c, POINT_COUNT]):
                total += point_float[c, j, NORMAL_IMPULSE]
            change = max(change, abs(total - before[c]))
            largest = max(largest, abs(total))
        if change <= tolerance * largest:
            break
    velocity[:] = velocity0
    counters[PRESOLVE_SWEEPS] = done
    angular_velocity[:] = angular_velocity0
    return OK


@kernel
def run(n_steps, fsettings, isettings, counters,
        position, angle, velocity, angular_velocity,
        inv_mass, inv_inertia, friction, restitution, vert_start, local_verts, local_normals,
        rotation, world_verts, world_normals, aabb, pair_keys,
        manifold_int, manifold_float, point_float, point_id,
        prev_key, prev_count, prev_id, prev_impulse, min_separation):
    """Advance ``n_steps`` steps. Returns (status, steps_done).

    Body arrays have M rows (N dynamic first, then static); ``min_separation`` (n_steps,) receives
    the deepest contact separation after each step, m.
    """
    dt = fsettings[DT]
    n_dyn = isettings[N_DYNAMIC]
    for step in range(n_steps):
        count = _detect(fsettings, isettings, counters, position, angle, vert_start, local_verts,
                        local_normals, friction, restitution, rotation, world_verts,
                        world_normals, aabb, pair_keys, manifold_int, manifold_float,
                        point_float, point_id, prev_key, prev_count, prev_id, prev_impulse)
        if count < 0:
            return GROW, step
        integrate_velocities(0, n_dyn, velocity, inv_mass, fsettings[GRAVITY_X],
                             fsettings[GRAVITY_Y], dt)
        prepare(count, manifold_int, manifold_float, point_float, velocity, angular_velocity,
                inv_mass, inv_inertia, dt, fsettings[RESTITUTION_THRESHOLD])
        warm_start(count, manifold_int, manifold_float, point_float, velocity, angular_velocity,
                   inv_mass, inv_inertia)
        for _ in range(isettings[ITERATIONS]):
            solve_velocities(count, manifold_int, manifold_float, point_float, velocity,
                             angular_velocity, inv_mass, inv_inertia)
        integrate_positions(0, n_dyn, position, angle, velocity, angular_velocity, dt)
        update_rotation(0, n_dyn, angle, rotation)
        deepest = 0.0
        for _ in range(isettings[POSITION_ITERATIONS]):
            deepest = correct_positions(count, manifold_int, manifold_float, point_float, position,
                                        angle, rotation, inv_mass, inv_inertia, fsettings[SLOP],
                                        fsettings[BAUMGARTE], fsettings[MAX_CORRECTION])
            if deepest >= -fsettings[SLOP]:
                break         # nothing was corrected, so further sweeps would change nothing
        min_separation[step] = deepest
        counters[STEP_COUNT] += 1
        bad = _first_non_finite(n_dyn, position, angle, velocity, angular_velocity)
        if bad >= 0:
            counters[BAD_BODY] = bad
            return NON_FINITE, step + 1
    return OK, n_steps
