"""The step loop: one compiled function runs many steps, so a call from Python costs one dispatch
however many steps it covers (per-step Python overhead would dominate cheap, mostly frozen scenes).

Arguments travel as tuples grouped by use (see ``World._kernel_state``):
  settings  (fsettings, isettings, counters)                       columns in ``sim.layout``
  bodies    (position, angle, velocity, angular_velocity, inv_mass, inv_inertia, friction,
             restitution, vert_start, local_verts, local_normals, extent)
  geometry  (rotation, world_verts, world_normals, aabb)
  contacts  (pair_keys, manifold_int, manifold_float, point_float, point_id,
             prev_key, prev_count, prev_id, prev_impulse)           see ``sim.contacts``
  activity  (states, awake, awake_slot, solver_inv_mass, solver_inv_inertia, events,
             body_real, body_int, links, link_load)                see ``sim.activity``
  resting   the resting grid (``broadphase.build_grid``), returned because it is rebuilt here

Status codes returned by ``run``: OK; GROW (the pair buffer is too small; nothing of the current
step has been changed: grow and call again); FLUSH (the event buffer needs emptying before the next
step); NON_FINITE (a body's state is NaN/inf or beyond MAX_COORDINATE: the run stops,
counters[BAD_BODY] names the body).
"""
import numpy as np

from .activity import resting_bodies
from .broadphase import build_grid, find_pairs, update_geometry
from .contacts import NORMAL_IMPULSE, POINT_COUNT, collide_pairs, save_for_warm_start
from .freeze.dispatch import freeze_after_solve, freeze_before_solve
from .jit import kernel
from .layout import (BAD_BODY, BAUMGARTE, CELL_SIZE, DT, FLOOR_FRICTION, FLOOR_RESTITUTION,
                     FAST_FRICTION, FAST_PATHS, FLOOR_Y, GRAVITY_X, GRAVITY_Y, HAS_FLOOR, ITERATIONS, MARGIN, MAX_CORRECTION,
                     N_AWAKE, N_DYNAMIC, N_EVENTS, N_MANIFOLDS, POLICY, POSITION_ITERATIONS,
                     PRESOLVE_SWEEPS, RESTING_DIRTY, RESTITUTION_THRESHOLD, SLOP, STEP_COUNT,
                     WARM_START)
from .solver import (correct_positions, integrate_positions, integrate_velocities, prepare,
                     solve_velocities, update_rotation, warm_start)

OK, GROW, NON_FINITE, FLUSH = 0, 1, 2, 3


#: A body farther than this from the origin (m) has diverged: beyond it the broadphase's cell
#: indices would overflow int64 long before the state turns NaN.
from .body import MAX_COORDINATE  # noqa: E402  m, defined once (bodies are refused beyond it)


@kernel
def _first_diverged(which, count, position, angle, velocity, angular_velocity):
    """The first of bodies which[0..count-1] whose state is NaN/inf or out of range, else -1."""
    for k in range(count):
        i = which[k]
        if not (abs(position[i, 0]) <= MAX_COORDINATE and abs(position[i, 1]) <= MAX_COORDINATE
                and np.isfinite(angle[i]) and np.isfinite(velocity[i, 0])
                and np.isfinite(velocity[i, 1]) and np.isfinite(angular_velocity[i])):
            return i
    return -1


@kernel
def rebuild_resting(settings, bodies, geometry, activity):
    """The resting grid of all static and frozen bodies, their geometry brought up to date
    (a body froze where it ended its last step). Run only when the frozen set changed."""
    fsettings, isettings, counters = settings
    position, angle = bodies[0], bodies[1]
    vert_start, local_verts, local_normals = bodies[8], bodies[9], bodies[10]
    rotation, world_verts, world_normals, aabb = geometry
    awake_slot = activity[2]
    resting = resting_bodies(isettings[N_DYNAMIC], position.shape[0], awake_slot)
    update_geometry(resting, resting.shape[0], position, angle, vert_start, local_verts,
                    local_normals, rotation, world_verts, world_normals, aabb, fsettings[MARGIN])
    counters[RESTING_DIRTY] = 0
    return build_grid(resting, resting.shape[0], aabb, fsettings[CELL_SIZE])


@kernel
def _detect(settings, bodies, geometry, contacts, activity, resting):
    """Collision detection on the current poses: awake geometry, pairs, manifolds (warm-started
    from the previous manifolds). Returns the manifold count, or -1 when ``pair_keys`` must grow
    (nothing that matters has changed then)."""
    fsettings, isettings, counters = settings
    position, angle = bodies[0], bodies[1]
    friction, restitution = bodies[6], bodies[7]
    vert_start, local_verts, local_normals = bodies[8], bodies[9], bodies[10]
    rotation, world_verts, world_normals, aabb = geometry
    (pair_keys, manifold_int, manifold_float, point_float, point_id, prev_key, prev_count, prev_id,
     prev_impulse) = contacts
    awake = activity[1]
    n_awake = counters[N_AWAKE]
    margin = fsettings[MARGIN]
    update_geometry(awake, n_awake, position, angle, vert_start, local_verts, local_normals,
                    rotation, world_verts, world_normals, aabb, margin)
    n_pairs = find_pairs(awake, n_awake, aabb, isettings[HAS_FLOOR] == 1, fsettings[FLOOR_Y],
                         fsettings[CELL_SIZE], resting, pair_keys)
    if n_pairs < 0:
        return -1
    n_prev = counters[N_MANIFOLDS]
    save_for_warm_start(n_prev, manifold_int, point_float, point_id, prev_key, prev_count,
                        prev_id, prev_impulse)
    count = collide_pairs(n_pairs, pair_keys, position.shape[0], position, rotation, vert_start,
                          local_verts, local_normals, world_verts, world_normals, friction,
                          restitution, fsettings[FLOOR_Y], fsettings[FLOOR_FRICTION],
                          fsettings[FLOOR_RESTITUTION], margin, manifold_int, manifold_float,
                          point_float, point_id, n_prev, prev_key, prev_count, prev_id,
                          prev_impulse, isettings[WARM_START] == 1, np.empty((2, 2)), np.empty(2),
                          np.empty(2, np.int64), np.empty(2))
    counters[N_MANIFOLDS] = count
    return count


@kernel
def presolve(n_iterations, tolerance, settings, bodies, geometry, contacts, activity, resting):
    """Solve the contact impulses of the initial configuration to convergence (or ``n_iterations``
    sweeps) without moving anything: velocities are restored afterwards, only the accumulated
    impulses are kept, to warm start step 1. A scene placed at rest then starts in equilibrium
    instead of sagging while a 10-iteration solver builds up the pressure in a tall stack over
    many steps. Returns OK or GROW."""
    fsettings, isettings, counters = settings
    velocity, angular_velocity = bodies[2], bodies[3]
    manifold_int, manifold_float, point_float = contacts[1], contacts[2], contacts[3]
    awake, solver_inv_mass, solver_inv_inertia = activity[1], activity[3], activity[4]
    count = _detect(settings, bodies, geometry, contacts, activity, resting)
    if count < 0:
        return GROW
    velocity0 = velocity.copy()
    angular_velocity0 = angular_velocity.copy()
    integrate_velocities(awake, counters[N_AWAKE], velocity, fsettings[GRAVITY_X],
                         fsettings[GRAVITY_Y], fsettings[DT])
    prepare(count, manifold_int, manifold_float, point_float, velocity, angular_velocity,
            solver_inv_mass, solver_inv_inertia, fsettings[DT], fsettings[RESTITUTION_THRESHOLD])
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
                             angular_velocity, solver_inv_mass, solver_inv_inertia,
                             (isettings[FAST_PATHS] & FAST_FRICTION) != 0)
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
    angular_velocity[:] = angular_velocity0
    counters[PRESOLVE_SWEEPS] = done
    return OK


@kernel
def run(n_steps, settings, bodies, geometry, contacts, activity, resting, min_separation):
    """Advance up to ``n_steps`` steps. Returns (status, steps_done, resting grid).

    ``min_separation`` (n_steps,) receives the deepest contact separation after each step, m.
    """
    fsettings, isettings, counters = settings
    position, angle, velocity, angular_velocity = bodies[0], bodies[1], bodies[2], bodies[3]
    manifold_int, manifold_float, point_float = contacts[1], contacts[2], contacts[3]
    rotation = geometry[0]
    awake, solver_inv_mass, solver_inv_inertia, events = (activity[1], activity[3], activity[4],
                                                          activity[5])
    dt = fsettings[DT]
    n_dyn = isettings[N_DYNAMIC]
    for step in range(n_steps):
        if counters[N_EVENTS] + 4 * n_dyn + 16 > events.shape[0]:
            return FLUSH, step, resting
        if counters[RESTING_DIRTY] == 1:
            resting = rebuild_resting(settings, bodies, geometry, activity)
        count = _detect(settings, bodies, geometry, contacts, activity, resting)
        if count < 0:
            return GROW, step, resting
        # From here on the counter is this step's number (1-based), which every event of the
        # step carries, whichever hook records it.
        counters[STEP_COUNT] += 1
        # Bodies woken by this step's contacts join it: detect again with them awake, until no
        # more wake (the woken bodies' own contacts were not generated while they were frozen).
        while freeze_before_solve(isettings[POLICY], count, settings, bodies, contacts,
                                  activity) > 0:
            resting = rebuild_resting(settings, bodies, geometry, activity)
            count = _detect(settings, bodies, geometry, contacts, activity, resting)
            if count < 0:
                counters[STEP_COUNT] -= 1        # the step is redone after the buffers grow
                return GROW, step, resting
        n_awake = counters[N_AWAKE]
        integrate_velocities(awake, n_awake, velocity, fsettings[GRAVITY_X], fsettings[GRAVITY_Y],
                             dt)
        prepare(count, manifold_int, manifold_float, point_float, velocity, angular_velocity,
                solver_inv_mass, solver_inv_inertia, dt, fsettings[RESTITUTION_THRESHOLD])
        warm_start(count, manifold_int, manifold_float, point_float, velocity, angular_velocity,
                   solver_inv_mass, solver_inv_inertia)
        for _ in range(isettings[ITERATIONS]):
            solve_velocities(count, manifold_int, manifold_float, point_float, velocity,
                             angular_velocity, solver_inv_mass, solver_inv_inertia,
                             (isettings[FAST_PATHS] & FAST_FRICTION) != 0)
        integrate_positions(awake, n_awake, position, angle, velocity, angular_velocity, dt)
        update_rotation(awake, n_awake, angle, rotation)
        deepest = 0.0
        for _ in range(isettings[POSITION_ITERATIONS]):
            deepest = correct_positions(count, manifold_int, manifold_float, point_float, position,
                                        angle, rotation, solver_inv_mass, solver_inv_inertia,
                                        fsettings[SLOP], fsettings[BAUMGARTE],
                                        fsettings[MAX_CORRECTION])
            if deepest >= -fsettings[SLOP]:
                break         # nothing was corrected, so further sweeps would change nothing
        min_separation[step] = deepest
        bad = _first_diverged(awake, n_awake, position, angle, velocity, angular_velocity)
        if bad >= 0:
            counters[BAD_BODY] = bad
            return NON_FINITE, step + 1, resting
        freeze_after_solve(isettings[POLICY], count, settings, bodies, contacts, activity)
    return OK, n_steps, resting
