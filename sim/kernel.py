"""The step loop: one compiled function runs many steps, so a call from Python costs one dispatch
however many steps it covers (per-step Python overhead would dominate cheap, mostly frozen scenes).

A step is a sequence of named stages (``data.STAGES``), each timed by the cycle counter when
``settings.profile`` is on:

  broadphase      refit the awake bodies' boxes; pairs for the bodies whose fat box moved
  narrowphase     every awake contact's manifold, from the current poses
  freeze_before   the policy wakes what this step's contacts disturb (``sim.freeze``)
  colour          colour the active contacts, lay them out in batches
  prepare         fill the batches (with the arms of the start poses); the awake bodies'
                  velocities into the solver rows
  integrate, arms, warm_start, solve, relax   per substep (``sim.soft_step``)
  restitution, store   once per step
  finalize        the bodies take their new velocities and poses; divergence check
  continuous      fast bodies swept against what they could tunnel through (``sim.continuous``)
  freeze_after    the policy's rest test and freezing

Status codes returned by ``run``: OK; GROW (a buffer is too small, counters[GROW_NEEDED] says
which; nothing of the current step has changed: grow and call again); FLUSH (the event buffer
needs emptying before the next step); NON_FINITE (a body's state is NaN/inf or beyond
MAX_COORDINATE: the run stops, counters[BAD_BODY] names the body).
"""

import numpy as np

from .activity import resting_bodies
from .body import MAX_COORDINATE
from .broadphase import build_grid, drop_stale_pairs, find_new_pairs, update_geometry
from .clock import cycles
from .contacts import sort_awake
from .data import (
    AWAKE_UNSORTED,
    BAD_BODY,
    GROW_AWAKE_GRID,
    GROW_NEEDED,
    GROW_RESTING_GRID,
    GROW_SOLVER,
    MAX_DEGREE,
    N_AWAKE,
    N_BATCHES,
    N_COLOURS,
    N_EVENTS,
    N_HARD,
    N_IMPACT_BATCHES,
    N_DEEP_BATCHES,
    N_LIVE,
    N_MOVED,
    N_QUIET,
    N_REBUILDS,
    QUIET_ARMED,
    PRESOLVE_CONVERGED,
    PRESOLVE_SWEEPS,
    RESTING_DIRTY,
    STAGE_ARMS,
    STAGE_BROADPHASE,
    STAGE_COLOUR,
    STAGE_CONTINUOUS,
    STAGE_FINALIZE,
    STAGE_FREEZE_AFTER,
    STAGE_FREEZE_BEFORE,
    STAGE_INTEGRATE,
    STAGE_NARROWPHASE,
    STAGE_PREPARE,
    STAGE_RELAX,
    STAGE_RESTITUTION,
    STAGE_SOLVE,
    STAGE_STORE,
    STAGE_WARM_START,
    STEP_COUNT,
)
from .freeze.codes import OFF
from .freeze.dispatch import freeze_after_solve, freeze_before_solve
from .narrowphase import update_manifolds
from .sweep import sweep_fast_bodies
from .jit import inline_kernel, kernel, lean_kernel
from .soft_step import (
    DEEP_SWEEPS,
    HARD_SWEEPS,
    IMPACT_SPEED,
    IMPACT_SWEEP_SPEED,
    LANES,
    colour,
    deepest_separation,
    arms,
    integrate_positions,
    integrate_velocities,
    lane_normal_impulse,
    load_bodies,
    max_colours,
    prepare,
    relax,
    relax_hard,
    restitution,
    solve,
    solve_impact,
    store,
    unload_bodies,
    warm_start,
)

OK, GROW, NON_FINITE, FLUSH = 0, 1, 2, 3


@inline_kernel
def _lap(settings, solver, stage, t0):
    """Add the cycles since t0 to ``stage``; returns the new start (0 when not profiling)."""
    if not settings.profile:
        return 0
    t = cycles()
    solver.profile[stage] += t - t0
    return t


@lean_kernel
def first_diverged(counters, bodies, activity):
    """The first awake body whose state is NaN/inf or out of range, else -1."""
    position, angle = bodies.position, bodies.angle
    velocity, angular_velocity = bodies.velocity, bodies.angular_velocity
    for k in range(counters[N_AWAKE]):
        i = activity.awake[k]
        if not (
            abs(position[i, 0]) <= MAX_COORDINATE
            and abs(position[i, 1]) <= MAX_COORDINATE
            and np.isfinite(angle[i])
            and np.isfinite(velocity[i, 0])
            and np.isfinite(velocity[i, 1])
            and np.isfinite(angular_velocity[i])
        ):
            return i
    return -1


@lean_kernel
def rebuild_resting(settings, counters, bodies, geometry, resting_grid, activity, scratch):
    """The resting grid of all static and frozen bodies' fat boxes, their geometry brought up to
    date (a body froze where it ended its last step). Run only when the frozen set changed.
    Returns False when the grid's buffers are too small."""
    n = resting_bodies(settings.n_dynamic, bodies.position.shape[0], activity.awake_slot, scratch)
    # resting bodies do not move: their refit boxes stay inside their fat boxes
    update_geometry(scratch, n, settings.dt, bodies, geometry, counters)
    if not build_grid(scratch, n, geometry.fat, settings.cell_size, resting_grid):
        counters[GROW_NEEDED] |= GROW_RESTING_GRID
        return False
    counters[RESTING_DIRTY] = 0
    counters[N_REBUILDS] += 1
    return True


@lean_kernel
def broadphase(
    settings,
    counters,
    bodies,
    geometry,
    awake_grid,
    resting_grid,
    contacts,
    solver,
    activity,
    scratch,
):
    """Boxes of the awake bodies; new and stale pairs of those whose fat box moved; and room in
    the solver for every contact. Returns False (counters[GROW_NEEDED] set) when a buffer is too
    small; every part is safe to run again after growing (moved bodies stay listed until their
    pairs are done)."""
    if counters[RESTING_DIRTY] == 1:
        if not rebuild_resting(
            settings, counters, bodies, geometry, resting_grid, activity, scratch
        ):
            return False
    update_geometry(activity.awake, counters[N_AWAKE], settings.dt, bodies, geometry, counters)
    if counters[N_MOVED] > 0:
        if not build_grid(
            activity.awake, counters[N_AWAKE], geometry.fat, settings.cell_size, awake_grid
        ):
            counters[GROW_NEEDED] |= GROW_AWAKE_GRID
            return False
        if not find_new_pairs(
            settings, bodies, geometry, awake_grid, resting_grid, contacts, counters, scratch
        ):
            return False
        drop_stale_pairs(settings, geometry, contacts, counters)
    # every live contact may be active this step (waking adds contacts, never slots)
    needed = (counters[N_LIVE] + LANES - 1) // LANES + max_colours(counters[MAX_DEGREE]) + 1
    if (
        needed > solver.lane_slot.shape[0] // LANES
        or max_colours(counters[MAX_DEGREE]) > 64 * solver.colour_mask.shape[1]
    ):
        counters[GROW_NEEDED] |= GROW_SOLVER
        return False
    return True


@inline_kernel
def _flagged_sweeps(count, n_colours, solver, inv_h, push, flags):
    """``count`` more biased sweeps with friction rows over the batches ``flags`` marks: a
    landing's (impact_iterations, Solver.batch_impact) and the deep contacts' (DEEP_SWEEPS,
    Solver.batch_deep)."""
    for _ in range(count):
        solve_impact(
            n_colours,
            solver.colour_batches,
            solver.wide,
            solver.lane_row,
            solver.state,
            inv_h,
            push,
            flags,
        )


@lean_kernel
def solve_step(settings, counters, bodies, contacts, activity, solver, t):
    """Colour, prepare, the substeps, restitution and store: velocities and displacements of this
    step in the solver rows. Returns the profiling clock."""
    t = _lap(settings, solver, STAGE_FREEZE_BEFORE, t)
    n_batches = colour(settings, counters, contacts, activity, solver)
    n_colours = counters[N_COLOURS]
    t = _lap(settings, solver, STAGE_COLOUR, t)
    prepare(settings, counters, bodies, contacts, activity, solver)
    load_bodies(counters, bodies, activity, solver)
    # prepare also left the lever arms and separations of the start poses; they change only
    # when the positions are integrated (then ``arms``: once per pose, read by every sweep)
    t = _lap(settings, solver, STAGE_PREPARE, t)
    h = settings.dt / settings.substeps
    inv_h = 1.0 / h
    n_awake = counters[N_AWAKE]
    for _ in range(settings.substeps):
        integrate_velocities(
            n_awake,
            solver.state,
            activity.awake,
            activity.solver_inv_mass,
            settings.gravity_x,
            settings.gravity_y,
            h,
        )
        t = _lap(settings, solver, STAGE_INTEGRATE, t)
        warm_start(
            n_colours,
            solver.colour_batches,
            solver.wide,
            solver.lane_row,
            solver.state,
            solver.batch_kind,
        )
        t = _lap(settings, solver, STAGE_WARM_START, t)
        for _ in range(settings.iterations):
            solve(
                n_colours,
                solver.colour_batches,
                solver.wide,
                solver.lane_row,
                solver.state,
                solver.batch_kind,
                inv_h,
                settings.push_speed,
            )
        if counters[N_IMPACT_BATCHES] > 0:
            _flagged_sweeps(
                settings.impact_iterations,
                n_colours,
                solver,
                inv_h,
                settings.push_speed,
                solver.batch_impact,
            )
        if counters[N_DEEP_BATCHES] > 0:
            _flagged_sweeps(
                DEEP_SWEEPS, n_colours, solver, inv_h, settings.push_speed, solver.batch_deep
            )
        t = _lap(settings, solver, STAGE_SOLVE, t)
        integrate_positions(n_awake, solver.state, h)
        t = _lap(settings, solver, STAGE_INTEGRATE, t)
        arms(n_batches, solver.wide, solver.lane_row, solver.state, solver.batch_kind)
        t = _lap(settings, solver, STAGE_ARMS, t)
        for _ in range(settings.relax_iterations):
            relax(
                n_colours,
                solver.colour_batches,
                solver.wide,
                solver.lane_row,
                solver.state,
                solver.batch_kind,
                inv_h,
                settings.fast_friction,
            )
        if counters[N_HARD] > 0:
            for _ in range(HARD_SWEEPS):
                relax_hard(
                    n_colours,
                    solver.colour_batches,
                    solver.wide,
                    solver.lane_row,
                    solver.state,
                    inv_h,
                    settings.fast_friction,
                    solver.batch_hard,
                )
        t = _lap(settings, solver, STAGE_RELAX, t)
    restitution(
        n_colours,
        solver.colour_batches,
        solver.wide,
        solver.lane_row,
        solver.state,
        settings.restitution_threshold,
        settings.gravity_x,
        settings.gravity_y,
        # m: what gravity closes in a substep (a point this near at the start is resting)
        np.hypot(settings.gravity_x, settings.gravity_y) / (inv_h * inv_h),
        solver.row_mark,
        # the bodies' velocities at the start of the step (unloaded after it)
        (bodies.velocity, bodies.angular_velocity, activity.awake),
    )
    t = _lap(settings, solver, STAGE_RESTITUTION, t)
    store(counters, contacts, solver, settings.load_rate, IMPACT_SPEED)
    t = _lap(settings, solver, STAGE_STORE, t)
    return t


@kernel
def run(
    n_steps,
    settings,
    counters,
    bodies,
    geometry,
    awake_grid,
    resting_grid,
    contacts,
    solver,
    activity,
    scratch,
    min_separation,
):
    """Advance up to ``n_steps`` steps. Returns (status, steps_done).

    ``min_separation`` (n_steps,) receives the deepest contact separation after each step, m.
    """
    n_dyn = settings.n_dynamic
    # Fast path "quiet" (settings.fast_quiet): a step that begins with nothing awake changes
    # nothing but the step count after its own first run. Nothing moves, no contact is looked at,
    # and no frozen body can wake, for only an awake body wakes one and nothing outside the step
    # loop changes a World's state (the World has no setters). What such a step does reset (the
    # resting grid rebuilt once, the batches emptied, the policy's per-step marks) it has reset by
    # its end, so the steps after it would repeat it exactly: a full step that began and ended
    # with nothing awake arms counters[QUIET_ARMED], and while it is armed steps only count, in
    # this call and the calls after it. Engines skip their sleeping islands the same way (a space
    # whose bodies all sleep costs pymunk and Box2D almost nothing a step); without this a frozen
    # World paid ~9 us a step in calls to stages with no work (pyramid(10)). A quiet run is
    # bit-identical to a full one (tests/unit/test_quiet.py compares them, every policy).
    for step in range(n_steps):
        if counters[N_EVENTS] + 4 * n_dyn + 16 > activity.events.shape[0]:
            return FLUSH, step
        if settings.fast_quiet and counters[QUIET_ARMED] == 1:
            counters[STEP_COUNT] += 1
            counters[N_QUIET] += 1
            # what the full step writes: no batches, so no point below zero
            min_separation[step] = deepest_separation(counters[N_BATCHES], solver.wide)
            if settings.profile:
                solver.steps_profiled[0] += 1
            continue
        began_frozen = counters[N_AWAKE] == 0
        t = cycles() if settings.profile else 0
        if not broadphase(
            settings,
            counters,
            bodies,
            geometry,
            awake_grid,
            resting_grid,
            contacts,
            solver,
            activity,
            scratch,
        ):
            return GROW, step
        if counters[AWAKE_UNSORTED] != 0:  # (the test first: a call costs ~0.2 us, see jit)
            sort_awake(bodies.position.shape[0], contacts, counters)
        t = _lap(settings, solver, STAGE_BROADPHASE, t)
        update_manifolds(settings, bodies, geometry, contacts, counters)
        t = _lap(settings, solver, STAGE_NARROWPHASE, t)
        # From here on the counter is this step's number (1-based), which every event of the
        # step carries, whichever hook records it.
        counters[STEP_COUNT] += 1
        # Bodies woken by this step's contacts join it: their contacts are awake again, and get
        # their manifolds from the current poses; until no more wake.
        # (policy off: no call at all. A call into a policy costs a reference-count increment
        # and decrement for every array it is passed, ~0.8 us a step; see sim/jit.py)
        while (
            settings.policy != OFF
            and freeze_before_solve(settings, counters, bodies, contacts, activity) > 0
        ):
            sort_awake(bodies.position.shape[0], contacts, counters)
            update_manifolds(settings, bodies, geometry, contacts, counters)
        t = solve_step(settings, counters, bodies, contacts, activity, solver, t)
        min_separation[step] = deepest_separation(counters[N_BATCHES], solver.wide)
        t = _lap(settings, solver, STAGE_FINALIZE, t)
        if settings.continuous:
            sweep_fast_bodies(
                settings,
                counters,
                bodies,
                geometry,
                awake_grid,
                resting_grid,
                activity,
                solver,
                scratch,
            )
        t = _lap(settings, solver, STAGE_CONTINUOUS, t)
        unload_bodies(counters, bodies, activity, solver)
        bad = first_diverged(counters, bodies, activity)
        if bad >= 0:
            counters[BAD_BODY] = bad
            return NON_FINITE, step + 1
        t = _lap(settings, solver, STAGE_FINALIZE, t)
        if settings.policy != OFF:
            freeze_after_solve(settings, counters, bodies, contacts, activity)
        t = _lap(settings, solver, STAGE_FREEZE_AFTER, t)
        if settings.profile:
            solver.steps_profiled[0] += 1
        counters[QUIET_ARMED] = 1 if began_frozen and counters[N_AWAKE] == 0 else 0
    return OK, n_steps


@kernel
def presolve(
    n_iterations,
    tolerance,
    settings,
    counters,
    bodies,
    geometry,
    awake_grid,
    resting_grid,
    contacts,
    solver,
    activity,
    scratch,
):
    """Solve the contact impulses of the initial configuration to convergence (or
    ``n_iterations`` sweeps) without moving anything: one substep of gravity, then rigid sweeps
    until no lane's normal impulse changes by more than ``tolerance`` times the largest over 10
    sweeps. Only the impulses are kept, to warm start step 1. A scene placed at rest then starts
    in equilibrium instead of sagging while the solver builds the pressure up over the first
    steps. A point approaching faster than IMPACT_SWEEP_SPEED is an impact in the making, not a
    load, and keeps no impulse: warm started (each substep repeats the warm start), the impulse
    its speculative row took stopped a box fired at the floor at 1e4 m/s 0.38 m in the air, and
    at 1e6 m/s sent it 43 m up. Returns OK or GROW; counters[PRESOLVE_SWEEPS] is the sweeps
    spent, counters[PRESOLVE_CONVERGED] 1 if it stopped on the tolerance."""
    if not broadphase(
        settings,
        counters,
        bodies,
        geometry,
        awake_grid,
        resting_grid,
        contacts,
        solver,
        activity,
        scratch,
    ):
        return GROW
    sort_awake(bodies.position.shape[0], contacts, counters)
    update_manifolds(settings, bodies, geometry, contacts, counters)
    n_batches = colour(settings, counters, contacts, activity, solver)
    n_colours = counters[N_COLOURS]
    prepare(settings, counters, bodies, contacts, activity, solver)
    load_bodies(counters, bodies, activity, solver)  # prepare left the arms the sweeps read
    h = settings.dt / settings.substeps
    integrate_velocities(
        counters[N_AWAKE],
        solver.state,
        activity.awake,
        activity.solver_inv_mass,
        settings.gravity_x,
        settings.gravity_y,
        h,
    )
    before = np.zeros(n_batches * LANES)
    done = 0
    counters[PRESOLVE_CONVERGED] = 0
    while done < n_iterations:
        _lane_impulses(n_batches, solver.wide, before)
        rounds = min(10, n_iterations - done)
        for _ in range(rounds):
            relax(
                n_colours,
                solver.colour_batches,
                solver.wide,
                solver.lane_row,
                solver.state,
                solver.batch_kind,
                1.0 / h,
                np.bool_(False),  # not a literal (sim/jit, LITERALS)
            )
        done += rounds
        change, largest = _impulse_change(n_batches, solver.wide, before)
        if change <= tolerance * largest:
            counters[PRESOLVE_CONVERGED] = 1
            break
    # the converged load is carried from the start; impacts are not loads (see above)
    store(counters, contacts, solver, 1.0, IMPACT_SWEEP_SPEED)
    counters[PRESOLVE_SWEEPS] = done
    return OK


@inline_kernel
def _lane_impulses(n_batches, wide, out):
    for e in range(n_batches * LANES):
        out[e] = lane_normal_impulse(wide, e)


@inline_kernel
def _impulse_change(n_batches, wide, before):
    change = 0.0
    largest = 0.0
    for e in range(n_batches * LANES):
        now = lane_normal_impulse(wide, e)
        change = max(change, abs(now - before[e]))
        largest = max(largest, abs(now))
    return change, largest
