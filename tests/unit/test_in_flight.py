"""``study.in_flight``: bench_freeze's part 4 restarts each phase from a run's state. A restarted
scene must be the run's bodies where the run left them, moving as they moved: otherwise a phase
would time some other motion."""

import numpy as np

import sim
from study import in_flight


def _off_centre_scene():
    """Two polygons whose frames are far from their centroids, spinning and flying, in a scene
    with a floor far below: nothing touches in the steps taken."""
    tri = sim.Body(
        vertices=[(2.0, 1.0), (3.0, 1.0), (2.2, 1.8)],
        position=(0.0, 50.0),
        angle=0.3,
        velocity=(1.0, 2.0),
        angular_velocity=1.5,
        friction=0.3,
        restitution=0.2,
    )
    box = sim.Body.box(0.5, 0.8, position=(5.0, 40.0), velocity=(-1.0, 0.0), angular_velocity=-2.0)
    return sim.Scene(bodies=[tri, box], name="pair", params={"n": 2})


def test_a_restarted_scene_is_the_run_where_it_was():
    scene = _off_centre_scene()
    run = sim.World(scene).step(7)
    again = sim.World(in_flight.restarted(scene, run))
    for field in ("positions", "angles", "velocities", "angular_velocities", "masses"):
        np.testing.assert_allclose(getattr(again, field), getattr(run, field), rtol=0, atol=1e-12)
    assert in_flight.restarted(scene, run).params == {"n": 2, "from_step": 7}


def test_a_restarted_scene_moves_on_as_the_run_does():
    """In free flight the restarted World and the run, stepped on alike, stay together (to
    round-off: the restart re-expresses each polygon about its centroid)."""
    scene = _off_centre_scene()
    run = sim.World(scene).step(7)
    again = sim.World(in_flight.restarted(scene, run)).step(30)
    run.step(30)
    np.testing.assert_allclose(again.positions, run.positions, rtol=0, atol=1e-9)
    np.testing.assert_allclose(again.angles, run.angles, rtol=0, atol=1e-9)


def test_phases_start_at_the_ends_and_the_middle_of_their_span():
    assert in_flight.phase_starts(100) == [0, 50, 100]
    assert in_flight.phase_starts(0) == [0]
