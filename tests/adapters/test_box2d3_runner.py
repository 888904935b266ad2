"""study.peers.Box2d3Runner (Box2D v3, the benchmarks' timing peer) against known answers and
sim's conventions.

Box2D v3 computes in float32 and steps like sim's soft step (4 substeps of semi-implicit Euler),
so free fall and a friction slide have exact discrete answers that both engines meet; the
tolerances are float32 round-off, with the measured figure.
"""

import json
import math

import numpy as np
import pytest

import sim
from study import systems
from study.common import build
from study.metadata import jsonable
from study.peers import Box2d3Runner, make_runner, solver_summary
from study.peers.box2d3_runner import MAX_LINEAR_SPEED, MAX_POLYGON_VERTICES
from study.timing import timed

DT = 1 / 60
G = 9.81
H = DT / 4  # s, a substep


def _free(bodies, **kwargs):
    return sim.Scene(bodies, floor_y=None, **kwargs)


def test_free_fall_is_semi_implicit_euler_per_substep_as_sims():
    """After m substeps of h: y = y0 - g h^2 m (m+1) / 2, x = x0 + v0 m h. Measured 1e-6 m off
    after 60 steps from 10 m (float32); sim's World with its 4 substeps lands on the same answer."""
    scene = _free([sim.Body.box(1.0, 1.0, position=(0.5, 10.0), velocity=(1.5, 0.0))])
    runner = Box2d3Runner(scene, dt=DT)
    world = sim.World(scene, dt=DT)
    for n in (1, 2, 60):
        runner.step(n - runner.step_count)
        world.step(n - world.step_count)
        m = 4 * n
        assert runner.positions[0, 1] == pytest.approx(10.0 - G * H * H * m * (m + 1) / 2, rel=1e-6)
        assert runner.positions[0, 0] == pytest.approx(0.5 + 1.5 * m * H, rel=1e-6)
        assert runner.velocities[0, 1] == pytest.approx(-G * m * H, rel=2e-6)
        np.testing.assert_allclose(runner.positions, world.positions, rtol=0, atol=1e-5)
    assert runner.time == pytest.approx(1.0)
    assert runner.angles[0] == 0.0 and runner.angular_velocities[0] == 0.0


def test_bodies_get_sims_mass_inertia_and_centre_of_mass():
    """An off-centre quadrilateral of density 2: Box2D computes sim's mass and moment about the
    centre of mass, and its origin is that centre (float32: 5e-8 relative)."""
    body = sim.Body(
        vertices=[(0, 0), (2, 0), (2, 1), (0, 1.5)], position=(1, 2), angle=0.3, density=2.0
    )
    runner = Box2d3Runner(_free([body]))
    b2body = runner._body_list[0]
    assert b2body.mass == pytest.approx(body.mass, rel=1e-6)
    assert b2body.rotational_inertia() == pytest.approx(body.inertia, rel=1e-6)
    centre = b2body.local_center_of_mass()
    assert abs(centre[0]) < 1e-7 and abs(centre[1]) < 1e-7
    world = sim.World(_free([body]))
    np.testing.assert_allclose(runner.positions, world.positions, rtol=0, atol=1e-6)
    assert runner.angles[0] == pytest.approx(0.3, rel=1e-6)


def test_friction_slide_distance_is_the_discrete_answer():
    """Friction takes mu g h off the speed each substep until it stops, and the position moves
    with the new speed: h * sum_j (v0 - j mu g h) = 1.14058 m (v0 3 m/s, mu 0.4), 0.5 % short of
    v0^2/(2 mu g). Measured 1.14055 (rel 3e-5); sim 1.14039."""
    speed, mu = 3.0, 0.4
    runner = Box2d3Runner(sim.scenes.sliding_box(speed=speed, friction=mu), dt=DT)
    x0 = runner.positions[0, 0]
    runner.step(120)
    v = speed - mu * G * H * np.arange(1, int(speed / (mu * G * H)) + 1)
    assert runner.positions[0, 0] - x0 == pytest.approx(H * v.sum(), rel=1e-4)
    assert runner.positions[0, 0] - x0 == pytest.approx(speed**2 / (2 * mu * G), rel=0.01)
    assert abs(runner.velocities[0, 0]) < 1e-6 and abs(runner.angles[0]) < 1e-6


def test_a_box_on_the_floor_stays_on_floor_y():
    """The floor is a static box whose top face is floor_y: a unit box placed on it stays
    (measured: 0.09 mm into the soft contact after 5 s, no slide), on any floor height."""
    for floor_y in (0.0, -3.0):
        scene = sim.Scene([sim.Body.box(1.0, 1.0, position=(0.3, floor_y + 0.5))], floor_y=floor_y)
        runner = Box2d3Runner(scene)
        start = runner.positions.copy()
        runner.step(300)
        assert np.abs(runner.positions - start).max() < 2e-4
        assert np.abs(runner.velocities).max() < 1e-5
        assert not runner.asleep.any()  # sleeping is off
        assert runner.settings["floor"]["top_y"] == floor_y


def test_no_body_of_a_pile_is_pushed_through_the_floor():
    """drop(200) seed 4: on a floor chain (one-sided, no thickness) Box2D v3 let the pile push a
    0.1 m triangle (body 8) through it at step 90, and it fell 39 m in 4 s; on the floor box every
    body stays above the floor (measured: the lowest centre 1.9 cm up at step 240)."""
    runner = Box2d3Runner(sim.scenes.drop(200, seed=4))
    runner.step(240)
    assert runner.positions[:, 1].min() > 0.0
    assert runner.settings["floor"]["kind"] == "static box"


def test_momentum_is_conserved_in_a_free_collision():
    """Two bodies of different masses and spin collide with no gravity and no floor: the total
    linear momentum keeps its value to float32 round-off."""
    bodies = [
        sim.Body.box(1.0, 1.0, position=(0.0, 0.0), velocity=(2.0, 0.0)),
        sim.Body.box(
            1.0, 0.5, position=(2.0, 0.2), velocity=(-1.0, 0.0), density=3.0, angular_velocity=0.5
        ),
    ]
    m = np.array([b.mass for b in bodies])
    runner = Box2d3Runner(_free(bodies, gravity=(0.0, 0.0)))
    v0 = runner.velocities
    p0 = (m[:, None] * v0).sum(axis=0)
    runner.step(120)
    p1 = (m[:, None] * runner.velocities).sum(axis=0)
    assert np.abs(runner.velocities - v0).max() > 0.5  # they did collide
    np.testing.assert_allclose(p1, p0, rtol=0, atol=1e-5 * np.hypot(*p0))


def test_what_box2d_cannot_hold_is_refused_with_the_reason():
    nine = [(math.cos(a), math.sin(a)) for a in np.linspace(0, 2 * math.pi, 10)[:-1]]
    with pytest.raises(
        ValueError, match=rf"body 0 \(nonagon\) has 9 vertices; .* at most {MAX_POLYGON_VERTICES}"
    ):
        Box2d3Runner(_free([sim.Body(vertices=nine, name="nonagon")]))
    welded = [(0, 0), (1, 0), (1.001, 0.0005), (1, 1), (0, 1)]  # two vertices 1 mm apart
    with pytest.raises(ValueError, match=r"body 0: Box2D's convex hull of its 5 vertices has 4"):
        Box2d3Runner(_free([sim.Body(vertices=welded)]))
    fast = sim.Body.box(1.0, 1.0, velocity=(MAX_LINEAR_SPEED, 0.0))
    with pytest.raises(ValueError, match="clamps speeds at 400 m/s"):
        Box2d3Runner(_free([fast]))
    spin = sim.Body.box(1.0, 1.0, angular_velocity=200.0)  # pi/4 per substep is 188.5 rad/s
    with pytest.raises(ValueError, match="188.496 rad/s"):
        Box2d3Runner(_free([spin]))
    with pytest.raises(ValueError, match="Box2D v3 solves each substep once"):
        Box2d3Runner(sim.scenes.single_box(), iterations=2)
    with pytest.raises(ValueError, match="must be a sim.Scene"):
        Box2d3Runner("not a scene")
    with pytest.raises(ValueError):
        Box2d3Runner(sim.scenes.single_box(), dt=0.0)
    with pytest.raises(ValueError):
        Box2d3Runner(sim.scenes.single_box(), substeps=0)
    with pytest.raises(ValueError):
        Box2d3Runner(sim.scenes.single_box()).step(-1)


def test_a_body_reaching_box2ds_speed_limit_stops_the_run():
    """Box2D clamps speeds at 400 m/s silently; a body falling from 399 m/s reaches it in the
    first steps, and ``step`` raises rather than report a slowed body."""
    runner = Box2d3Runner(_free([sim.Body.box(1.0, 1.0, velocity=(0.0, -399.0))]))
    with pytest.raises(RuntimeError, match="Box2D v3's limit"):
        runner.step(10)


def test_benchmarks_time_the_engines_steps():
    """study.timing.timed returns the time inside Box2D's step calls (``engine_seconds``), not
    the runner's speed check after them."""
    runner = Box2d3Runner(sim.scenes.pyramid(5))
    before = runner.engine_seconds
    engine = timed(runner, 20)
    assert engine == pytest.approx(runner.engine_seconds - before) and engine > 0


def test_it_is_a_benchmark_system_outside_the_studys_comparisons():
    """The registry knows box2d3 (engine, style) but no experiment of outcomes loops over it;
    make_runner and the study's build make it; its settings are JSON and say what was run."""
    assert "box2d3" not in systems.SYSTEMS and "box2d3" in systems.BENCH_SYSTEMS
    assert systems.engine_of("box2d3") == "box2d3" and "box2d3" not in systems.PEERS
    assert systems.style("box2d3")["marker"] == "*"
    with make_runner("box2d3", sim.scenes.stack(2)) as runner:
        runner.step(2)
        assert runner.name == "box2d3" and runner.step_count == 2
    assert runner.world is None
    runner.close()  # idempotent
    runner = build("box2d3", sim.scenes.drop(20, seed=0))
    settings = json.loads(json.dumps(jsonable(runner.settings)))
    for key in ("version", "precision", "simd", "substeps", "contact_hertz", "floor"):
        assert key in settings, key
    assert settings["engine"] == "box2d3" and settings["sleeping"] is False
    assert solver_summary(settings) == {
        "substeps": 4,
        "iterations": 1,
        "relax_iterations": 1,
        "contact_sweeps_per_step": 8,
    }
    runner.step(30)
    shapes = [runner.positions, runner.velocities, runner.angles, runner.angular_velocities]
    assert [a.shape for a in shapes] == [(20, 2), (20, 2), (20,), (20,)]
    assert all(np.isfinite(a).all() for a in shapes)
