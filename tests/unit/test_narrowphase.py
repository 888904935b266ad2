"""The narrowphase's shortcuts never hide a contact.

``narrowphase.update_manifolds`` skips a pair that was apart while its last separating-axis gap,
less how far its bodies have since moved, exceeds the speculative margin. That is safe only if the
gap ``geometry.collide_*_rows`` report is a lower bound on the distance between the shapes, and if
the skip is never taken for a pair that has come near. Both are checked here: the gap against an
exact distance (``naive.polygon_distance``) on random polygons, and the whole pipeline on a
settling pile, where every pair of bodies that starts a step within half its resting speculative
reach must have been given contact points that step.
"""

import math

import numpy as np
import pytest

import naive
import sim
from sim import geometry
from sim.tolerances import body_speculative


def random_convex(rng, centre):
    n = int(rng.integers(3, 9))
    angles = np.sort(rng.uniform(0.0, 2.0 * math.pi, n))
    if np.diff(np.concatenate([angles, [angles[0] + 2 * math.pi]])).max() > 0.9 * math.pi:
        angles = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False) + rng.uniform(0, 1)
    radius = rng.uniform(0.2, 1.0)
    return np.column_stack([np.cos(angles), np.sin(angles)]) * radius + centre


@pytest.mark.parametrize("seed", range(4))
def test_the_reported_gap_is_a_lower_bound_on_the_distance(seed):
    rng = np.random.default_rng(seed)
    apart = 0
    for _ in range(300):
        a = random_convex(rng, (0.0, 0.0))
        b = random_convex(rng, rng.uniform(-2.5, 2.5, 2))
        margin = float(rng.uniform(0.0, 0.5))
        out = np.zeros((2, 2)), np.zeros(2), np.zeros(2, np.int64), np.zeros(2)
        count, _, _, gap = geometry.collide_polygons(
            a, geometry.edge_normals(a), b, geometry.edge_normals(b), margin, *out
        )
        if naive.polygons_intersect(a, b):
            assert gap <= 1e-12
            continue
        distance, _ = naive.polygon_distance(a, b)
        assert gap <= distance + 1e-12
        # the best gap over both polygons' axes, or over A's alone when that already exceeds the
        # margin (the search stops there)
        if naive.max_separation(a, b)[1] > margin:
            assert gap == pytest.approx(naive.max_separation(a, b)[1], abs=1e-12)
        else:
            assert gap == pytest.approx(naive.sat_separation(a, b), abs=1e-12)
        apart += count == 0
    assert apart > 50


def test_the_floor_gap_is_the_height_of_the_lowest_vertex():
    rng = np.random.default_rng(7)
    for _ in range(100):
        v = random_convex(rng, (0.0, rng.uniform(-1.0, 3.0)))
        floor_y = float(rng.uniform(-0.5, 0.5))
        count, gap = geometry.collide_floor(
            v,
            geometry.edge_normals(v),
            floor_y,
            0.1,
            np.zeros((2, 2)),
            np.zeros(2),
            np.zeros(2, np.int64),
        )
        assert gap == pytest.approx(v[:, 1].min() - floor_y, abs=1e-12)
        assert (count > 0) == (gap <= 0.1)


def _world_polygons(scene, positions, angles):
    out = []
    for body, p, a in zip(scene.bodies, positions, angles):
        _, centre, _ = geometry.mass_properties(np.asarray(body.vertices, float), body.density)
        local = np.asarray(body.vertices, float) - centre
        c, s = math.cos(a), math.sin(a)
        out.append(local @ np.array([[c, s], [-s, c]]) + p)
    return out


def test_every_pair_that_comes_near_gets_contact_points_in_a_settling_pile():
    scene = sim.scenes.drop(40, seed=3)
    world = sim.World(scene)
    reach = body_speculative(world.sizes[: len(scene.bodies)], world.speculative_distance)
    skipped = checked = 0
    for _ in range(150):
        polygons = _world_polygons(scene, world.positions, world.angles)
        world.step(1)
        points = world.contacts()
        touching = {(int(a), int(b)) for a, b in zip(points["body_a"], points["body_b"])}
        skipped += world.inspect().n_skipped
        for i in range(len(polygons)):
            for j in range(i + 1, len(polygons)):
                near = 0.5 * min(reach[i], reach[j])
                lo = np.maximum(polygons[i].min(0), polygons[j].min(0))
                hi = np.minimum(polygons[i].max(0), polygons[j].max(0))
                if (lo - hi).max() > near:
                    continue  # boxes apart by more than that
                if naive.polygons_intersect(polygons[i], polygons[j]):
                    distance = 0.0
                else:
                    distance, _ = naive.polygon_distance(polygons[i], polygons[j])
                if distance <= near:
                    checked += 1
                    assert (i, j) in touching, (world.step_count, i, j, distance)
    assert skipped > 1000 and checked > 1000, (skipped, checked)
