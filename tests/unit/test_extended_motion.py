"""`extended` against `off` where a user's test found it wrong (2026-12): bodies frozen while
they moved (a pair that leans on each other, a body drifting without gravity), and impacts on
frozen bodies missed or underestimated (one ending a substep's travel apart, a bounce, a small
body). Each case: the physics answer, and the off reference on the same scene."""

import math

import numpy as np
import pytest

import sim
from naive import complementary_impulses
from sim import State
from sim.freeze.contact_math import stopping_impulses


def woken(world, body, cause):
    """Steps at which ``body`` was woken by ``cause``."""
    return [s for s, b, _, to, c in world.events if b == body and to == State.FREE and c == cause]


def _leaning_plank(density):
    """A 0.1 x 2 m plank leaning 15 degrees on the side of a 1 x 3 m box P of ``density``; P is
    frictionless (against the floor and the plank), so the plank's push drives it away."""
    tilt = math.radians(15.0)
    corners = [(-0.05, -1.0), (0.05, -1.0), (0.05, 1.0), (-0.05, 1.0)]
    turned = [
        (x * math.cos(tilt) + y * math.sin(tilt), -x * math.sin(tilt) + y * math.cos(tilt))
        for x, y in corners
    ]
    low = min(y for _, y in turned)
    right = max(x for x, _ in turned)
    plank = sim.Body.box(0.1, 2.0, position=(0.0, -low), angle=-tilt, friction=0.8)
    box = sim.Body.box(1.0, 3.0, position=(right + 0.5, 1.5), friction=0.0, density=density)
    return sim.Scene(bodies=[plank, box], floor_friction=0.8)


@pytest.mark.parametrize("density", [3.0, 50.0])
def test_a_box_pushed_by_a_plank_leaning_on_it_slides_away(density):
    # Nothing holds P against the plank's push (0.26 N): it must accelerate (2e-3 m/s^2 at
    # density 50). Before, the pair was certified as one rigid body in step 1, on the solver's
    # impulses, which leave P's push unbalanced (its acceleration under the steadiness gate's
    # 0.1 m/s^2): both froze and P never moved (off: 0.33 m in 5 s at density 3).
    scene = _leaning_plank(density)
    off = sim.World(scene).step(300)
    world = sim.World(scene, freeze="extended").step(300)
    assert off.positions[1, 0] - scene.bodies[1].position[0] > 1e-3  # P moves under off
    np.testing.assert_allclose(world.positions, off.positions, atol=1e-6)


@pytest.mark.parametrize("friction", [0.0, 0.6])
def test_a_box_drifting_along_the_floor_without_gravity_keeps_drifting(friction):
    # Newton's first law: nothing presses it onto the floor, so no friction stops it; 1 cm/s for
    # 10 s is 0.1 m. Before, zero forces "balanced" its zero weight and it froze in step 2. A box
    # that is still there is at rest, and freezes.
    def scene(speed):
        box = sim.Body.box(1.0, 1.0, position=(0.0, 0.5), velocity=(speed, 0.0), friction=friction)
        return sim.Scene(bodies=[box], floor_friction=friction, gravity=(0.0, 0.0))

    world = sim.World(scene(0.01), freeze="extended").step(600)
    assert world.positions[0, 0] == pytest.approx(0.1, abs=1e-9)
    assert not world.frozen[0]
    still = sim.World(scene(0.0), freeze="extended").step(5)
    assert still.frozen[0]


@pytest.mark.parametrize("gap", [0.001, 0.004, 0.01])
@pytest.mark.parametrize("gravity", [False, True])
def test_a_box_drifting_onto_a_wall_reaches_it_before_it_freezes(gap, gravity):
    # A 1 m box moving at 1 cm/s toward a static wall ``gap`` away, nothing else slowing it
    # (no gravity, or a frictionless floor): it stops where it meets the wall (restitution 0),
    # as under off. A point within slop counts as touching, so the wall was a support before the
    # box reached it, and one that could stop its drift: it froze at once 1 mm short (gap 1 mm),
    # or 5 mm short (gap 1 cm, at the slop), still moving. On the frictionless floor the floor's
    # contact slips at its (zero) friction limit, which keeps the box awake first ("sliding").
    def scene():
        box = sim.Body.box(1.0, 1.0, position=(0.0, 0.5), velocity=(0.01, 0.0), friction=0.0)
        wall = sim.Body.box(1.0, 4.0, position=(1.0 + gap, 2.0), friction=0.0)
        if gravity:
            return sim.Scene(bodies=[box], static_bodies=[wall], floor_friction=0.0)
        return sim.Scene(bodies=[box], static_bodies=[wall], gravity=(0.0, 0.0), floor_y=None)

    steps = int(gap / 0.01 / (1.0 / 60.0)) + 60  # to the wall, then a second
    reference = sim.World(scene(), freeze="off").step(steps)
    assert reference.positions[0, 0] == pytest.approx(gap, abs=1e-5)
    world = sim.World(scene(), freeze="extended")
    reasons = set()
    while not world.frozen[0] and world.step_count < steps:
        world.step()
        reasons.update(world.why_awake())
    assert world.frozen[0]
    assert world.positions[0, 0] == pytest.approx(gap, abs=1e-5)
    assert ("sliding" if gravity else "closing") in reasons


@pytest.mark.parametrize("gap", [0.305, 0.33, 0.355])
def test_a_box_fired_at_a_frozen_box_passes_its_momentum_on(gap):
    # A 0.81 kg box at 3 m/s hits a frozen 1 kg box from the side, starting `gap` m away, so
    # that it arrives at another point of a step each time. The frozen box must wake before the
    # solve (an impact), so that the collision is solved between two moving bodies: then the run
    # is off's. Before, at gaps 0.305 and 0.355 the box ended the impact step 5 mm short, which
    # the impact rule took for no impact, but the relax sweep after the last substep stopped it
    # against the frozen box: 60% of the momentum was lost (2.43 -> 0.97 N s) and the target
    # ended 0.18 m from the start instead of 1.02 m.
    target = sim.Body.box(1.0, 1.0, position=(0.0, 0.5), friction=0.1)
    shot = sim.Body.box(
        0.3, 0.3, position=(-0.65 - gap, 0.55), velocity=(3.0, 0.0), density=9.0, friction=0.1
    )
    scene = sim.Scene(bodies=[target, shot], floor_friction=0.1)
    off = sim.World(scene).step(120)
    world = sim.World(scene, freeze="extended").step(120)
    assert woken(world, 0, "impact")
    assert world.positions[0, 0] == pytest.approx(off.positions[0, 0], abs=1e-3)
    assert world.positions[0, 0] > 0.9


def test_a_bouncing_box_wakes_the_frozen_box_it_lands_on():
    # A 0.25 kg box with restitution 1 dropped 1 m onto a resting 1 kg box: every landing hands
    # the base 2 x 0.57 N s (stopped, then bounced), 1.1 m/s over its mass. Before, each corner
    # was judged alone (0.23 N s each: the box's whole momentum taken at a corner, its rotation
    # free) and without the bounce: the base was woken by 2 of the 11 landings, and the box
    # bounced 44 times in 20 s off a base that took nothing (off: 6).
    base = sim.Body.box(1.0, 1.0, position=(0.0, 0.5))
    ball = sim.Body.box(0.5, 0.5, position=(0.0, 2.25), restitution=1.0)
    scene = sim.Scene(bodies=[base, ball])
    off = sim.World(scene)
    world = sim.World(scene, freeze="extended")
    heights = {"off": [], "extended": []}
    for _ in range(240):
        for name, w in (("off", off), ("extended", world)):
            w.step()
            heights[name].append(w.positions[1, 1])
    assert len(woken(world, 0, "impact")) >= 4

    def peaks(h):
        h = np.asarray(h)
        return h[1:-1][(h[1:-1] > h[:-2]) & (h[1:-1] >= h[2:])]

    expected = peaks(heights["off"])[:4]
    assert len(expected) == 4
    np.testing.assert_allclose(peaks(heights["extended"])[:4], expected, atol=0.01)


def test_an_impact_on_a_small_frozen_box_wakes_it():
    # The impact rule is a speed (impact_speed: the impulse over the frozen body's mass), the
    # same at every size. A 1 cm box thrown down at 1 m/s from 10 cm above an equal frozen one
    # hands it ~1.7 m/s. With the old threshold of 0.5 N s (1.7e-4 N s here) no impact on a body
    # under ~0.3 kg ever woke it.
    s = 0.01
    base = sim.Body.box(s, s, position=(0.0, s / 2))
    top = sim.Body.box(s, s, position=(0.0, 1.5 * s + 0.1), velocity=(0.0, -1.0))
    world = sim.World(sim.Scene(bodies=[base, top]), freeze="extended", substeps=16)
    world.step(1)
    assert world.frozen[0]  # the base froze at once
    world.step(10)
    assert woken(world, 0, "impact")


def test_the_impact_estimate_solves_a_two_point_contact_as_one_complementarity_problem():
    # What a frozen body's impact wake reads (contact_math.impact_impulses): the impulses that
    # stop a body closing at two points of one contact, against a slow reference that shares
    # nothing with the enumeration (tests/naive.py). The draws include the block pulling at
    # either point (both points on one side of the centre, one closing much faster: stopping it
    # turns the body away from the other); until b40d9d7 that case kept the larger impulse of
    # the two points taken alone, wrong when the two points lie on one side of the centre.
    rng = np.random.default_rng(7)
    pulled = 0
    for _ in range(400):
        v0, v1 = -rng.uniform(0.0, 3.0, 2)
        r0, r1 = rng.uniform(-1.0, 1.0, 2)
        inv_m, inv_i = rng.uniform(0.1, 2.0, 2)
        K = inv_m + inv_i * np.array([[r0 * r0, r0 * r1], [r0 * r1, r1 * r1]])
        if np.linalg.det(K) < 1e-3 * K[0, 0] * K[1, 1]:
            continue  # nearly coincident points: the estimate shares one row (below)
        p = np.array(stopping_impulses(v0, v1, r0, r1, inv_m, inv_i))
        expected = complementary_impulses(K, np.array([v0, v1]))
        assert p == pytest.approx(expected, abs=1e-9 * (1.0 + expected.max()))
        pulled += int(expected.min() == 0.0)
    assert pulled > 20  # the pull case is exercised, not only the block


def test_two_coincident_points_of_an_impact_take_one_rows_impulse():
    # K singular: the block is refused, and the pair takes what one point alone would stop
    p = stopping_impulses(-2.0, -2.0, 0.3, 0.3, 1.0, 0.5)
    assert sum(p) == pytest.approx(2.0 / (1.0 + 0.5 * 0.09), rel=1e-12)
    assert min(p) >= 0.0
