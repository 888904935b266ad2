"""The solver's body rows (``SolverData.state``): row 0 is the dummy row of everything that cannot
move (floor, static and frozen bodies); awake body k is row k + 1. Loaded from the bodies before
the substeps, integrated in them, and written back after."""

import numpy as np

from ..data import DPX, DPY, DQC, DQS, N_AWAKE, TURN, VX, VY, W
from ..jit import inline_kernel, lean_kernel


@inline_kernel
def row_of(i, n_dynamic, awake_slot):
    """The solver row of body i: its awake slot + 1, or the dummy row 0 (floor, static, frozen)."""
    if 0 <= i < n_dynamic and awake_slot[i] >= 0:
        return awake_slot[i] + 1
    return 0


@lean_kernel
def load_bodies(counters, bodies, activity, solver):
    """The awake bodies' velocities into their solver rows, displacements zeroed; the dummy row."""
    state = solver.state
    for c in range(state.shape[1]):
        state[0, c] = 0.0
    state[0, DQC] = 1.0
    for k in range(counters[N_AWAKE]):
        i = activity.awake[k]
        r = k + 1
        state[r, VX] = bodies.velocity[i, 0]
        state[r, VY] = bodies.velocity[i, 1]
        state[r, W] = bodies.angular_velocity[i]
        state[r, TURN] = 0.0
        state[r, DPX] = 0.0
        state[r, DPY] = 0.0
        state[r, DQC] = 1.0
        state[r, DQS] = 0.0


@lean_kernel
def integrate_velocities(n_awake, state, awake, solver_inv_mass, gx, gy, h):
    """Gravity over one substep, for every awake body the solver can move (a body a freeze
    policy holds awake but immovable, as ``paper``'s sliding ROTATION_STABLE, is kinematic:
    gravity would carry it away from what rests on it within the step)."""
    for r in range(1, n_awake + 1):
        if solver_inv_mass[awake[r - 1]] > 0.0:
            state[r, VX] += h * gx
            state[r, VY] += h * gy


@lean_kernel
def integrate_positions(n_awake, state, h):
    """Displacement and rotation over one substep. The rotation so far is kept as an angle (the
    body's final angle) and as (cos, sin), advanced without trigonometry and renormalised, which
    the solver uses to rotate anchors."""
    for r in range(1, n_awake + 1):
        w = state[r, W]
        state[r, DPX] += h * state[r, VX]
        state[r, DPY] += h * state[r, VY]
        state[r, TURN] += h * w
        c = state[r, DQC]
        s = state[r, DQS]
        c2 = c - h * w * s
        s2 = s + h * w * c
        inv = 1.0 / np.sqrt(c2 * c2 + s2 * s2)
        state[r, DQC] = c2 * inv
        state[r, DQS] = s2 * inv


@lean_kernel
def unload_bodies(counters, bodies, activity, solver):
    """The step's result into the bodies: velocities, and the start pose plus the displacement."""
    state = solver.state
    for k in range(counters[N_AWAKE]):
        i = activity.awake[k]
        r = k + 1
        bodies.velocity[i, 0] = state[r, VX]
        bodies.velocity[i, 1] = state[r, VY]
        bodies.angular_velocity[i] = state[r, W]
        bodies.position[i, 0] += state[r, DPX]
        bodies.position[i, 1] += state[r, DPY]
        bodies.angle[i] += state[r, TURN]
