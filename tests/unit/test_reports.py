"""``World.contacts()`` (``sim.reports.contact_points``): every point of every active contact, each
the point it is, not its manifold's first one again."""

import numpy as np

import sim
from sim.scenes import rest_row, stack


def _by_pair(points):
    pairs = {}
    for k, (a, b) in enumerate(zip(points["body_a"], points["body_b"])):
        pairs.setdefault((int(a), int(b)), []).append(k)
    return pairs


def test_a_box_resting_flat_reports_its_two_bottom_corners():
    # rest_row(3): unit boxes on the floor, each touching the floor at its two bottom corners;
    # stack(3): each box on the one below at the same two corners. A manifold's second point
    # read at the first's place (a wrong point index) repeats one corner twice.
    for scene in (rest_row(3), stack(3)):
        w = sim.World(scene)
        w.step(2)
        points = w.contacts()
        pairs = _by_pair(points)
        assert len(pairs) == 3
        for (_, b), rows in pairs.items():
            assert len(rows) == 2
            x = np.sort(points["point"][rows, 0]) - w.positions[b, 0]
            np.testing.assert_allclose(x, [-0.5, 0.5], atol=1e-3)
            y = points["point"][rows, 1] - (w.positions[b, 1] - 0.5)
            np.testing.assert_allclose(y, 0.0, atol=1e-3)
            # each point carries its share of the box's load (and the floor's of the whole
            # stack): the two halves of a symmetric landing
            impulses = points["normal_impulse"][rows]
            assert impulses.min() > 0.0
            np.testing.assert_allclose(impulses[0], impulses[1], rtol=1e-3)


def test_each_report_is_a_copy():
    w = sim.World(rest_row(2))
    w.step(1)
    first = w.contacts()
    for name, array in first.items():
        array[...] = -7  # changing a report changes neither the run nor the next report
    again = w.contacts()
    for name, array in again.items():
        assert not (np.asarray(array) == -7).all(), name
