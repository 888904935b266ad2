"""Sequential-impulse contact solver (velocity level) and non-linear Gauss-Seidel position correction.

Per step (see ``kernel.run``): integrate gravity into velocities, ``prepare`` the contact rows,
``warm_start`` them with last step's impulses, ``solve_velocities`` for ``iterations`` sweeps,
integrate positions, then ``correct_positions``.

Normal constraint per point: relative normal velocity vn >= TARGET_VELOCITY, accumulated impulse >= 0.
TARGET_VELOCITY is
  -separation/dt   for a speculative point (still apart): the bodies may close the gap, not more;
  0                for a touching point (penetration is removed by position correction, not by
                   velocity, so no energy is injected);
  -e * vn_before   when the point is being hit faster than the restitution threshold (a bounce).
Friction: |tangent impulse| <= mu * normal impulse (Coulomb), both accumulated and clamped.
Two-point manifolds are solved as a 2x2 linear complementarity problem (block solver), which
keeps boxes resting on two corners from rocking.
"""
import numpy as np
from .jit import inline_kernel, lean_kernel

from .contacts import (ANCHOR_AX, ANCHOR_AY, ANCHOR_BX, ANCHOR_BY, BLOCK, BODY_A, BODY_B,
                       FRICTION, INCIDENT, K11, K12, K22, LOCAL_FACE_X, LOCAL_FACE_Y,
                       LOCAL_NORMAL_X, LOCAL_NORMAL_Y, LOCAL_X, LOCAL_Y, NORMAL_IMPULSE,
                       NORMAL_MASS, NORMAL_X, NORMAL_Y, POINT_COUNT, REFERENCE, RESTITUTION,
                       SEPARATION, TANGENT_IMPULSE, TANGENT_MASS, TARGET_VELOCITY)

#: Largest condition number of a two-point normal-mass matrix still solved as a block.
MAX_CONDITION = 1000.0


@lean_kernel
def integrate_velocities(which, count, velocity, gravity_x, gravity_y, dt):
    """v += g dt for the bodies which[0..count-1] (the awake dynamic bodies)."""
    for k in range(count):
        i = which[k]
        velocity[i, 0] += gravity_x * dt
        velocity[i, 1] += gravity_y * dt


@lean_kernel
def integrate_positions(which, count, position, angle, velocity, angular_velocity, dt):
    """Semi-implicit Euler: positions from the new velocities, bodies which[0..count-1]."""
    for k in range(count):
        i = which[k]
        position[i, 0] += velocity[i, 0] * dt
        position[i, 1] += velocity[i, 1] * dt
        angle[i] += angular_velocity[i] * dt


@lean_kernel
def prepare(count, manifold_int, manifold_float, point_float, velocity, angular_velocity,
            inv_mass, inv_inertia, dt, restitution_threshold):
    """Effective masses, block matrices and velocity targets of every contact row."""
    for c in range(count):
        a = manifold_int[c, BODY_A]
        b = manifold_int[c, BODY_B]
        nx = manifold_float[c, NORMAL_X]
        ny = manifold_float[c, NORMAL_Y]
        tx = ny                   # tangent = normal rotated by -90 degrees
        ty = -nx
        if a >= 0:
            ma = inv_mass[a]
            ia = inv_inertia[a]
            vax = velocity[a, 0]
            vay = velocity[a, 1]
            wa = angular_velocity[a]
        else:
            ma = 0.0
            ia = 0.0
            vax = 0.0
            vay = 0.0
            wa = 0.0
        mb = inv_mass[b]
        ib = inv_inertia[b]
        e = manifold_float[c, RESTITUTION]
        n = manifold_int[c, POINT_COUNT]
        for j in range(n):
            rax = point_float[c, j, ANCHOR_AX]
            ray = point_float[c, j, ANCHOR_AY]
            rbx = point_float[c, j, ANCHOR_BX]
            rby = point_float[c, j, ANCHOR_BY]
            rna = rax * ny - ray * nx
            rnb = rbx * ny - rby * nx
            k_normal = ma + mb + ia * rna * rna + ib * rnb * rnb
            point_float[c, j, NORMAL_MASS] = 1.0 / k_normal if k_normal > 0.0 else 0.0
            rta = rax * ty - ray * tx
            rtb = rbx * ty - rby * tx
            k_tangent = ma + mb + ia * rta * rta + ib * rtb * rtb
            point_float[c, j, TANGENT_MASS] = 1.0 / k_tangent if k_tangent > 0.0 else 0.0
            # relative velocity of B's point with respect to A's, along the normal
            dvx = velocity[b, 0] - angular_velocity[b] * rby - vax + wa * ray
            dvy = velocity[b, 1] + angular_velocity[b] * rbx - vay - wa * rax
            vn = dvx * nx + dvy * ny
            s = point_float[c, j, SEPARATION]
            target = -s / dt if s > 0.0 else 0.0
            if e > 0.0 and vn < -restitution_threshold and vn < target:
                target = -e * vn
            point_float[c, j, TARGET_VELOCITY] = target
        manifold_float[c, BLOCK] = 0.0
        if n == 2:
            ra1 = point_float[c, 0, ANCHOR_AX] * ny - point_float[c, 0, ANCHOR_AY] * nx
            rb1 = point_float[c, 0, ANCHOR_BX] * ny - point_float[c, 0, ANCHOR_BY] * nx
            ra2 = point_float[c, 1, ANCHOR_AX] * ny - point_float[c, 1, ANCHOR_AY] * nx
            rb2 = point_float[c, 1, ANCHOR_BX] * ny - point_float[c, 1, ANCHOR_BY] * nx
            k11 = ma + mb + ia * ra1 * ra1 + ib * rb1 * rb1
            k22 = ma + mb + ia * ra2 * ra2 + ib * rb2 * rb2
            k12 = ma + mb + ia * ra1 * ra2 + ib * rb1 * rb2
            det = k11 * k22 - k12 * k12
            manifold_float[c, K11] = k11
            manifold_float[c, K12] = k12
            manifold_float[c, K22] = k22
            if k11 * k11 < MAX_CONDITION * det:
                manifold_float[c, BLOCK] = 1.0


@inline_kernel
def _apply(a, b, px, py, rax, ray, rbx, rby, velocity, angular_velocity, inv_mass, inv_inertia):
    """Apply impulse P to B at rB and -P to A at rA (A = -1 is the floor)."""
    if a >= 0:
        velocity[a, 0] -= inv_mass[a] * px
        velocity[a, 1] -= inv_mass[a] * py
        angular_velocity[a] -= inv_inertia[a] * (rax * py - ray * px)
    velocity[b, 0] += inv_mass[b] * px
    velocity[b, 1] += inv_mass[b] * py
    angular_velocity[b] += inv_inertia[b] * (rbx * py - rby * px)


@lean_kernel
def warm_start(count, manifold_int, manifold_float, point_float, velocity, angular_velocity,
               inv_mass, inv_inertia):
    """Apply last step's accumulated impulses, so a resting stack starts near its solution."""
    for c in range(count):
        a = manifold_int[c, BODY_A]
        b = manifold_int[c, BODY_B]
        nx = manifold_float[c, NORMAL_X]
        ny = manifold_float[c, NORMAL_Y]
        for j in range(manifold_int[c, POINT_COUNT]):
            pn = point_float[c, j, NORMAL_IMPULSE]
            pt = point_float[c, j, TANGENT_IMPULSE]
            _apply(a, b, pn * nx + pt * ny, pn * ny - pt * nx, point_float[c, j, ANCHOR_AX], point_float[c, j, ANCHOR_AY],
                   point_float[c, j, ANCHOR_BX], point_float[c, j, ANCHOR_BY], velocity, angular_velocity, inv_mass,
                   inv_inertia)


@lean_kernel
def solve_velocities(count, manifold_int, manifold_float, point_float, velocity,
                     angular_velocity, inv_mass, inv_inertia, skip_frictionless):
    """One Gauss-Seidel sweep over all contact rows: friction first (bounded by the current normal
    impulse), then the normal constraint (as a 2x2 block for two-point manifolds).

    The two bodies' velocities are loaded into locals once per manifold and stored back at the end:
    velocity[a] and velocity[b] could alias as far as the compiler knows, so updating the arrays in
    place would force a reload after every impulse. The sweep is bound by the latency of its
    dependent arithmetic (~70 ns per two-point manifold here); solving in graph-colour order, so that
    consecutive manifolds share no body, gained only ~12% and weakened tall stacks, so key order
    (bottom rows first) is kept.

    ``skip_frictionless``: a contact with friction coefficient 0 gets no friction rows (their
    impulse would be clamped to zero anyway: the rows are pure cost)."""
    for c in range(count):
        a = manifold_int[c, BODY_A]
        b = manifold_int[c, BODY_B]
        n = manifold_int[c, POINT_COUNT]
        if a >= 0:
            ma = inv_mass[a]
            ia = inv_inertia[a]
            vax = velocity[a, 0]
            vay = velocity[a, 1]
            wa = angular_velocity[a]
        else:                      # the floor: infinite mass, at rest
            ma = 0.0
            ia = 0.0
            vax = 0.0
            vay = 0.0
            wa = 0.0
        mb = inv_mass[b]
        ib = inv_inertia[b]
        vbx = velocity[b, 0]
        vby = velocity[b, 1]
        wb = angular_velocity[b]
        nx = manifold_float[c, NORMAL_X]
        ny = manifold_float[c, NORMAL_Y]
        tx = ny
        ty = -nx
        mu = manifold_float[c, FRICTION]
        for j in range(0 if skip_frictionless and mu == 0.0 else n):
            rax = point_float[c, j, ANCHOR_AX]
            ray = point_float[c, j, ANCHOR_AY]
            rbx = point_float[c, j, ANCHOR_BX]
            rby = point_float[c, j, ANCHOR_BY]
            # relative velocity of B's point with respect to A's: vB + wB x rB - vA - wA x rA
            dvx = vbx - wb * rby - vax + wa * ray
            dvy = vby + wb * rbx - vay - wa * rax
            vt = dvx * tx + dvy * ty
            limit = mu * point_float[c, j, NORMAL_IMPULSE]
            old = point_float[c, j, TANGENT_IMPULSE]
            new = min(max(old - point_float[c, j, TANGENT_MASS] * vt, -limit), limit)
            point_float[c, j, TANGENT_IMPULSE] = new
            px = (new - old) * tx
            py = (new - old) * ty
            vax -= ma * px
            vay -= ma * py
            wa -= ia * (rax * py - ray * px)
            vbx += mb * px
            vby += mb * py
            wb += ib * (rbx * py - rby * px)
        if n == 2 and manifold_float[c, BLOCK] > 0.0:
            # Solve both normal impulses at once: x >= 0, w = K x + b' >= 0, x . w = 0, trying the
            # four complementarity cases in turn.
            ra1x = point_float[c, 0, ANCHOR_AX]
            ra1y = point_float[c, 0, ANCHOR_AY]
            rb1x = point_float[c, 0, ANCHOR_BX]
            rb1y = point_float[c, 0, ANCHOR_BY]
            ra2x = point_float[c, 1, ANCHOR_AX]
            ra2y = point_float[c, 1, ANCHOR_AY]
            rb2x = point_float[c, 1, ANCHOR_BX]
            rb2y = point_float[c, 1, ANCHOR_BY]
            x1_old = point_float[c, 0, NORMAL_IMPULSE]
            x2_old = point_float[c, 1, NORMAL_IMPULSE]
            vn1 = ((vbx - wb * rb1y - vax + wa * ra1y) * nx
                   + (vby + wb * rb1x - vay - wa * ra1x) * ny)
            vn2 = ((vbx - wb * rb2y - vax + wa * ra2y) * nx
                   + (vby + wb * rb2x - vay - wa * ra2x) * ny)
            k11 = manifold_float[c, K11]
            k12 = manifold_float[c, K12]
            k22 = manifold_float[c, K22]
            # b' = (vn - target) - K x_old: the velocity error with the old impulses removed
            b1 = vn1 - point_float[c, 0, TARGET_VELOCITY] - (k11 * x1_old + k12 * x2_old)
            b2 = vn2 - point_float[c, 1, TARGET_VELOCITY] - (k12 * x1_old + k22 * x2_old)
            inv_det = 1.0 / (k11 * k22 - k12 * k12)
            solved = True
            x1 = -(k22 * b1 - k12 * b2) * inv_det          # case 1: both points push
            x2 = -(k11 * b2 - k12 * b1) * inv_det
            if not (x1 >= 0.0 and x2 >= 0.0):
                x1 = -b1 * point_float[c, 0, NORMAL_MASS]    # case 2: only point 1 pushes
                x2 = 0.0
                if not (x1 >= 0.0 and k12 * x1 + b2 >= 0.0):
                    x1 = 0.0                                 # case 3: only point 2 pushes
                    x2 = -b2 * point_float[c, 1, NORMAL_MASS]
                    if not (x2 >= 0.0 and k12 * x2 + b1 >= 0.0):
                        x1 = 0.0                             # case 4: both separate
                        x2 = 0.0
                        # K is positive definite, so one case always holds; keep the old
                        # impulses if round-off says otherwise
                        solved = b1 >= 0.0 and b2 >= 0.0
            if solved:
                point_float[c, 0, NORMAL_IMPULSE] = x1
                point_float[c, 1, NORMAL_IMPULSE] = x2
                d1 = x1 - x1_old
                d2 = x2 - x2_old
                p1x = d1 * nx
                p1y = d1 * ny
                p2x = d2 * nx
                p2y = d2 * ny
                vax -= ma * (p1x + p2x)
                vay -= ma * (p1y + p2y)
                wa -= ia * (ra1x * p1y - ra1y * p1x + ra2x * p2y - ra2y * p2x)
                vbx += mb * (p1x + p2x)
                vby += mb * (p1y + p2y)
                wb += ib * (rb1x * p1y - rb1y * p1x + rb2x * p2y - rb2y * p2x)
        else:
            for j in range(n):
                rax = point_float[c, j, ANCHOR_AX]
                ray = point_float[c, j, ANCHOR_AY]
                rbx = point_float[c, j, ANCHOR_BX]
                rby = point_float[c, j, ANCHOR_BY]
                vn = (vbx - wb * rby - vax + wa * ray) * nx + (vby + wb * rbx - vay - wa * rax) * ny
                old = point_float[c, j, NORMAL_IMPULSE]
                new = max(old - point_float[c, j, NORMAL_MASS]
                          * (vn - point_float[c, j, TARGET_VELOCITY]), 0.0)
                point_float[c, j, NORMAL_IMPULSE] = new
                px = (new - old) * nx
                py = (new - old) * ny
                vax -= ma * px
                vay -= ma * py
                wa -= ia * (rax * py - ray * px)
                vbx += mb * px
                vby += mb * py
                wb += ib * (rbx * py - rby * px)
        if a >= 0:
            velocity[a, 0] = vax
            velocity[a, 1] = vay
            angular_velocity[a] = wa
        velocity[b, 0] = vbx
        velocity[b, 1] = vby
        angular_velocity[b] = wb


@lean_kernel
def update_rotation(which, count, angle, rotation):
    """rotation[i] = (cos, sin) of angle[i], for bodies which[0..count-1]."""
    for k in range(count):
        i = which[k]
        rotation[i, 0] = np.cos(angle[i])
        rotation[i, 1] = np.sin(angle[i])


@inline_kernel
def _turn(c, s, d_angle):
    """(cos, sin) of angle + d_angle from those of angle, for the small turns of position
    correction: first order, renormalised (no trigonometry in the loop)."""
    c2 = c - s * d_angle
    s2 = s + c * d_angle
    inv = 1.0 / np.sqrt(c2 * c2 + s2 * s2)
    return c2 * inv, s2 * inv


@lean_kernel
def correct_positions(count, manifold_int, manifold_float, point_float, position, angle, rotation,
                      inv_mass, inv_inertia, slop, baumgarte, max_correction):
    """One non-linear Gauss-Seidel sweep that pushes penetrating points apart in position only
    (no velocity change, so no energy is added). Separations are recomputed from the current poses
    through the stored body-frame feature data. Penetration up to ``slop`` is left alone, which
    keeps resting contacts from jittering. ``rotation`` (M,2) must hold cos/sin of ``angle`` on
    entry and is kept in step with it. Returns the deepest separation seen (m), before correction:
    when it is >= -slop, the sweep changed nothing."""
    deepest = 0.0
    for c in range(count):
        ref = manifold_int[c, REFERENCE]
        inc = manifold_int[c, INCIDENT]
        # the two poses in locals, stored back once at the end (see solve_velocities)
        if ref >= 0:
            xr = position[ref, 0]
            yr = position[ref, 1]
            ar = angle[ref]
            cr = rotation[ref, 0]
            sr = rotation[ref, 1]
            m_ref = inv_mass[ref]
            i_ref = inv_inertia[ref]
        else:                                   # the floor: fixed, identity frame
            xr = yr = ar = sr = m_ref = i_ref = 0.0
            cr = 1.0
        xi = position[inc, 0]
        yi = position[inc, 1]
        ai = angle[inc]
        ci = rotation[inc, 0]
        si = rotation[inc, 1]
        m_inc = inv_mass[inc]
        i_inc = inv_inertia[inc]
        lnx = manifold_float[c, LOCAL_NORMAL_X]
        lny = manifold_float[c, LOCAL_NORMAL_Y]
        lfx = manifold_float[c, LOCAL_FACE_X]
        lfy = manifold_float[c, LOCAL_FACE_Y]
        moved = False
        for j in range(manifold_int[c, POINT_COUNT]):
            nx = cr * lnx - sr * lny
            ny = sr * lnx + cr * lny
            fx = cr * lfx - sr * lfy + xr
            fy = sr * lfx + cr * lfy + yr
            lx = point_float[c, j, LOCAL_X]
            ly = point_float[c, j, LOCAL_Y]
            px = ci * lx - si * ly + xi
            py = si * lx + ci * ly + yi
            s = (px - fx) * nx + (py - fy) * ny
            deepest = min(deepest, s)
            error = min(max(baumgarte * (s + slop), -max_correction), 0.0)
            if error >= 0.0:
                continue
            # lever arms to the midpoint between the surfaces
            mx = px - 0.5 * s * nx
            my = py - 0.5 * s * ny
            rni = (mx - xi) * ny - (my - yi) * nx
            rnr = (mx - xr) * ny - (my - yr) * nx
            k = m_inc + i_inc * rni * rni + m_ref + i_ref * rnr * rnr
            if k <= 0.0:
                continue
            impulse = -error / k               # along the normal, from reference to incident
            moved = True
            xi += m_inc * impulse * nx
            yi += m_inc * impulse * ny
            turn = i_inc * impulse * rni
            ai += turn
            ci, si = _turn(ci, si, turn)
            if ref >= 0:
                xr -= m_ref * impulse * nx
                yr -= m_ref * impulse * ny
                turn = -i_ref * impulse * rnr
                ar += turn
                cr, sr = _turn(cr, sr, turn)
        if moved:
            position[inc, 0] = xi
            position[inc, 1] = yi
            angle[inc] = ai
            rotation[inc, 0] = ci
            rotation[inc, 1] = si
            if ref >= 0:
                position[ref, 0] = xr
                position[ref, 1] = yr
                angle[ref] = ar
                rotation[ref, 0] = cr
                rotation[ref, 1] = sr
    return deepest
