"""Bad input raises ValueError naming the body and the problem; a run that goes non-finite stops
with an error naming the step and the body."""

import math

import numpy as np
import pytest

import sim

BOX = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]


def scene_with(body, **kwargs):
    """A resting box (body 0) plus ``body`` (body 1) far from it."""
    return sim.Scene(bodies=[sim.Body.box(1, 1, position=(-10.0, 0.5)), body], **kwargs)


@pytest.mark.parametrize(
    "vertices,problem",
    [
        (BOX[::-1], "clockwise"),
        ([(0, 0), (2, 0), (1, 0.2), (2, 2), (0, 2)], "non-convex"),
        ([(0, 0), (1, 0), (1, 0), (0, 1)], "degenerate"),
        ([(0, 0), (1, 0), (2, 0)], "degenerate"),
        ([(0, 0), (1, 0)], "at least 3"),
        ([(0, 0), (1, math.nan), (0, 1)], "NaN"),
        ([(0, 0), (1, math.inf), (0, 1)], "NaN or inf"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], "shape"),
        ("not a polygon", "vertices"),
        # float() takes these, so they were accepted (the README refuses text given as a number)
        ([("0", "0"), ("1", "0"), ("0", "1")], "vertices must be numbers"),
        (np.array([(0, 0), (1, 0), (0, 1)], complex), "vertices must be numbers"),
        (np.array([(0, 0), (1, 0), (0, 1)], bool), "vertices must be numbers"),
    ],
)
def test_bad_polygon(vertices, problem):
    with pytest.raises(ValueError, match=problem) as err:
        sim.Body(vertices=vertices, name="crate 7")
    assert "crate 7" in str(err.value)


@pytest.mark.parametrize(
    "field,value,problem",
    [
        ("density", 0.0, "density must be > 0"),
        ("density", -1.0, "density must be > 0"),
        ("density", math.nan, "density is not finite"),
        ("friction", -0.1, "friction must be >= 0"),
        ("restitution", 1.5, "restitution must be in"),
        ("position", (0.0, math.nan), "position is not finite"),
        ("velocity", (math.inf, 0.0), "velocity is not finite"),
        ("angle", math.nan, "angle is not finite"),
        ("angular_velocity", math.inf, "angular_velocity is not finite"),
        ("position", (1.0,), "position must be a pair"),
        # numbers inside a pair, and pairs, that float() or unpacking took
        ("position", ("1", "2"), "position must be a pair of numbers"),
        ("velocity", (b"1", b"2"), "velocity must be a pair of numbers"),
        ("position", {1: 2, 3: 4}, "position must be a pair of numbers"),
        ("position", {1, 2}, "position must be a pair of numbers"),
        ("position", (True, 0.0), "position must be a pair of numbers"),
        ("density", True, "density must be a number"),
        ("angle", True, "angle must be a number"),
        ("angle", 1 + 0j, "angle must be a number"),
    ],
)
def test_bad_body_field(field, value, problem):
    with pytest.raises(ValueError, match=problem) as err:
        sim.Body(vertices=BOX, name="crate 7", **{field: value})
    assert "crate 7" in str(err.value)


def test_body_changed_after_creation_is_caught_by_the_world():
    body = sim.Body.box(1, 1, position=(0.0, 0.5))
    scene = scene_with(body)
    body.density = -2.0  # dataclasses are mutable; the World re-validates
    with pytest.raises(ValueError, match="body 1: density"):
        sim.World(scene)


def test_unnamed_bodies_are_named_by_index():
    bad = sim.Body.box(1, 1, position=(0.0, 0.5))
    bad.vertices = BOX[::-1]
    with pytest.raises(ValueError, match="body 1: vertices are clockwise"):
        sim.World(scene_with(bad))


@pytest.mark.parametrize(
    "kwargs,problem",
    [
        ({"dt": 0.0}, "dt must be > 0"),
        ({"dt": -1 / 60}, "dt must be > 0"),
        ({"dt": math.nan}, "dt must be > 0"),
        ({"dt": math.inf}, "dt must be > 0"),
        ({"iterations": 0}, "iterations must be an integer >= 1"),
        ({"iterations": 2.5}, "iterations must be an integer"),
        ({"position_iterations": 0}, "position_iterations"),
        ({"slop": -0.001}, "slop"),
        ({"baumgarte": 1.5}, "baumgarte"),
        ({"freeze": "nap"}, "unknown freeze policy 'nap'"),
        ({"freeze": "off", "impulse_threshold": 1.0}, "World got impulse_threshold: not a World"),
        # a misspelt setting was reported as the policy's ("freeze='off' does not take iteratons")
        (
            {"iteratons": 3},
            "not a World setting .* nor a parameter of freeze='off'.* iterations\\?",
        ),
    ],
)
def test_bad_world_settings(kwargs, problem):
    with pytest.raises(ValueError, match=problem):
        sim.World(sim.scenes.single_box(), **kwargs)


@pytest.mark.parametrize(
    "kwargs,problem",
    [
        ({"dt": 1e-310}, r"dt=1e-310 s is too small for float64"),
        ({"damping_ratio": 1e308}, r"damping_ratio=1e\+308 is too large for float64"),
        # undamped and nearly infinitely soft: h omega underflowed to 0, the bias rate to inf
        (
            {"damping_ratio": 0.0, "contact_hertz": 1e-323},
            r"contact_hertz=1e-323 is too small for float64 with damping_ratio=0.0",
        ),
    ],
)
def test_settings_whose_soft_contacts_overflow_are_refused_by_name(kwargs, problem):
    """Each was accepted (a positive float), and the first step's soft coefficients were NaN: the
    World then blamed body 0, at rest, as diverged, and for the subnormal dt advised a smaller
    one. The neighbours that float64 holds still build and step."""
    with pytest.raises(ValueError, match=problem):
        sim.World(sim.scenes.single_box(), **kwargs)
    for fine in (
        {"dt": 1e-300},
        {"damping_ratio": 1e300},
        {"contact_hertz": 1e308},  # capped at the substep rate's share, as used
        {"damping_ratio": 0.0, "contact_hertz": 1e-300},
    ):
        world = sim.World(sim.scenes.single_box(), **fine)
        world.step(2)
        assert np.isfinite(world.positions).all()


@pytest.mark.parametrize("switch", [np.True_, np.False_])
def test_fast_paths_takes_numpys_switches_as_every_other_switch_does(switch):
    world = sim.World(sim.scenes.single_box(), fast_paths=switch)
    assert (
        world.fast_paths == (sim.World(sim.scenes.single_box(), fast_paths=bool(switch))).fast_paths
    )


def test_overlapping_bodies_are_refused_with_both_names():
    a = sim.Body.box(1, 1, position=(0.0, 0.5), name="left")
    b = sim.Body.box(1, 1, position=(0.8, 0.5), name="right")  # 0.2 m into `left`
    with pytest.raises(ValueError, match=r"left and right start overlapping by 0\.2"):
        sim.World(sim.Scene(bodies=[a, b]))


def test_small_overlap_within_tolerance_is_accepted():
    a = sim.Body.box(1, 1, position=(0.0, 0.5))
    b = sim.Body.box(1, 1, position=(0.995, 0.5))
    sim.World(sim.Scene(bodies=[a, b])).step(10)


def test_body_below_the_floor_is_refused():
    with pytest.raises(ValueError, match=r"sunk starts 0\.3 m below the floor"):
        sim.World(sim.Scene(bodies=[sim.Body.box(1, 1, position=(0.0, 0.2), name="sunk")]))


def test_body_inside_a_static_wall_is_refused():
    wall = sim.Body.box(1, 4, position=(0.0, 2.0), name="wall")
    with pytest.raises(ValueError, match="crate and wall start overlapping"):
        sim.World(
            sim.Scene(
                bodies=[sim.Body.box(1, 1, position=(0.5, 1.5), name="crate")], static_bodies=[wall]
            )
        )


@pytest.mark.parametrize(
    "kwargs,problem",
    [
        ({"bodies": []}, "at least one body"),
        ({"bodies": ["box"]}, "expected sim.Body"),
        ({"gravity": (0.0, math.nan)}, "gravity is not finite"),
        ({"floor_friction": -1.0}, "floor_friction"),
        ({"floor_restitution": 2.0}, "floor_restitution"),
        ({"floor_y": math.inf}, "floor_y is not finite"),
        ({"gravity": (True, False)}, "gravity must be a pair of numbers"),
        # a lone Body was reported as "needs at least one body"
        ({"bodies": sim.Body.box(1, 1, position=(0, 0.5))}, "a list of sim.Body, got Body \\(put"),
        ({"bodies": (b for b in [])}, "a list of sim.Body, got generator"),
    ],
)
def test_bad_scene(kwargs, problem):
    args = {"bodies": [sim.Body.box(1, 1, position=(0, 0.5))], **kwargs}
    with pytest.raises(ValueError, match=problem):
        sim.Scene(**args)


def test_moving_static_body_is_refused():
    wall = sim.Body.box(1, 1, position=(5, 0.5), velocity=(1.0, 0.0))
    with pytest.raises(ValueError, match="static body 0: static bodies cannot move"):
        sim.Scene(bodies=[sim.Body.box(1, 1, position=(0, 0.5))], static_bodies=[wall])


def test_bad_scene_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("floor_y = [\n")
    with pytest.raises(ValueError, match="not valid TOML"):
        sim.Scene.from_file(path)
    path.write_text("[[bodies]]\nposition = [0, 1]\n")
    with pytest.raises(ValueError, match="body 0: needs `vertices`"):
        sim.Scene.from_file(path)
    path.write_text("wind = 3\n[[bodies]]\nbox = [1, 1]\nposition = [0, 0.5]\n")
    with pytest.raises(ValueError, match="wind"):
        sim.Scene.from_file(path)


def test_non_finite_run_names_step_and_body():
    # the fastest body allowed, over a step so long that its position overflows to inf
    fast = sim.Body.box(1, 1, position=(0.0, 5.0), velocity=(1e12, 0.0), name="bullet")
    world = sim.World(
        sim.Scene(bodies=[sim.Body.box(1, 1, position=(-10, 0.5)), fast], gravity=(0, 0)), dt=1e297
    )
    with pytest.raises(sim.SimulationError, match=r"step 1: bullet diverged .*position \[inf"):
        world.step(5)
    assert world.step_count == 1  # stopped at the bad step, not run on


def test_body_flung_out_of_range_names_step_and_body():
    # finite, but far beyond any scene: the broadphase's cell indices would overflow first
    rocket = sim.Body.box(1, 1, position=(0.0, 0.5), velocity=(1e12, 0.0), name="rocket")
    world = sim.World(sim.Scene(bodies=[rocket], gravity=(0, 0)), dt=10.0)
    with pytest.raises(sim.SimulationError, match=r"step 1: rocket diverged"):
        world.step(3)


def test_step_count_must_be_a_non_negative_integer():
    world = sim.World(sim.scenes.single_box())
    with pytest.raises(ValueError, match="n must be an integer >= 0"):
        world.step(-1)
    with pytest.raises(ValueError):
        world.step(1.5)
    world.step(0)
    assert world.step_count == 0


@pytest.mark.parametrize(
    "freeze,kwargs,problem",
    [
        ("paper", {"impulse_threshold": -1.0}, "impulse_threshold must be finite and >= 0"),
        ("extended", {"rest_steps": 0}, "rest_steps must be an integer >= 1"),
        ("extended", {"rest_steps": 1.5}, "rest_steps must be an integer >= 1"),
        ("extended", {"rest_speed": math.nan}, "rest_speed must be finite"),
        ("sleep", {"sleep_time": "long"}, "sleep_time must be a number"),
        ("sleep", {"impulse_threshold": 1.0}, "nor a parameter of freeze='sleep' \\(sleep_speed"),
        ("extended", {"tip_margn": 0.1}, "did you mean tip_margin\\?"),
        # 1e155 and more overflowed the certificate's moments, and every body passed it
        ("extended", {"tip_margin": 1e300}, "tip_margin must be below 1.0"),
        ("extended", {"tip_margin": 1.0}, "tip_margin must be below 1.0"),
    ],
)
def test_bad_policy_parameters(freeze, kwargs, problem):
    with pytest.raises(ValueError, match=problem):
        sim.World(sim.scenes.single_box(), freeze=freeze, **kwargs)


def test_every_policy_builds_and_reports_its_parameters():
    for name in sim.POLICY_NAMES:
        world = sim.World(sim.scenes.single_box(), freeze=name)
        world.step(3)
        assert world.freeze == name
        assert set(world.policy_parameters) == set(world.policy.PARAMETERS)


def test_observables_are_copies():
    world = sim.World(sim.scenes.single_box())
    world.positions[0, 0] = 99.0
    world.velocities[0, 0] = 99.0
    assert world.positions[0, 0] == 0.0 and world.velocities[0, 0] == 0.0
    # masses and inertias are the World's own (the energies use them), extents and sizes
    # copies of the solver's: read-only
    for array in (world.masses, world.inertias, world.extents, world.sizes):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = -1.0
    assert world.kinetic_energy() == 0.0
    assert world.states.dtype == np.int8 and world.states[0] == sim.State.FREE


@pytest.mark.parametrize("i", [-1, 1, 5, True, 0.0, "0"])
def test_vertices_take_only_a_dynamic_body_index(i):
    # body 1 is the static one: World.vertices is of dynamic bodies (-1 gave an empty array, 1
    # the static body's polygon, 5 numpy's IndexError)
    world = sim.World(
        sim.Scene(
            bodies=[sim.Body.box(1, 1, position=(0.0, 0.5))],
            static_bodies=[sim.Body.box(1, 1, position=(3.0, 0.5))],
        )
    )
    assert world.vertices(np.int64(0)).shape == (4, 2)
    with pytest.raises(ValueError, match="body index"):
        world.vertices(i)


@pytest.mark.parametrize("static", [False, True])
def test_a_centre_of_mass_beyond_the_solvers_range_is_refused(static):
    # the position and the vertices are each within 1e12 m, their sum is not: the World was
    # built, and its first step stopped the resting box as "diverged"
    v = np.array(BOX) + [9e11, 0.0]
    far = sim.Body(vertices=v, position=(9e11, 0.5), name="far")
    near = sim.Body.box(1, 1, position=(0.0, 0.5))
    scene = sim.Scene(bodies=[near], static_bodies=[far]) if static else sim.Scene(bodies=[far])
    with pytest.raises(ValueError, match="far.*centre of mass .* beyond 1e\\+12 m"):
        sim.World(scene)


def test_array_scenes_take_no_text_as_a_number():
    tri = [(0, 0), (1, 0), (0, 1)]
    with pytest.raises(ValueError, match="position must be numbers"):
        sim.Scene.from_arrays(tri, [["1", "2"]])
    with pytest.raises(ValueError, match="density must be numbers"):
        sim.Scene.from_arrays(tri, [[1, 2]], density="2")


def test_vertices_edited_in_place_are_caught_by_the_world():
    """A body passes its full check once and is then only fingerprinted; an in-place edit of its
    vertex array must still be noticed (here: the polygon turned clockwise)."""
    body = sim.Body.box(1, 1, position=(0.0, 0.5))
    scene = scene_with(body)
    body.vertices[:] = body.vertices[::-1].copy()
    with pytest.raises(ValueError, match="clockwise"):
        sim.World(scene)


# ---- extreme but finite inputs, and counts that would make a step unstoppable --------------------
def test_vertices_beyond_the_solvers_range_are_refused():
    # squared, 1e155 overflows: the square passed the convexity test on NaN turn angles and
    # reached the World with mass inf and inertia NaN
    with pytest.raises(ValueError, match=r"huge: a vertex lies 1e\+155 m from the body's origin"):
        sim.Body(
            vertices=[[-1e155, -1e155], [1e155, -1e155], [1e155, 1e155], [-1e155, 1e155]],
            name="huge",
        )
    with pytest.raises(ValueError, match=r"body 0: a vertex lies 1e\+155 m"):  # the array path
        sim.Scene.from_arrays(
            np.array([[[-1e155, -1e155], [1e155, -1e155], [1e155, 1e155], [-1e155, 1e155]]]),
            np.zeros((1, 2)),
        )


@pytest.mark.parametrize(
    "make, why",
    [
        (
            lambda: sim.Body.box(1e12, 1e12, position=(0, 5e11), density=1e300, name="dense"),
            "mass inf",
        ),
        (lambda: sim.Body.box(1, 1, position=(0, 0.5), density=1e-320, name="airy"), "mass 1e-320"),
        # finite, but its kinetic energy overflowed: kinetic_energy() was inf
        (
            lambda: sim.Body.box(1, 1, position=(0, 0.5), density=1e308, name="dense"),
            "mass 1e\\+308",
        ),
        (
            lambda: sim.Body.box(1e-3, 1e-3, position=(0, 0.5), density=1e-100, name="airy"),
            "mass 1e-106",
        ),
    ],
)
def test_bodies_whose_mass_properties_overflow_are_refused_by_name(make, why):
    body = make()
    with pytest.raises(
        ValueError,
        match=rf"{body.name}: its mass properties are beyond what "
        rf"the solver can use \({why}",
    ):
        sim.World(sim.Scene(bodies=[body]))
    lo, hi = sim.validation.MASS_RANGE
    assert not lo <= body.mass <= hi or not lo <= body.inertia <= hi


@pytest.mark.parametrize("field, value", [("velocity", (-1.1e12, 0.0)), ("angular_velocity", 2e12)])
def test_bodies_faster_than_the_solver_can_follow_are_refused(field, value):
    with pytest.raises(ValueError, match=rf"fast: {field} .* is beyond 1e\+12"):
        sim.Body.box(1, 1, position=(0, 0.5), name="fast", **{field: value})
    with pytest.raises(ValueError, match=rf"body 1: {field} .* is beyond 1e\+12"):
        sim.Scene.from_arrays(
            sim.Body.box(1, 1).vertices,
            [(0, 0.5), (3, 0.5)],
            **{field: [0.0, value] if field == "angular_velocity" else [(0, 0), value]},
        )
    sim.Body.box(
        1, 1, position=(0, 0.5), **{field: 1e12 if field == "angular_velocity" else (1e12, -1e12)}
    )


@pytest.mark.parametrize(
    "field, value",
    [
        ("iterations", 10**9),
        ("relax_iterations", 1001),
        ("impact_iterations", 1001),
        ("substeps", 10**6),
        ("initial_iterations", 10**7),
    ],
)
def test_solver_counts_beyond_what_a_step_can_afford_are_refused(field, value):
    with pytest.raises(ValueError, match=rf"{field} must be at most .*cannot be interrupted"):
        sim.World(sim.scenes.single_box(), **{field: value})


def test_an_initial_solve_without_warm_starting_is_refused_not_ignored():
    """Its impulses reach step 1 only as the warm start: asked for with warm_starting=False, it
    was silently skipped. Left out, the World chooses: 5000 sweeps with warm starting, none
    without."""
    scene = sim.scenes.stack(3)
    with pytest.raises(ValueError, match=r"initial_iterations=10 needs warm_starting=True"):
        sim.World(scene, warm_starting=False, initial_iterations=10)
    assert sim.World(scene, warm_starting=False).initial_iterations == 0
    assert sim.World(scene, warm_starting=False, initial_iterations=0).initial_iterations == 0
    assert sim.World(scene).initial_iterations == 5000
    assert sim.World(scene, initial_iterations=7).initial_iterations == 7


# ---- numpy values in bodies and scenes ---------------------------------------------------------
def test_a_body_restarted_from_a_worlds_arrays_builds_a_world():
    world = sim.World(sim.scenes.stack(3)).step(30)
    scene = sim.scenes.stack(3)
    for i, body in enumerate(scene.bodies):  # the natural restart: numpy rows and floats
        body.position, body.velocity = world.positions[i], world.velocities[i]
        body.angle, body.angular_velocity = world.angles[i], world.angular_velocities[i]
    again = sim.World(scene, initial_iterations=0)
    assert np.allclose(again.positions, world.positions, atol=1e-12)


def test_bodies_and_scenes_compare_whole():
    a, b, c = sim.Body.box(1, 1), sim.Body.box(1, 1), sim.Body.box(1, 2)
    assert a == b and a != c
    assert sim.Scene(bodies=[a]) == sim.Scene(bodies=[b])
    assert sim.Scene(bodies=[a]) != sim.Scene(bodies=[c])
    b.position = np.array([0.0, 0.0])
    assert a == b  # an array equal to the tuple
    b.name = "other"
    assert a != b


@pytest.mark.parametrize("n", [0, 1, 2, -3, 1025, 10**30])
def test_a_regular_polygon_needs_three_vertices_and_no_more_than_the_solver_takes(n):
    with pytest.raises(ValueError, match="vertex count must be an integer from 3 to 1024"):
        sim.Body.regular(n, 1.0)


# ---- the right exception type, and no text taken as a number -------------------------------------
@pytest.mark.parametrize(
    "build, match",
    [
        (
            lambda: sim.Scene(bodies=[sim.Body.box(1, 1, position=(0, 0.5))], static_bodies=None),
            "static_bodies must be a list",
        ),
        (
            lambda: sim.World(sim.scenes.single_box(), freeze="extended", rest_steps=10**30),
            r"rest_steps must be an integer >= 1 \(and < 2\*\*62\)",
        ),
        (
            lambda: sim.World(sim.scenes.single_box(), fast_paths=1),
            "fast_paths must be True, False",
        ),
        (lambda: sim.Body.box(1, 1, position="12"), "position must be a pair of numbers, got '12'"),
        (lambda: sim.Body.box(1, 1, density="2"), "density must be a number, got '2'"),
        (
            lambda: sim.World(sim.scenes.single_box(), warm_starting="no"),
            "warm_starting must be True or False, got 'no'",
        ),
        (
            lambda: sim.World(sim.scenes.single_box(), continuous="no"),
            "continuous must be True or False",
        ),
        (
            lambda: sim.World(sim.scenes.single_box(), freeze="paper", impulse_threshold="0.1"),
            "impulse_threshold must be a number, got '0.1'",
        ),
        # the scene builders name themselves and the argument (were Python's TypeError deep
        # inside, a math domain error, numpy's SeedSequence error, or "body: degenerate polygon")
        (lambda: sim.scenes.pyramid(2.5), "pyramid: base must be an integer >= 1, got 2.5"),
        (lambda: sim.scenes.stack(2.5), "stack: height must be an integer"),
        (lambda: sim.scenes.single_box("1"), "single_box: size must be a number, got '1'"),
        (lambda: sim.scenes.drop(-1), "drop: n must be an integer >= 1, got -1"),
        (lambda: sim.scenes.drop(3, seed="a"), "drop: seed must be an integer >= 0"),
        (lambda: sim.scenes.drop(3, radius=0), "drop: radius must be > 0"),
        (lambda: sim.scenes.arch(1), "arch: n_blocks must be an integer >= 2, got 1"),
        (lambda: sim.scenes.arch(thickness=4.0), "arch: thickness must be below twice the radius"),
        (lambda: sim.scenes.rest_row(3, gap=-1.0), "rest_row: gap must be >= 0"),
        # from_arrays' params: "TypeError: 'int' object is not iterable"
        (
            lambda: sim.Scene.from_arrays([(0, 0), (1, 0), (0, 1)], [[0, 0]], params=5),
            "params must be a dict, got 5",
        ),
        # gravity far beyond the solver: an 80-digit substep count was suggested
        (
            lambda: sim.World(sim.scenes.single_box(), dt=1e9),
            "No substep count up to 1000 can .* use dt <= ",
        ),
    ],
)
def test_bad_values_raise_a_value_error_that_names_them(build, match):
    with pytest.raises(ValueError, match=match):
        build()


@pytest.mark.parametrize(
    "contents, match",
    [
        (bytes(range(256)), r"bad\.toml: not valid TOML \(not UTF-8 text"),
        (("a = " + "[" * 3000 + "]" * 3000 + "\n").encode(), r"bad\.toml: not valid TOML .*nested"),
        (
            b"[[bodies]]\nbox = [1, 1]\nposition = [0, 1]\n\n[[bodies]]\nbox = [1, 1]\n"
            b'position = [0, "x"]\n',
            r"bad\.toml: body 1: position must be a pair of numbers",
        ),
        (
            b'[[bodies]]\nbox = [1, 1]\nposition = [0, 1]\n[[static_bodies]]\nname = "wall"\n'
            b"box = [1, 1]\nposition = [0, 1, 3]\n",
            r"bad\.toml: static body 0 \(wall\): position must be a pair",
        ),
        (b'[[bodies]]\nbox = [1, "x"]\n', r"bad\.toml: body 0: height must be a number, got 'x'"),
        (b"[[bodies]]\nbox = 3\n", r"bad\.toml: body 0: box must be \[width, height\], got 3"),
        (b"[[bodies]]\nbox = [1, 1]\ncolour = 3\n", r"bad\.toml: body 0: .*'colour'"),
        (b"bodies = 3\n", r"bad\.toml: body entries must be a list of tables"),
        (b"bodies = [3]\n", r"bad\.toml: body 0: expected a table of body fields"),
        (b"name = 3\n[[bodies]]\nbox = [1, 1]\n", r"bad\.toml: scene: name must be a string"),
    ],
)
def test_every_scene_file_error_is_a_value_error_naming_the_file_and_entry(
    tmp_path, contents, match
):
    path = tmp_path / "bad.toml"
    path.write_bytes(contents)
    with pytest.raises(ValueError, match=match):
        sim.Scene.from_file(path)


@pytest.mark.parametrize("system", ["sim-off", "pymunk", "pybullet", "box2d"])
@pytest.mark.parametrize(
    "setting, value",
    [("dt", "0.01"), ("iterations", 3.0), ("iterations", "3"), ("dt", True), ("iterations", 2**31)],
)  # beyond a C int
def test_runners_take_no_text_as_a_number_nor_counts_beyond_their_range(system, setting, value):
    from study.peers import make_runner

    with pytest.raises(ValueError, match=rf"{setting} must be"):
        make_runner(system, sim.scenes.single_box(), **{setting: value})


def test_names_must_be_strings():
    with pytest.raises(ValueError, match=r"body: name must be a string, got \['a'\]"):
        sim.Body.box(1, 1, name=["a"])
    assert sim.Body.box(1, 1, name=None).name == ""
    body = sim.Body.box(1, 1, position=(0, 0.5))
    body.name = 3
    with pytest.raises(ValueError, match="body 0: name must be a string, got 3"):
        sim.Scene(bodies=[body])
    with pytest.raises(ValueError, match="scene: name must be a string"):
        sim.Scene(bodies=[sim.Body.box(1, 1, position=(0, 0.5))], name=3)


# ---- a World is not changed by edits to its scene after it was built -----------------------------
def test_edits_to_the_scene_after_the_world_is_built_reach_neither_the_run_nor_its_reports():
    scene = sim.Scene(bodies=[sim.Body.box(1, 1, position=(0, 5), name="a")])
    world = sim.World(scene)
    twin = sim.World(sim.Scene(bodies=[sim.Body.box(1, 1, position=(0, 5), name="a")]))
    pe = world.potential_energy()
    scene.gravity = (0.0, -100.0)  # each of these was half-seen before
    scene.bodies[0].name = "renamed"
    scene.bodies.append(sim.Body.box(1, 1, position=(3, 5)))
    scene.floor_y = 2.0
    assert world.potential_energy() == pe
    assert world.scene.gravity == (0.0, -9.81) and world.scene.n_bodies == 1
    assert world.scene.floor_y == 0.0 and world.scene.bodies[0].name == "a"
    world.step(90), twin.step(90)
    assert np.array_equal(world.positions, twin.positions)  # the run as built
    # and editing the World's own copy changes nothing either
    world.scene.gravity = (0.0, -100.0)
    assert world.potential_energy() == twin.potential_energy()


def test_a_scene_snapshot_is_equal_and_independent():
    scene = sim.scenes.drop(5, seed=2)
    copy = scene.snapshot()
    assert copy.body_arrays is not None  # gathered into arrays, not body by body
    assert copy == scene
    scene.bodies[0].position = (9.0, 9.0)
    scene.params["seed"] = 99
    assert copy != scene and copy.params["seed"] == 2


def test_a_world_cannot_be_copied_or_pickled_and_says_what_to_do():
    # copy.copy shared the World's arrays (stepping the copy moved the original); pickle and
    # deepcopy failed with "cannot pickle 'module' object"
    import copy
    import pickle

    world = sim.World(sim.scenes.single_box())
    for attempt in (copy.copy, copy.deepcopy, pickle.dumps):
        with pytest.raises(TypeError, match="cannot be copied or pickled: build another"):
            attempt(world)


def test_a_scene_file_into_a_missing_folder_names_the_folder(tmp_path):
    # the error named a hidden temporary file (".y.toml.xxxx.tmp")
    path = tmp_path / "no such folder" / "y.toml"
    with pytest.raises(FileNotFoundError, match="the folder .*no such folder does not exist"):
        sim.scenes.single_box().to_file(path)
    assert not path.parent.exists()


def test_extendeds_old_impulse_threshold_names_what_replaced_it():
    # extended's impulse_threshold (N s) became impact_speed (m/s) in 2026-12: a World given
    # the old name says what replaced it (paper keeps its own impulse_threshold)
    with pytest.raises(ValueError, match="impact_speed .* replaced extended's impulse_threshold"):
        sim.World(sim.scenes.single_box(), freeze="extended", impulse_threshold=0.5)
    assert sim.World(sim.scenes.single_box(), freeze="paper", impulse_threshold=0.5)


@pytest.mark.parametrize("steps", [2**53 + 1, 2**62 - 1])
def test_an_integer_policy_parameter_is_taken_exactly(steps):
    # rest_steps went through a float: 2**62 - 1 became 2**62 and was refused as "< 2**62",
    # 2**53 + 1 silently became 2**53
    world = sim.World(sim.scenes.single_box(), freeze="extended", rest_steps=steps)
    assert world.policy_parameters["rest_steps"] == steps


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"rest_steps": 10**400}, r"rest_steps must be an integer >= 1 \(and < 2\*\*62\)"),
        ({"rest_speed": 10**400}, "rest_speed must be finite"),
    ],
)
def test_an_integer_beyond_floats_range_is_refused_by_name(kwargs, match):
    # float(10**400) raised a bare OverflowError from the argument checks
    with pytest.raises(ValueError, match=match):
        sim.World(sim.scenes.single_box(), freeze="extended", **kwargs)


_BOX = np.array([(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)])


@pytest.mark.parametrize(
    "build",
    [
        lambda: sim.Body(vertices=[(0, 0), (True, 0), (0, 1)]),
        lambda: sim.Scene.from_arrays(_BOX, [[True, 2.5]]),
        lambda: sim.Scene.from_arrays(_BOX, [[0.0, 2.5], [3.0, 2.5]], density=[True, 2.0]),
        lambda: sim.Scene.from_arrays(_BOX, [[0.0, 2.5]], velocity=[(1.0, np.False_)]),
    ],
)
def test_a_switch_among_numbers_in_a_list_is_refused(build):
    """numpy reads [True, 2.5] as the float array [1.0, 2.5]: a switch hidden among numbers was
    taken as 1.0 (until 2026-12-07), where the same switch alone is refused."""
    with pytest.raises(ValueError, match=r"switch \(True or False\)"):
        build()
