"""The solver against known answers (freeze="off"). Each test names the physics it checks; the
tolerances are the issue's, not tuned to the code."""

import math

import numpy as np
import pytest

import sim
from conftest import G, SPLIT_BOX, run_until, tilted_box
import naive


@pytest.mark.parametrize("substeps", [1, 4, 7])
def test_free_fall_is_exact_semi_implicit_euler(substeps):
    dt = 1 / 60
    h = dt / substeps
    world = sim.World(
        sim.Scene(bodies=[sim.Body.box(1, 1, position=(0.0, 100.0))]), dt=dt, substeps=substeps
    )
    for n in (1, 10, 60):
        world.step(n - world.step_count)
        # semi-implicit Euler over k = n * substeps substeps of h:
        # v_k = -g k h, y_k = y_0 - g h^2 k (k + 1) / 2
        k = n * substeps
        assert world.velocities[0, 1] == pytest.approx(-G * k * h, rel=1e-12)
        assert world.positions[0, 1] == pytest.approx(
            100.0 - G * h * h * k * (k + 1) / 2, rel=1e-12
        )
    assert world.velocities[0, 0] == 0.0 and world.angular_velocities[0] == 0.0


def test_box_at_rest_for_ten_seconds():
    world = sim.World(sim.scenes.single_box())
    start = world.positions
    run_until(world, 10.0)
    # measured (2026-12-06): it moves, turns and overlaps the floor by exactly 0
    assert np.linalg.norm(world.positions - start) < 1e-9
    assert abs(world.angles[0]) < 1e-9
    assert world.max_penetration < 1e-9


@pytest.mark.parametrize("base,moved,speed", [(20, 1e-5, 1e-5), (40, 1e-2, 2e-2)])
def test_a_pyramid_placed_at_rest_stands(base, moved, speed):
    # Static equilibrium: a pyramid of boxes placed in contact stays where it is. Over 5 s
    # (measured at 238f82e): pyramid(20) moves under 1e-6 m; pyramid(40), 820 boxes, keeps a
    # small rocking, 2.6 mm and 5.8 mm/s at most (pymunk's and Box2D 2.3's slide 0.46 and 0.75 m
    # in bench_step). The bounds on pyramid(40) leave 4x that and catch a solver whose tall
    # stacks sink: the contacts' rigid dead band of 9ab5ff0 did (4.4 cm and 0.26 m/s in 1 s).
    world = sim.World(sim.scenes.pyramid(base))
    start = world.positions.copy()
    for _ in range(5):
        run_until(world, 1.0)
        assert np.hypot(*(world.positions - start).T).max() < moved
        assert np.hypot(*world.velocities.T).max() < speed


def test_dropped_box_settles_with_small_penetration():
    scene = sim.Scene(bodies=[sim.Body.box(1, 1, position=(0.0, 2.0), angle=0.3)])
    world = run_until(sim.World(scene), 5.0)
    # measured (2026-12-06): overlap 2e-10 m, 1e-10 m off its resting height, 3e-10 m/s
    assert world.penetration < 1e-6
    assert abs(world.positions[0, 1] - 0.5) < 1e-6
    assert np.abs(world.velocities).max() < 1e-6


@pytest.mark.parametrize(
    "speed,mu,dt", [(3.0, 0.4, 1 / 60), (5.0, 0.2, 1 / 60), (2.0, 0.8, 1 / 240)]
)
def test_friction_slide_distance(speed, mu, dt):
    world = sim.World(sim.scenes.sliding_box(speed=speed, friction=mu), dt=dt)
    h = dt / world.substeps
    # The discrete answer, up to the step in which the box stops: over substeps of h,
    # v_k = v0 - k mu g h (friction at its limit from the first substep: the initial impulse
    # solve found it, the warm start carries it), x = h sum v_k. Not to the last bit, as the
    # rigid solver before soft step: the soft contacts share the box's weight between its two
    # corners a little differently from substep to substep while friction tips it forward, and
    # the friction limit follows (measured: 4e-5 to 2.1e-4 of the distance, 1e-5 of the speed).
    while world.velocities[0, 0] > 0.0:
        world.step()
    k = world.step_count * world.substeps
    x_stop = h * (speed * k - mu * G * h * k * (k + 1) / 2)
    assert world.positions[0, 0] == pytest.approx(x_stop, rel=3e-4)
    # When friction lets go, the weight shifts back from the front corner: the box rocks back
    # on its contacts as they take the new load (load_time, 1/3 s), and then stands, not creeping,
    # where it stopped.
    run_until(world, 3.0)
    assert abs(world.positions[0, 0] - x_stop) < 5e-4
    assert abs(world.velocities[0, 0]) < 1e-7
    assert abs(world.angles[0]) < 1e-6  # slid flat, did not tip
    # Coulomb: v0^2 / (2 mu g). Semi-implicit Euler falls short of it by about v0 h / 2 (h the
    # substep), under 1% in each case: the 3% bound tests the friction, not the step.
    assert world.positions[0, 0] == pytest.approx(speed**2 / (2 * mu * G), rel=0.03)


@pytest.mark.parametrize("speed", [10.0, 100.0, 1000.0])
def test_a_frictionless_box_gliding_fast_along_the_floor_stays_on_it_level(speed):
    """Nothing but gravity and the floor's push acts across the glide: the floor carries the
    whole weight every step and the box neither tilts nor sinks, at any speed. (Until 2026-12-07
    the box's lever arms were moved half way back along its slide within the step, as against a
    movable body: at 100 m/s the floor carried 96% of the weight in the first step, at 1000 m/s
    27%, and the box tilted 0.028 rad and sank 14 mm in 2 s.)"""
    box = sim.Body.box(1, 1, position=(0, 0.5), velocity=(speed, 0), friction=0.0)
    world = sim.World(sim.Scene([box], floor_friction=0.0))
    for _ in range(120):
        world.step()
        weight_dt = world.masses[0] * G * world.dt
        assert world.contacts()["normal_impulse"].sum() == pytest.approx(weight_dt, rel=1e-9)
    assert world.positions[0, 1] == pytest.approx(0.5, abs=1e-9)
    assert abs(world.angles[0]) < 1e-12 and abs(world.angular_velocities[0]) < 1e-12
    assert world.velocities[0, 0] == pytest.approx(speed, rel=1e-12)


@pytest.mark.parametrize("e", [0.5, 0.7, 0.9, 1.0])
@pytest.mark.parametrize("drop", [0.25, 0.5, 1.0, 2.0, 3.7])
@pytest.mark.parametrize("steps_per_s", [30, 60, 120])
def test_bounce_height_from_restitution(e, drop, steps_per_s):
    # A box dropped `drop` m onto the floor (floor restitution 0: max mixing gives the pair e)
    # leaves it at e times the speed it arrived with, so its bottom rises e^2 drop above the
    # floor, less what semi-implicit Euler loses of a height at substep h: v h / 2 on the way
    # down (a speed v) and the same on the way up (e v). A box the step's speculative contact
    # stopped a gap short of the floor bounces from there with e times the speed it has there,
    # so it rises gap (1 - e^2) higher (with e = 1: no higher, its energy kept). Nothing else:
    # the tolerance is what sampling the flight at the steps' ends can miss of the apex
    # (g dt^2 / 8) and 0.5 mm. The drops put the landing at different points of a step.
    # Measured at dt 1/60 while the approach speed was the one at the start of the landing step
    # (soft_step.bounce.free_flight_approach has why): the apex fell short of e^2 drop by
    # 16-51 mm at 0.5 m (13%) and 48-142 mm at 3.7 m (5%); now by 1-3%, the integrator's loss.
    half = 0.25
    scene = sim.Scene(
        bodies=[sim.Body.box(2 * half, 2 * half, position=(0.0, drop + half), restitution=e)]
    )
    world = sim.World(scene, dt=1 / steps_per_s)
    h = world.dt / world.substeps
    fall = math.sqrt(2 * drop / G)
    heights = []
    for _ in range(int((fall + 2 * e * fall + 0.5) / world.dt)):
        world.step()
        heights.append(world.positions[0, 1] - half)
    heights = np.array(heights)
    bounced = int(np.argmin(heights[: int((fall + 0.2) / world.dt)]))
    assert heights[bounced:].argmax() < len(heights) - bounced - 1  # the apex is passed
    apex = heights[bounced:].max()
    v = math.sqrt(2 * G * drop)
    gap = heights[bounced]
    expected = gap * (1 - e * e) + e * e * drop - (e * e + e) * v * h / 2
    assert apex == pytest.approx(expected, abs=G * world.dt**2 / 8 + 0.5e-3)


@pytest.mark.parametrize("e", [0.5, 0.9])
@pytest.mark.parametrize("drop", [0.25, 0.5, 1.0, 3.7])
def test_bounce_off_a_heavy_box_resting_on_the_floor(e, drop):
    # The same bounce onto the top of a box 1000 times as heavy resting on the floor (its own
    # restitution 0, so the pair bounces with e and it stays on the floor): the heavy box is held
    # up, it does not fall with the box landing on it, so the landing box arrives as on the floor
    # and rises as high, within what it hands the heavy box (m/M of its momentum). Measured while
    # both were taken to fall alike (soft_step.bounce.mark_held): 1-10% short of e^2 drop.
    half = 0.25
    heavy = sim.Body.box(2.0, 1.0, position=(0.0, 0.5), density=1000.0)
    box = sim.Body.box(2 * half, 2 * half, position=(0.0, 1.0 + drop + half), restitution=e)
    world = sim.World(sim.Scene(bodies=[heavy, box]), dt=1 / 60)
    h = world.dt / world.substeps
    fall = math.sqrt(2 * drop / G)
    heights = []
    for _ in range(int((fall + 2 * e * fall + 0.5) / world.dt)):
        world.step()
        heights.append(world.positions[1, 1] - half - (world.positions[0, 1] + 0.5))
    heights = np.array(heights)
    bounced = int(np.argmin(heights[: int((fall + 0.2) / world.dt)]))
    assert heights[bounced:].argmax() < len(heights) - bounced - 1  # the apex is passed
    v = math.sqrt(2 * G * drop)
    gap = heights[bounced]
    expected = gap * (1 - e * e) + e * e * drop - (e * e + e) * v * h / 2
    assert heights[bounced:].max() == pytest.approx(expected, abs=G * world.dt**2 / 8 + 1e-3)


@pytest.mark.parametrize(("speed", "gap"), [(4.0, 0.3), (6.0, 0.77), (6.0, 1.0), (8.0, 0.3)])
def test_a_bounce_off_a_ceiling_adds_no_energy(speed, gap):
    # A box thrown up at a static ceiling `gap` m above it, with restitution 1 and no floor:
    # gravity slows it on the way up, so it arrives slower than it was at the start of the
    # landing step, and bouncing with that earlier speed gave it energy (measured before
    # soft_step.bounce.free_flight_approach: +0.37 to +0.59 J/kg, up to 6% of what it was
    # thrown with). Back at its starting height its energy may only have fallen: semi-implicit
    # Euler loses g^2 h / 2 per second of flight (h the substep).
    half = 0.25
    ceiling = sim.Body.box(4, 0.5, position=(0.0, 1.0 + half + gap + 0.25))
    box = sim.Body.box(
        2 * half, 2 * half, position=(0.0, 1.0), velocity=(0.0, speed), restitution=1.0
    )
    scene = sim.Scene(bodies=[box], static_bodies=[ceiling], floor_y=None)
    world = sim.World(scene, dt=1 / 60)
    h = world.dt / world.substeps
    energy = 0.5 * speed**2 + G * 1.0  # J/kg
    while world.positions[0, 1] >= 1.0 or world.velocities[0, 1] > 0.0:
        world.step()
        assert world.step_count < 200
    assert world.velocities[0, 1] < -1.0  # it bounced (an inelastic touch would fall from rest)
    now = 0.5 * world.velocities[0, 1] ** 2 + G * world.positions[0, 1]
    assert now - energy <= 0.0
    assert now - energy > -(0.5 * G * G * h * world.time + 0.05)


@pytest.mark.parametrize("tilt", [0.1, 0.3, 0.6])
def test_a_turning_corner_bounces_without_gaining_energy(tilt):
    """A 1 m box tilted ``tilt`` rad, thrown at 5 m/s into a static wall with e = 1 and no
    friction, without gravity: its corners strike in turn, and it turns (11.8 rad/s after the
    first strike at 0.3 rad). Each bounce may keep or lose energy, never gain it. Until 2026-12-07
    the bounce took the approach speed at the arms of the start of the step and pushed at the
    arms the substeps had turned to: it left with 21% more energy at 0.3 rad."""
    wall = sim.Body.box(1.0, 10.0, position=(3.0, 0.0))
    box = sim.Body.box(1.0, 1.0, velocity=(5.0, 0.0), angle=tilt, restitution=1.0, friction=0.0)
    scene = sim.Scene(bodies=[box], static_bodies=[wall], floor_y=None, gravity=(0.0, 0.0))
    world = sim.World(scene, dt=1 / 60)
    before = world.kinetic_energy()
    world.step(90)
    assert world.velocities[0, 0] < -1.0  # it bounced back
    assert world.kinetic_energy() <= before * (1 + 1e-9)
    assert world.kinetic_energy() > 0.9 * before  # an elastic bounce, not a dead stop


@pytest.mark.parametrize("tilt", [0.15, 0.3])
def test_a_tilted_box_dropped_with_full_restitution_rises_no_higher_than_it_fell(tilt):
    """A 1 x 0.5 m box dropped from 3 m tilted ``tilt`` rad, e = 1, no friction: it lands on a
    corner, turns, and bounces on. Its energy (kinetic plus potential) may only fall; until
    2026-12-07 it doubled at 0.3 rad and the box rose to 5 m."""
    box = sim.Body.box(1.0, 0.5, position=(0.0, 3.0), angle=tilt, restitution=1.0, friction=0.0)
    world = sim.World(sim.Scene(bodies=[box], floor_friction=0.0), dt=1 / 60)
    start = world.kinetic_energy() + world.masses[0] * G * 3.0
    for _ in range(600):
        world.step()
        energy = world.kinetic_energy() + world.masses[0] * G * world.positions[0, 1]
        assert energy <= start * (1 + 1e-9)
        assert world.positions[0, 1] < 3.0 + 1e-9


@pytest.mark.parametrize("e", [0.5, 0.9])
@pytest.mark.parametrize("boxes", [1, 2])
def test_a_box_dropped_flat_bounces_flat(e, boxes):
    # Both bottom corners land and bounce at once, so nothing turns or moves sideways: a box
    # dropped flat 2 m onto the floor, or onto a box resting there. Measured while restitution
    # solved a lane's two points one after the other (before 2026-12, now
    # soft_step.batches.two_row_impulses): at restitution 0.9 the single box turned up to
    # 0.0275 rad, the box on a box 4.6e-3 rad; at 0.5, 1e-4 rad.
    bodies = [sim.Body.box(1, 1, position=(0.0, 2.5), restitution=e)]
    if boxes == 2:
        bodies.insert(0, sim.Body.box(1, 1, position=(0.0, 0.5), restitution=e))
    world = sim.World(sim.Scene(bodies=bodies))
    for _ in range(300):
        world.step()
        assert np.abs(world.angles).max() < 1e-12
        assert np.abs(world.positions[:, 0]).max() < 1e-12


def test_no_bounce_below_restitution_threshold():
    # impact at ~0.77 m/s, under the 1 m/s threshold: a restitution of 0.9 must not bounce
    scene = sim.Scene(bodies=[sim.Body.box(0.5, 0.5, position=(0.0, 0.25 + 0.03), restitution=0.9)])
    world = sim.World(scene)
    heights = []
    for _ in range(60):
        world.step()
        heights.append(world.positions[0, 1] - 0.25)
    low = int(np.argmin(heights))
    assert max(heights[low:]) < 0.005


def _momenta(world):
    p = world.masses @ world.velocities
    r, v = world.positions, world.velocities
    angular = float(
        world.inertias @ world.angular_velocities
        + world.masses @ (r[:, 0] * v[:, 1] - r[:, 1] * v[:, 0])
    )
    return p, angular


def test_momentum_conserved_in_gravity_free_collision():
    a = sim.Body.box(
        1.0,
        1.0,
        position=(-2.0, 0.0),
        velocity=(3.0, 0.5),
        angular_velocity=1.0,
        density=2.0,
        restitution=0.5,
    )
    b = sim.Body(
        vertices=[(-0.6, -0.4), (0.7, -0.5), (0.4, 0.6), (-0.5, 0.5)],
        position=(1.0, 0.3),
        angle=0.4,
        velocity=(-1.0, 0.0),
    )
    world = sim.World(sim.Scene(bodies=[a, b], gravity=(0.0, 0.0), floor_y=None))
    p0, l0 = _momenta(world)
    ke0 = world.kinetic_energy()
    run_until(world, 2.0)
    p1, l1 = _momenta(world)
    assert np.linalg.norm(world.velocities[0] - [3.0, 0.5]) > 0.5  # they did collide
    np.testing.assert_allclose(p1, p0, rtol=1e-10, atol=1e-10)
    assert l1 == pytest.approx(l0, rel=1e-9, abs=1e-9)
    assert world.kinetic_energy() <= ke0 * (1 + 1e-9)  # never gains energy


def _spinning_plank_beside(wall, spin, gap):
    """A 2 m plank, upright, spinning at ``spin`` rad/s about its centre, in zero gravity, its
    reach ``gap`` m short of a 5 cm wide, 10 m tall wall ('static', or a dynamic wall of density
    'light' 1 or 'heavy' 1000)."""
    plank = sim.Body.box(
        2.0, 0.05, position=(-0.025 - gap - 1.0, 2.0), angle=np.pi / 2, angular_velocity=spin
    )
    free = dict(gravity=(0.0, 0.0), floor_y=None)
    if wall == "static":
        post = sim.Body.box(0.05, 10.0, position=(0.0, 5.0))
        return sim.World(sim.Scene(bodies=[plank], static_bodies=[post], **free))
    density = 1.0 if wall == "light" else 1000.0
    post = sim.Body.box(0.05, 10.0, position=(0.0, 5.0), density=density)
    return sim.World(sim.Scene(bodies=[plank, post], **free))


@pytest.mark.parametrize("wall", ["static", "light", "heavy"])
@pytest.mark.parametrize("spin", [60.0, 100.0, 140.0])
def test_a_spinning_plank_is_not_pushed_by_a_wall_it_never_reaches(wall, spin):
    # Its corners pass 0.175 m from the wall, turning up to 0.58 rad a substep (140 rad/s, 4
    # substeps): the speculative contact made ahead of them must never push. Before the arms
    # kept the turning body's own anchor (soft_step.arms.line_arms), they read the velocity half
    # way to the wall's anchor: from ~80 rad/s the plank was pushed 5-20 m away in 2 s and lost
    # up to 20% of its spin.
    world = _spinning_plank_beside(wall, spin, gap=0.175)
    start = world.positions.copy()
    world.step(120)
    assert np.abs(world.positions - start).max() < 1e-9
    assert world.angular_velocities[0] == pytest.approx(spin, rel=1e-12)


def test_a_spinning_plank_striking_a_free_box_conserves_momentum():
    # The same plank at 30 rad/s with its reach 5 cm into a light box: it strikes it. However
    # the contact's line of action is shared between a fast-turning and a still body (the
    # turning one keeps its anchor), impulse and reaction act on one line.
    world = _spinning_plank_beside("light", 30.0, gap=-0.05)
    p0, l0 = _momenta(world)
    world.step(60)
    p1, l1 = _momenta(world)
    assert np.linalg.norm(world.velocities[1]) > 0.5  # it was struck
    np.testing.assert_allclose(p1, p0, rtol=1e-10, atol=1e-10)
    assert l1 == pytest.approx(l0, rel=1e-9, abs=1e-9)


@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
@pytest.mark.parametrize("mass_ratio", [1.0, 3.0])
def test_head_on_collision_gives_the_one_dimensional_answer(e, mass_ratio):
    # Two boxes meeting face to face, in zero gravity: Newton's law of restitution with momentum
    # conserved, v1' = ((m1 - e m2) v1 + (1 + e) m2 v2) / (m1 + m2) and symmetrically; no turn,
    # no sideways motion. (Measured exact to 4e-14 m/s.)
    v1, v2, m1, m2 = 2.0, -1.0, 1.0, mass_ratio
    a = sim.Body.box(1, 1, position=(-1.0, 0.0), velocity=(v1, 0.0), restitution=e)
    b = sim.Body.box(1, 1, position=(1.0, 0.0), velocity=(v2, 0.0), density=m2, restitution=e)
    world = sim.World(sim.Scene(bodies=[a, b], gravity=(0.0, 0.0), floor_y=None))
    world.step(120)
    after = [
        ((m1 - e * m2) * v1 + (1 + e) * m2 * v2) / (m1 + m2),
        ((m2 - e * m1) * v2 + (1 + e) * m1 * v1) / (m1 + m2),
    ]
    np.testing.assert_allclose(world.velocities[:, 0], after, rtol=0, atol=1e-12)
    assert np.abs(world.velocities[:, 1]).max() < 1e-12
    assert np.abs(world.angular_velocities).max() < 1e-12


def _box_overlap(world):
    """m: how far two unit boxes of ``world`` overlap (0 when apart): minus their largest
    separation along either's edge normals (tests/naive.py)."""
    corners = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
    verts = []
    for i in range(2):
        c, s = math.cos(world.angles[i]), math.sin(world.angles[i])
        verts.append(corners @ np.array([[c, s], [-s, c]]) + world.positions[i])
    sep = max(
        naive.axis_separations(verts[0], verts[1]).max(),
        naive.axis_separations(verts[1], verts[0]).max(),
    )
    return max(0.0, -sep)


@pytest.mark.parametrize("phase", range(4))
def test_boxes_meeting_corner_to_corner_do_not_interpenetrate(phase):
    """Two unit boxes, no gravity, one at rest and one coming at it along the diagonal at 2.1
    m/s (25 mm a step on each axis), corner to corner, the meeting at four phases of a step.
    The corners never overlap (a speculative contact at the closest points exists before they
    meet), and the head-on inelastic collision leaves both at the common velocity, half the
    mover's (momentum). Measured before that contact (geometry._closest_points): 5-25 mm of
    overlap, growing with the phase, and the two ended 0.1-0.3 m/s off the common velocity."""
    start = 1.25 + phase * 0.025 / 4
    a = sim.Body.box(1.0, 1.0, position=(0.0, 0.0))
    b = sim.Body.box(1.0, 1.0, position=(start, start), velocity=(-1.5, -1.5))
    world = sim.World(sim.Scene(bodies=[a, b], gravity=(0.0, 0.0), floor_y=None))
    deepest = 0.0
    for _ in range(30):
        world.step(1)
        deepest = max(deepest, _box_overlap(world))
    assert deepest < 1e-4, f"the corners overlapped by {deepest:.3g} m"
    np.testing.assert_allclose(world.velocities, [[-0.75, -0.75], [-0.75, -0.75]], atol=1e-3)


@pytest.mark.parametrize("height", [11.0, 20.0, 100.0])
@pytest.mark.parametrize("support", ["floor", "static box", "box"])
def test_a_slender_plank_stands_on_its_end(support, height):
    # A 0.1 m plank standing upright on its end carries its weight on two points 0.1 m apart,
    # whose rows are nearly the same row (the 2x2 mass matrix is near singular from an aspect
    # ratio of ~110 on). Both must push: before soft_step.batches.two_row_impulses solved such a
    # pair as one row, neither did, and a plank of 11 m or more fell through the floor as if it
    # were not there (exactly free fall: 4.9 m in the first second).
    static, bodies = [], []
    base = 0.0
    if support != "floor":
        box = sim.Body.box(2.0, 1.0, position=(0.0, 0.5))
        (static if support == "static box" else bodies).append(box)
        base = 1.0
    bodies.append(sim.Body.box(0.1, height, position=(0.0, base + height / 2)))
    world = sim.World(sim.Scene(bodies=bodies, static_bodies=static))
    start = world.positions
    world.step(120)
    assert np.abs(world.positions - start).max() < 1e-6
    assert np.abs(world.angles).max() < 1e-9


@pytest.mark.parametrize("on", ["floor", "static box"])
def test_a_face_given_in_parts_supports_as_one_face(on):
    # Collinear vertices are valid (polygons.validate_polygon), and a face split by them is
    # still one face. A box whose bottom was given in four parts rested on the first quarter
    # only, tipped over and sank 0.53 m into the floor; a box on a static box whose top was
    # given in parts fell off it (polygons.drop_collinear).
    split = SPLIT_BOX
    if on == "floor":
        scene = sim.Scene(bodies=[sim.Body(vertices=split, position=(0.0, 0.5))])
    else:
        top = [(x, -y) for x, y in reversed(split)]  # the top edge in four parts
        scene = sim.Scene(
            bodies=[sim.Body.box(1, 1, position=(0.3, 1.5))],
            static_bodies=[sim.Body(vertices=top, position=(0.0, 0.5))],
        )
    world = sim.World(scene)
    start = world.positions
    world.step(120)
    assert np.abs(world.positions - start).max() < 1e-6
    assert abs(world.angles[0]) < 1e-9


@pytest.mark.parametrize("sides", [64, 300, 1024])
def test_a_many_sided_polygon_rests_where_it_is_placed(sides):
    # A regular polygon of many sides (the World takes up to 1024) placed on one of its edges:
    # the edge is short, so its two points are close and their rows nearly one (see the plank).
    # From 282 sides on, the polygon fell through the floor before the two were solved as one.
    radius = 0.5
    body = sim.Body.regular(sides, radius, position=(0.0, radius * math.cos(math.pi / sides)))
    world = sim.World(sim.Scene(bodies=[body]))
    start = world.positions
    world.step(120)
    assert np.abs(world.positions - start).max() < 1e-6
    assert abs(world.angles[0]) < 1e-9


@pytest.mark.parametrize("offset_deg,falls", [(-2.0, False), (2.0, True)])
def test_tall_box_tips_past_critical_angle(offset_deg, falls):
    w, h = 0.5, 2.0
    critical = math.atan(w / h)  # centre of mass right above the corner
    angle = critical + math.radians(offset_deg)
    world = sim.World(sim.Scene(bodies=[tilted_box(w, h, angle)]))
    # back upright, it rocks: a slender block keeps ~91% of its angular velocity at each landing
    # (Housner's rocking block, 1 - 3/2 sin^2(atan(w/h))), so it takes seconds to come to rest
    # (measured: 6.5 s, never past 0.13 rad the other way, half the critical angle)
    steepest = 0.0
    for _ in range(8 * 60):
        world.step()
        if world.step_count > 60:
            steepest = max(steepest, abs(world.angles[0]))
    if not falls:
        assert steepest < critical  # it never tipped over the other way
    if falls:
        assert world.angles[0] == pytest.approx(math.pi / 2, abs=0.01)  # lying on its side
        assert world.positions[0, 1] == pytest.approx(w / 2, abs=0.006)
    else:
        assert world.angles[0] == pytest.approx(0.0, abs=0.01)  # back upright
        assert world.positions[0, 1] == pytest.approx(h / 2, abs=0.006)


def gap_landing(density=1.0):
    """Two unit boxes on the floor 0.125 m apart and a third (``density`` times as dense) whose
    bottom is 0.5 m above their tops, centred over the gap: it falls flat and lands on both at
    once (3.1 m/s)."""
    pitch = 1.125
    return sim.Scene(
        bodies=[
            sim.Body.box(1, 1, position=(-pitch / 2, 0.5)),
            sim.Body.box(1, 1, position=(pitch / 2, 0.5)),
            sim.Body.box(1, 1, position=(0.0, 2.0), density=density),
        ]
    )


#: measured (3 s): the most any box moved sideways, with that many relax sweeps per substep
RELAX_SWEEPS_SLIDE = {2: 0.97e-3, 4: 0.79e-3, 16: 1.25e-3}


@pytest.mark.parametrize(
    "relax",
    [1]
    + [
        pytest.param(
            r,
            marks=pytest.mark.xfail(
                strict=True,
                reason=(
                    f"measured: with {r} relax sweeps per substep a box moves "
                    f"{RELAX_SWEEPS_SLIDE[r] * 1e3:.2f} mm sideways (1 sweep: 0.04 mm). The "
                    "landing's first impulse comes in the relax sweeps of the substep before "
                    "contact (the speculative row binds once the positions are integrated), "
                    "where friction is solved before the normal rows; cause of the growth with "
                    "more sweeps not found (docs/ARCHITECTURE.md section 2.3, 'More relax sweeps')"
                ),
            ),
        )
        for r in sorted(RELAX_SWEEPS_SLIDE)
    ],
)
def test_box_landing_across_a_gap_stays_centred(relax):
    # Symmetry: a box dropped flat, centred over the gap between two boxes resting on the floor,
    # lands on both at once; nothing pushes anything sideways, so every box ends where it started
    # in x and unturned. More sweeps of the solver must not break that: the relax sweeps are a
    # documented knob (World's relax_iterations).
    world = sim.World(gap_landing(), relax_iterations=relax)
    start = world.positions
    world.step(180)
    assert np.abs(world.positions[:, 0] - start[:, 0]).max() < 1e-4
    assert np.abs(world.angles).max() < 1e-3
    assert world.positions[2, 1] == pytest.approx(1.5, abs=1e-4)


#: measured (3 s): the most any box moved sideways when the falling box is that many times as heavy
#: as each of the two below (pybullet at its 50 iterations: 0.24 / 2.2 mm; Box2D 2.3: 0.55 / 4.5 mm)
HEAVY_LANDING_SLIDE = {20: 6.0e-3}


@pytest.mark.parametrize(
    "ratio",
    [
        pytest.param(
            r,
            marks=pytest.mark.xfail(
                strict=True,
                reason=(
                    f"measured: a box {r} times as heavy as the two it lands on slides "
                    f"{HEAVY_LANDING_SLIDE[r] * 1e3:.1f} mm sideways (5 times: 0.055 mm). In "
                    "its landing step the right light box is pushed out 1.8 mm and the left "
                    "0.01 mm: the two contacts share the falling box, so they are solved in "
                    "turn. Its contacts are hard (soft_step.HARD_RATIO), and hard batches get no "
                    "impact sweeps. Before soft_step.batches.two_row_impulses: 37.7 mm (5 times: "
                    "0.36 mm), the landing bounced it 31 mm; with impact sweeps in hard batches "
                    "1.1 mm, but a dropped 100:1 stack under sleep then kept 11 mm of overlap "
                    "(docs/ARCHITECTURE.md section 2.3, 'Landings')"
                ),
            ),
        )
        if r in HEAVY_LANDING_SLIDE
        else r
        for r in (5, 20)
    ],
)
def test_heavy_box_landing_across_a_gap_stays_centred(ratio):
    # The same symmetric landing with the falling box ``ratio`` times as dense: the exact answer
    # still moves nothing sideways. Measured: 0.055 mm at 5 times (20 times: the xfail above);
    # within 0.2 mm.
    world = sim.World(gap_landing(density=float(ratio)))
    start = world.positions
    world.step(180)
    assert np.abs(world.positions[:, 0] - start[:, 0]).max() < 2e-4


def test_pyramid_20_stands_ten_seconds():
    world = sim.World(sim.scenes.pyramid(20))
    start = world.positions
    run_until(world, 10.0)
    # measured: no box moves 1e-6 m (the top box 5.7e-7 m); penetration 3.5e-10 m
    assert np.linalg.norm(world.positions[-1] - start[-1]) < 1e-5  # the top box
    assert np.abs(world.positions - start).max() < 1e-5
    assert world.penetration < 1e-5


def test_stack_of_ten_holds():
    world = sim.World(sim.scenes.stack(10))
    start = world.positions
    run_until(world, 10.0)
    # measured (2026-12-06): no box moves 3.1e-14 m or turns at all
    assert np.abs(world.positions - start).max() < 1e-9
    assert np.abs(world.angles).max() < 1e-9


def test_arch_stands():
    world = sim.World(sim.scenes.arch())
    start = world.positions
    run_until(world, 10.0)
    # measured (2026-12-06): no block moves 3.2e-8 m or turns 3.1e-10 rad
    assert np.abs(world.positions - start).max() < 1e-6
    assert np.abs(world.angles).max() < 1e-6


def test_drop_pile_settles_inside_the_bin():
    scene = sim.scenes.drop(30, seed=2)
    world = run_until(sim.World(scene), 8.0)
    walls = [b.position[0] for b in scene.static_bodies]
    assert np.all(world.positions[:, 0] > min(walls)) and np.all(world.positions[:, 0] < max(walls))
    assert np.all(world.positions[:, 1] > 0.0)
    # measured (2026-12-06): kinetic energy 3.6e-9 J after 8 s, overlap 0.42 mm
    assert world.kinetic_energy() < 1e-6  # at rest (the pile's weight falling 1 cm: 0.5 J)
    assert world.penetration < 2e-3


def test_seed_fig3_upper_body_slides_off_and_lands_on_the_floor():
    world = run_until(sim.World(sim.scenes.seed_fig3()), 4.0)
    a, b = world.positions
    # measured (2026-12-06): A ends at x 2.16 m lying on the floor (y 0.2), B moved 0.21 mm
    assert a[0] > 1.0  # past B's right edge (x = 1)
    assert a[1] == pytest.approx(0.2, abs=1e-3)  # down on the floor, on its long side (0.4 tall)
    assert np.linalg.norm(b - (0.0, 0.5)) < 1e-3  # B barely moved


def test_seed_fig2_lands_on_top_edge():
    world = run_until(sim.World(sim.scenes.seed_fig2()), 4.0)
    a, b = world.positions
    # measured (2026-12-06): 1.6e-7 m off that height, turned 6.9e-8 rad
    assert a[1] == pytest.approx(1.0 + 0.4, abs=1e-5)  # on B's top face (B is 1 tall, A 0.8)
    assert (
        abs(world.angles[0]) % (math.pi / 2) < 1e-5
        or abs(abs(world.angles[0]) % (math.pi / 2) - math.pi / 2) < 1e-5
    )


def test_friction_mixes_by_geometric_mean():
    # box mu 0.2 on a floor of mu 0.8: sqrt(0.16) = 0.4 (an arithmetic mean would give 0.5)
    box = sim.Body.box(1, 1, position=(0.0, 0.5), velocity=(3.0, 0.0), friction=0.2)
    world = sim.World(sim.Scene(bodies=[box], floor_friction=0.8), dt=1 / 240)
    run_until(world, 2.0)
    assert world.positions[0, 0] == pytest.approx(9.0 / (2 * 0.4 * G), rel=0.01)


def test_box_rests_on_a_static_ledge():
    ledge = sim.Body.box(2.0, 0.5, position=(0.0, 3.0), name="ledge")
    box = sim.Body.box(1.0, 1.0, position=(0.3, 3.25 + 0.5 + 0.2))  # dropped 0.2 m onto it
    world = run_until(sim.World(sim.Scene(bodies=[box], static_bodies=[ledge])), 3.0)
    # after an impact, position correction leaves exactly up to `slop` of penetration, no more
    assert 3.75 - world.slop - 1e-9 <= world.positions[0, 1] <= 3.75
    assert world.positions[0, 0] == pytest.approx(0.3, abs=1e-3)


def test_contact_report_balances_weight():
    world = run_until(sim.World(sim.scenes.stack(3)), 1.0)
    c = world.contacts()
    floor = c["body_a"] == -1
    # the floor carries all three boxes: sum of normal impulses = total weight * dt
    assert c["normal_impulse"][floor].sum() == pytest.approx(
        world.masses.sum() * G * world.dt, rel=1e-3
    )
    np.testing.assert_allclose(c["normal"][floor], [[0.0, 1.0]] * int(floor.sum()))
    assert np.all(c["separation"] > -5e-3)


@pytest.mark.parametrize("n", [3, 5, 8, 64])
def test_regular_polygon_rests_on_its_flat_side(n):
    radius = 0.5
    poly = sim.Body.regular(n, radius)
    bottom = -float(poly.vertices[:, 1].min())  # flat bottom edge at y = -bottom
    poly.position = (0.0, bottom - float(poly.centroid[1]))  # vertices are centred on the COM
    world = sim.World(sim.Scene(bodies=[poly]))
    start = world.positions
    run_until(world, 5.0)
    assert np.linalg.norm(world.positions - start) < 1e-3
    assert abs(world.angles[0]) < 1e-3


def test_polygon_dropped_on_a_vertex_settles_on_a_face():
    # point down, tilted 0.1 rad off balance (dropped exactly point-down it would balance on the
    # vertex, an unstable equilibrium that round-off leaves only after many seconds)
    tri = sim.Body.regular(3, 0.6, position=(0.0, 2.0), angle=math.pi / 3 + 0.1)
    world = run_until(sim.World(sim.Scene(bodies=[tri])), 6.0)
    # an equilateral triangle ends on one of its three faces: angle a multiple of 2 pi / 3
    k = world.angles[0] / (2 * math.pi / 3)
    assert abs(k - round(k)) < 0.01
    assert np.abs(world.velocities).max() < 1e-3


def test_friction_between_bodies_mixes_by_geometric_mean():
    # a box (mu 0.2) sliding along a long static slab (mu 0.8): sqrt(0.16) = 0.4
    slab = sim.Body.box(20.0, 1.0, position=(0.0, 0.5), friction=0.8)
    box = sim.Body.box(1, 1, position=(-5.0, 1.5), velocity=(3.0, 0.0), friction=0.2)
    world = sim.World(sim.Scene(bodies=[box], static_bodies=[slab]), dt=1 / 240)
    run_until(world, 2.0)
    assert world.positions[0, 0] + 5.0 == pytest.approx(9.0 / (2 * 0.4 * G), rel=0.01)


# ---- fast paths: skipped work must not change a single bit ------------------------------------
def _pile(mu):
    boxes = [
        sim.Body.box(
            1.0,
            1.0,
            position=(1.6 * c + 0.3 * (i % 2), 0.55 + 1.1 * i),
            angle=0.05 * i,
            friction=mu,
        )
        for c in range(4)
        for i in range(4)
    ]
    boxes.append(sim.Body.box(0.5, 0.5, position=(-3.0, 0.3), velocity=(4.0, 0.0), friction=mu))
    return sim.Scene(bodies=boxes, floor_friction=mu)


@pytest.mark.parametrize("freeze", ["off", "extended"])
@pytest.mark.parametrize("mu", [0.0, 0.5])
def test_fast_paths_change_nothing(freeze, mu):
    """Skipping the friction rows of frictionless contacts is exact (their impulse is clamped to
    zero anyway), and frictional contacts keep theirs: the same scene with and without fast paths
    is bit for bit the same run."""
    runs = []
    for fast in (True, False):
        w = sim.World(_pile(mu), freeze=freeze, fast_paths=fast)
        w.step(120)
        runs.append((w.positions, w.angles, w.velocities))
    for a, b in zip(*runs):
        np.testing.assert_array_equal(a, b)


def test_fast_paths_are_validated():
    with pytest.raises(ValueError, match="unknown fast path"):
        sim.World(sim.scenes.single_box(), fast_paths=["bogus"])
    assert sim.World(sim.scenes.single_box(), fast_paths=False).fast_paths == ()
    assert sim.World(sim.scenes.single_box()).fast_paths == ("friction", "quiet")


#: m/s, the largest speed of any body of each drop(30) pile in the 20th second, sim-off at its
#: defaults, for the piles that do not come to rest; a pile listed here is a strict xfail. None of
#: seeds 0-4 since a two-point manifold on an immovable body carries its load's split at once (the
#: soft step's store). From the corner contacts (geometry._closest_points) to that, seed 1: its body
#: 12 (28 g, 8 cm thin), pinched between the floor, the bin's wall and heavier polygons and carrying
#: 170 times its weight, slipped at 2.8e-4 m/s. Over seeds 0-99, 9 piles do not come to rest, before
#: the carried split as after it (13 before the corner contacts; median step after which no body
#: moves at 1 mm/s: 358.5 before it, 346.5 after). None from the deep sweeps (soft_step.DEEP_SWEEPS)
#: to the corner contacts. Before the deep sweeps seed 2 crept: body 17 (230 g), held between a 30 g
#: and a 132 g polygon, at 1.4e-4 m/s (2.2-2.4 um a step), and before the impact sweeps seed 4
#: instead (body 20, 18 g, pinched between polygons 10-20 times heavier, slipping in jerks of ~4
#: mm/s). The same piles in pymunk moved at most 4e-7 m over that second, Box2D 2.3 2e-4 m, pybullet
#: 2e-3 to 8e-3 m.
PILE_CREEP = {}
#: seeds whose pile does come to rest
PILES_AT_REST = (0, 1, 2, 3, 4)


@pytest.mark.parametrize(
    "seed",
    [
        pytest.param(
            seed,
            marks=pytest.mark.xfail(
                strict=True,
                reason=(
                    f"measured: the pile still moves at {speed:.2g} m/s after 19 s: one "
                    "polygon pinched under heavier ones creeps (see PILE_CREEP; issue 11's drift)"
                ),
            ),
        )
        for seed, speed in PILE_CREEP.items()
    ]
    + list(PILES_AT_REST),
)
def test_a_dropped_pile_comes_to_rest(seed):
    # Static equilibrium: once a pile of polygons has settled in its bin (30 polygons dropped from
    # up to ~8 m come to rest within ~3 s in every peer), nothing in it moves. Every body moves
    # less than 0.1 mm over the 20th second.
    world = sim.World(sim.scenes.drop(30, seed=seed))
    world.step(19 * 60)
    start = world.positions.copy()
    world.step(60)
    assert np.hypot(*(world.positions - start).T).max() < 1e-4


def test_most_dropped_piles_come_to_rest():
    # The same on 20 piles, so that no one chaotic pile decides it: all 20 come to rest (moving
    # less than 0.1 mm over the 20th second; measured 2026-12-06 on the Intel AVX-512 machine;
    # 18, all but seeds 1 and 14, at an earlier commit after the corner contacts; 17 before the
    # deep sweeps, soft_step.DEEP_SWEEPS, 16 before the impact sweeps). The bound leaves two: the
    # piles are chaotic, and another CPU's rounding makes other piles (89 of seeds 0-99 at rest
    # on an AMD machine against 91 here, ARCHITECTURE). When a point's feature id changed (the
    # other body's face became the reference face, as it does between two nearly parallel faces
    # whenever the full narrowphase runs again) it restarted without its load and friction, and
    # only 2 of the 20 came to rest.
    at_rest = 0
    for seed in range(20):
        world = sim.World(sim.scenes.drop(30, seed=seed))
        world.step(19 * 60)
        start = world.positions.copy()
        world.step(60)
        at_rest += np.hypot(*(world.positions - start).T).max() < 1e-4
    assert at_rest >= 18


@pytest.mark.parametrize(
    ("body", "size"),
    [
        (sim.Body.box(2.0, 0.05), 0.05),
        (sim.Body.regular(6, 1.0), math.sqrt(3.0)),
        (sim.Body(vertices=[(0, 0), (3, 0), (0, 4)]), 2.4),
    ],
)
def test_a_bodys_size_is_its_thinnest_width(body, size):
    # the length its contact tolerances scale with (sim.tolerances), public for the peers'
    # comparable settings (study.common.comparable_slop)
    assert body.size == pytest.approx(size, rel=1e-12)
