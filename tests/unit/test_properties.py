"""Random and adversarial values through every public constructor and ``step`` (issue 15).

One outcome is allowed for any input: success with a finite state, or a ValueError that names what
was wrong: the body (by its name) and the field, or the setting. A run that diverges later is a
SimulationError naming the body (the documented outcome of a run that cannot go on: a finite
velocity of 1e300 m/s passes every check and leaves the solver's range in one step).

Each field is drawn either from its valid range or from a pool of adversarial values (text,
bools, None, NaN, inf, huge and tiny numbers, wrong shapes, numpy scalars and arrays, objects).
The test knows which fields were adversarial and requires the message to name one of them.
"""

import math
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st

import sim
from study.peers import make_runner
from sim.world import SimulationError

SETTINGS = settings(
    max_examples=int(os.environ.get("PROPERTY_EXAMPLES", 500)),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)

#: values no public call should take without a clear ValueError, or should take and stay finite
ODD = st.one_of(
    st.sampled_from(
        [
            0,
            -1,
            1,
            2,
            0.5,
            -0.0,
            1e-320,
            5e-324,
            1e-9,
            1e9,
            1e12,
            1e155,
            1e300,
            1e308,
            -1e308,
            2**31,
            2**53,
            2**62,
            2**63,
            10**30,
            -(10**30),
            True,
            False,
            None,
            "",
            "1",
            "0.5",
            "12",
            "nan",
            "no",
            b"1",
            [],
            [1.0],
            [1.0, 2.0],
            [1.0, 2.0, 3.0],
            (0.0, "x"),
            [[1.0, 2.0]],
            {},
            {"x": 1},
            np.float64("nan"),
            np.float32(0.5),
            np.int64(3),
            np.bool_(True),
            np.array([1.0, 2.0]),
            np.array([np.inf, 0.0]),
            np.array(0.5),
            np.zeros((2, 2)),
            object(),
            math.pi,
            float("inf"),
            float("-inf"),
            float("nan"),
        ]
    ),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(),
    st.text(max_size=3),
    st.tuples(
        st.floats(allow_nan=True, allow_infinity=True),
        st.floats(allow_nan=True, allow_infinity=True),
    ),
)


@st.composite
def fields(draw, valid):
    """({field: value}, adversarial field names): each field valid or odd, at random."""
    out, odd = {}, set()
    for name, strategy in valid.items():
        if draw(st.integers(0, 5)) == 0:  # about one field in six
            out[name] = draw(ODD)
            odd.add(name)
        else:
            out[name] = draw(strategy)
    return out, odd


BODY = {
    "vertices": st.sampled_from(
        [
            [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)],
            [(-0.3, -0.2), (0.4, -0.2), (0.0, 0.5)],
            np.array([[-1.0, -0.1], [1.0, -0.1], [1.0, 0.1], [-1.0, 0.1]]),
        ]
    ),
    "position": st.tuples(st.floats(-5, 5), st.floats(1.0, 6.0)),
    "angle": st.floats(-7, 7),
    "velocity": st.tuples(st.floats(-30, 30), st.floats(-30, 30)),
    "angular_velocity": st.floats(-30, 30),
    "density": st.floats(0.01, 100),
    "friction": st.floats(0, 2),
    "restitution": st.floats(0, 1),
    "bullet": st.booleans(),
    "name": st.just("probe"),
}

SCENE = {
    "floor_y": st.one_of(st.none(), st.floats(-2, 0.5)),
    "gravity": st.tuples(st.floats(-5, 5), st.floats(-20, 0)),
    "floor_friction": st.floats(0, 2),
    "floor_restitution": st.floats(0, 1),
    "name": st.text(max_size=8),
    "params": st.just({"seed": 1}),
}

WORLD = {
    "dt": st.floats(1e-3, 0.05),
    "substeps": st.integers(1, 8),
    "iterations": st.integers(1, 4),
    "relax_iterations": st.integers(0, 2),
    "impact_iterations": st.integers(0, 8),
    "slop": st.floats(0, 0.01),
    "speculative_distance": st.floats(1e-4, 0.05),
    "contact_hertz": st.one_of(st.none(), st.floats(1, 120)),
    "damping_ratio": st.floats(0, 20),
    "push_speed": st.floats(0.1, 5),
    "restitution_threshold": st.floats(0, 2),
    "warm_starting": st.booleans(),
    "continuous": st.booleans(),
    "overlap_tolerance": st.floats(0, 0.05),
    "initial_iterations": st.integers(0, 50),
    "fast_paths": st.sampled_from([True, False, ("friction",), ("quiet",), ()]),
}

#: words a polygon's messages use for its vertices
VERTEX_WORDS = ("vert", "polygon", "clockwise")


def names_a_field(message, odd):
    return any(
        f in message or (f == "vertices" and any(w in message for w in VERTEX_WORDS)) for f in odd
    )


def assert_runs_finite(world, steps):
    """Step; succeed with every observable finite, or raise SimulationError naming a body."""
    try:
        world.step(steps)
    except SimulationError as exc:
        assert "diverged" in str(exc) or "flew" in str(exc) or "range" in str(exc), str(exc)
        assert "probe" in str(exc) or "body 0" in str(exc), str(exc)
        return "diverged"
    for a in (world.positions, world.angles, world.velocities, world.angular_velocities):
        assert np.isfinite(a).all(), a
    assert math.isfinite(world.kinetic_energy()) and math.isfinite(world.potential_energy())
    return "finite"


def build_and_run(body_fields, scene_fields=None, world_fields=None, steps=10):
    """Body -> Scene -> World -> step, each stage's ValueError returned (not raised)."""
    try:
        body = sim.Body(**body_fields)
    except ValueError as exc:
        event("refused: body")
        return "body", exc
    try:
        scene = sim.Scene(bodies=[body], **(scene_fields or {}))
    except ValueError as exc:
        event("refused: scene")
        return "scene", exc
    try:
        world = sim.World(scene, **(world_fields or {}))
    except ValueError as exc:
        event("refused: world")
        return "world", exc
    event(f"ran: {assert_runs_finite(world, steps)}")
    return "ran", None


SQUARE = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]


def body_example(**odd):
    """One body with the ``odd`` fields, the others valid (for the cases found by exploring)."""
    valid = {
        "vertices": SQUARE,
        "position": (0.0, 1.0),
        "angle": 0.0,
        "velocity": (0.0, 0.0),
        "angular_velocity": 0.0,
        "density": 1.0,
        "friction": 0.5,
        "restitution": 0.0,
        "bullet": False,
        "name": "probe",
    }
    return ({**valid, **odd}, set(odd))


@SETTINGS
@given(fields(BODY))
@example(body_example(density=1e308))  # finite, but kinetic_energy() was inf
@example(body_example(angular_velocity=1e300))
@example(body_example(name=["a"]))
def test_any_body_builds_and_runs_finite_or_is_refused_by_name_and_field(drawn):
    body_fields, odd = drawn
    name = body_fields["name"]
    shown = name if isinstance(name, str) and name else "body"  # what messages call it
    stage, exc = build_and_run(body_fields)
    if stage == "body":
        assert str(exc).startswith(f"{shown}: "), str(exc)
        assert names_a_field(str(exc), odd), (str(exc), odd)
    elif stage in ("scene", "world"):
        # the body passed its own checks, and the World refuses it as a whole (too big, too
        # dense, below the floor): by name ("body 0" once in a scene, if it has none)
        assert (shown if shown != "body" else "body 0") in str(exc), str(exc)


@SETTINGS
@given(fields(SCENE))
@example(({"gravity": (0.0, 7.19e306)}, {"gravity"}))  # its message overflowed
def test_any_scene_builds_and_runs_finite_or_is_refused_by_field(drawn):
    scene_fields, odd = drawn
    body = {"vertices": SQUARE, "position": (0.0, 3.0), "name": "probe"}
    stage, exc = build_and_run(body, scene_fields)
    assert stage != "body"
    if stage == "scene":
        assert str(exc).startswith("scene: "), str(exc)
        assert names_a_field(str(exc), odd), (str(exc), odd)
    elif stage == "world":
        assert "probe" in str(exc), str(exc)  # e.g. the body starts below a raised floor


@SETTINGS
@given(fields(WORLD), st.sampled_from(sim.POLICY_NAMES))
def test_any_world_settings_run_finite_or_are_refused_by_name(drawn, freeze):
    world_fields, odd = drawn
    if world_fields["warm_starting"] is False and world_fields["initial_iterations"] != 0:
        odd = odd | {"initial_iterations"}  # an initial solve needs warm starting: refused
    body = {"vertices": SQUARE, "position": (0.0, 0.52), "velocity": (1.0, -1.0), "name": "probe"}
    stage, exc = build_and_run(body, None, {**world_fields, "freeze": freeze}, steps=5)
    assert stage not in ("body", "scene")
    if stage == "world":
        assert names_a_field(str(exc), odd) or "probe" in str(exc), (str(exc), odd)


@SETTINGS
@given(st.one_of(ODD, st.integers(0, 40)))
def test_step_takes_a_count_or_refuses_it_by_name(n):
    world = sim.World(sim.scenes.single_box())
    before = world.step_count
    counted = (
        isinstance(n, (int, np.integer)) and not isinstance(n, (bool, np.bool_)) and 0 <= n <= 40
    )
    if (
        not counted
        and isinstance(n, (int, np.integer))
        and not isinstance(n, (bool, np.bool_))
        and n > 40
    ):
        return  # a valid count, too long to run here
    try:
        world.step(n)
    except ValueError as exc:
        assert not counted, (n, str(exc))
        assert str(exc).startswith("n must be"), str(exc)
        assert world.step_count == before  # nothing was run
        return
    assert counted, n
    assert world.step_count == before + n
    assert np.isfinite(world.positions).all()


SHAPES = {"width": st.floats(0.01, 5), "height": st.floats(0.01, 5)}
REGULAR = {"n": st.integers(3, 12), "radius": st.floats(0.01, 5)}


@SETTINGS
@given(fields(SHAPES), fields(REGULAR))
def test_shape_builders_build_or_refuse_by_name_and_argument(box, regular):
    for build, (args, odd), words in (
        (sim.Body.box, box, {"width": ("width",), "height": ("height",)}),
        (sim.Body.regular, regular, {"n": ("vertex count",), "radius": ("radius",)}),
    ):
        try:
            body = build(*args.values(), name="probe")
        except ValueError as exc:
            assert str(exc).startswith("probe: "), str(exc)
            assert odd, str(exc)
            assert any(w in str(exc) for f in odd for w in (*words[f], "vert", "polygon")), (
                str(exc),
                odd,
            )
        else:
            assert math.isfinite(body.mass) and body.mass > 0


ARRAYS = {
    "position": st.sampled_from([np.array([[0.0, 1.0], [3.0, 1.0]]), [(0.0, 1.0), (3.0, 1.0)]]),
    "angle": st.sampled_from([0.0, np.array([0.1, -0.1])]),
    "velocity": st.sampled_from([(0.0, 0.0), np.array([[1.0, 0.0], [0.0, 1.0]])]),
    "angular_velocity": st.floats(-5, 5),
    "density": st.sampled_from([1.0, np.array([1.0, 2.0])]),
    "friction": st.floats(0, 1),
    "restitution": st.floats(0, 1),
    "bullet": st.sampled_from([False, [True, False]]),
    "names": st.sampled_from([None, ["probe", "probe 2"]]),
}


@SETTINGS
@given(fields(ARRAYS))
def test_array_scenes_build_and_run_finite_or_are_refused_by_argument(drawn):
    arrays, odd = drawn
    try:
        scene = sim.Scene.from_arrays(SQUARE, **arrays)
    except ValueError as exc:
        # a bad body is refused as a Body would be ("body 1: ..."), a bad argument by its name
        assert odd, str(exc)
        assert names_a_field(str(exc), odd) or "body" in str(exc) or "probe" in str(exc), (
            str(exc),
            odd,
        )
        return
    try:
        world = sim.World(scene)
    except ValueError as exc:  # a body the World refuses whole, by name
        assert "body" in str(exc) or "probe" in str(exc), str(exc)
        return
    try:
        world.step(5)
    except SimulationError as exc:
        assert "body" in str(exc) or "probe" in str(exc), str(exc)
        return
    assert np.isfinite(world.positions).all() and np.isfinite(world.velocities).all()


RUNNER = {"dt": st.floats(1e-3, 0.05), "iterations": st.integers(1, 20)}


@pytest.mark.parametrize("system", ["sim-off", "pymunk", "pybullet", "box2d"])
@settings(max_examples=40, deadline=None)
@given(drawn=fields(RUNNER))
def test_any_runner_settings_run_finite_or_are_refused_by_name(system, drawn):
    settings_, odd = drawn
    try:
        runner = make_runner(system, sim.scenes.single_box(), **settings_)
    except ValueError as exc:
        assert odd and names_a_field(str(exc), odd), (str(exc), odd)
        return
    with runner:
        runner.step(3)
        assert np.isfinite(runner.positions).all() and np.isfinite(runner.velocities).all()
