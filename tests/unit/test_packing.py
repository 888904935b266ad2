"""sim.polygons, sim.packing and Scene.from_arrays against the one-body code they replace.

The references are slow loops written here: ``slow_pack`` is the World's per-body packing loop
(``World._pack`` before sim.packing existed) on ``sim.geometry``'s one-polygon functions; the
vectorised code must give the same arrays bit for bit, the same verdicts on polygons, and the same
error messages as Body-list scenes."""

import math

import numpy as np
import pytest

import sim
from conftest import SPLIT_BOX
from sim import geometry, polygons, scenes
from sim.body import MAX_COORDINATE
from sim.packing import Packed, pack

BOX = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]


# ---- references ---------------------------------------------------------------------------------
def slow_width(local):
    """Min over edges e of max over vertices v of dot(v_e - v, n_e), one polygon, loops."""
    normals = geometry.edge_normals(local)
    return min(max(float((local[e] - v) @ normals[e]) for v in local) for e in range(len(local)))


def slow_pack(scene):
    """The World's per-body packing loop, one body at a time with sim.geometry."""
    bodies = list(scene.bodies) + list(scene.static_bodies)
    n, m = len(scene.bodies), len(bodies)
    vert_start = np.zeros(m + 1, np.int64)
    np.cumsum([len(b.vertices) for b in bodies], out=vert_start[1:])
    out = {
        "n_dynamic": n,
        "vert_start": vert_start,
        "local_verts": np.empty((vert_start[-1], 2)),
        "local_normals": np.empty((vert_start[-1], 2)),
        "position": np.empty((m, 2)),
        "angle": np.empty(m),
        "velocity": np.zeros((m, 2)),
        "angular_velocity": np.zeros(m),
        "inv_mass": np.zeros(m),
        "inv_inertia": np.zeros(m),
        "mass": np.empty(n),
        "inertia": np.empty(n),
        "friction": np.empty(m),
        "restitution": np.empty(m),
        "extent": np.empty(m),
        "size": np.empty(m),
        "bullet": np.zeros(m, bool),
    }
    for i, b in enumerate(bodies):
        mass, centroid, inertia = geometry.mass_properties(b.vertices, b.density)
        local = b.vertices - centroid
        s0, s1 = vert_start[i], vert_start[i + 1]
        out["local_verts"][s0:s1] = local
        out["local_normals"][s0:s1] = geometry.edge_normals(local)
        c, s = math.cos(b.angle), math.sin(b.angle)
        out["position"][i] = (
            b.position[0] + c * centroid[0] - s * centroid[1],
            b.position[1] + s * centroid[0] + c * centroid[1],
        )
        out["angle"][i] = b.angle
        out["friction"][i] = b.friction
        out["restitution"][i] = b.restitution
        out["extent"][i] = float(np.max(np.hypot(local[:, 0], local[:, 1])))
        out["size"][i] = slow_width(local)
        if i < n:
            out["velocity"][i] = b.velocity
            out["angular_velocity"][i] = b.angular_velocity
            out["inv_mass"][i] = 1.0 / mass
            out["inv_inertia"][i] = 1.0 / inertia
            out["mass"][i] = mass
            out["inertia"][i] = inertia
            out["bullet"][i] = b.bullet
    return out


def assert_packed_equal(packed, expected, exact_size=False):
    assert isinstance(packed, Packed)
    assert set(Packed._fields) == set(expected)
    for name in Packed._fields:
        got, want = getattr(packed, name), expected[name]
        if name == "n_dynamic":
            assert got == want
            continue
        assert got.shape == np.shape(want), name
        assert got.dtype == np.asarray(want).dtype, name
        if name == "size" and not exact_size:  # the reference loops in another order
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=0, err_msg=name)
        else:
            np.testing.assert_array_equal(got, want, err_msg=name)


def random_convex(rng, k, radius=1.0, offset=(0.0, 0.0)):
    angles = np.sort(rng.uniform(0.0, 2 * math.pi, k))
    aspect = rng.uniform(0.2, 1.0)
    v = np.stack([radius * np.cos(angles), radius * aspect * np.sin(angles)], axis=1)
    return v + np.asarray(offset)


def packed(polys):
    vert_start = np.zeros(len(polys) + 1, np.int64)
    np.cumsum([len(p) for p in polys], out=vert_start[1:])
    return np.concatenate([np.asarray(p, float).reshape(-1, 2) for p in polys]), vert_start


def message(fn, *args):
    """The ValueError message of fn(*args), or None when it does not raise."""
    try:
        fn(*args)
    except ValueError as exc:
        return f"{type(exc).__name__}: {exc}"
    return None


# ---- pack() against the World's loop -------------------------------------------------------------
def mixed_scene():
    """Off-centre, rotated, spinning, dense, bouncy bodies of several vertex counts, a bullet,
    and static bodies (one rotated, one with many vertices)."""
    rng = np.random.default_rng(7)
    bodies = [
        sim.Body(
            vertices=random_convex(rng, k, 0.3, offset=(0.2, -0.1)),
            position=(1.5 * k, 3.0),
            angle=0.3 * k - 1.0,
            velocity=(0.1 * k, -1.0),
            angular_velocity=0.5 - 0.1 * k,
            density=0.5 + k,
            friction=0.1 * k,
            restitution=0.05 * k,
            bullet=k % 2 == 0,
        )
        for k in range(3, 12)
    ]
    walls = [
        sim.Body.box(0.5, 6.0, position=(-2.0, 3.0), angle=0.1, name="wall"),
        sim.Body.regular(40, 1.0, position=(20.0, 1.0), density=3.0, friction=0.9),
    ]
    return sim.Scene(bodies=bodies, static_bodies=walls, name="mixed")


@pytest.mark.parametrize(
    "build",
    [
        lambda: scenes.pyramid(6),
        lambda: scenes.drop(25, seed=3),
        lambda: scenes.arch(),
        scenes.seed_fig1,
        scenes.seed_fig2,
        scenes.seed_fig3,
        lambda: scenes.sliding_box(speed=2.0),
        mixed_scene,
    ],
    ids=["pyramid", "drop", "arch", "seed_fig1", "seed_fig2", "seed_fig3", "sliding_box", "mixed"],
)
def test_pack_equals_the_per_body_loop(build):
    scene = build()
    assert_packed_equal(pack(scene), slow_pack(scene))


def test_pack_of_a_box_has_the_box_numbers():
    p = pack(sim.Scene(bodies=[sim.Body.box(2.0, 0.5, position=(1.0, 0.25), density=3.0)]))
    assert p.mass[0] == 3.0 and p.inv_mass[0] == 1 / 3.0
    assert p.inertia[0] == pytest.approx(3.0 * (4.0 + 0.25) / 12.0, rel=1e-14)
    assert p.size[0] == 0.5 and p.extent[0] == pytest.approx(math.hypot(1.0, 0.25), rel=1e-15)
    np.testing.assert_array_equal(p.position, [[1.0, 0.25]])


# ---- sim.polygons against sim.geometry -----------------------------------------------------------
def random_polygons(seed, count=400, k_max=40):
    rng = np.random.default_rng(seed)
    polys = []
    while len(polys) < count:
        k = int(rng.integers(3, k_max + 1))
        p = random_convex(
            rng,
            k,
            radius=10 ** rng.uniform(-3, 2),
            offset=rng.uniform(-1e3, 1e3, 2) * rng.integers(0, 2),
        )
        if message(polygons.validate_polygon, p) is None:
            polys.append(p)
    return polys


def test_mass_properties_many_is_bit_for_bit_the_one_polygon_result():
    polys = random_polygons(1)
    vertices, vert_start = packed(polys)
    density = np.random.default_rng(2).uniform(0.1, 10.0, len(polys))
    mass, centroid, inertia = polygons.mass_properties_many(vertices, vert_start, density)
    for i, (p, d) in enumerate(zip(polys, density)):
        m_ref, c_ref, i_ref = geometry.mass_properties(p, d)
        assert (mass[i], inertia[i]) == (m_ref, i_ref), i
        np.testing.assert_array_equal(centroid[i], c_ref)


def test_collinear_vertices_are_dropped_and_nothing_else():
    # a unit box with its bottom edge in four parts, a triangle with a vertex mid-edge, and a
    # box whose corner is off by 1e-7 m (a real corner, kept)
    split = SPLIT_BOX
    tri = [(0, 0), (1, 0), (2, 0), (0, 1)]
    near = [(-0.5, -0.5), (0, -0.5 - 1e-7), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
    vertices = np.array(split + tri + near, float)
    vert_start = np.array([0, 7, 11, 16])
    out, start = polygons.drop_collinear(vertices, vert_start)
    np.testing.assert_array_equal(start, [0, 4, 7, 12])
    np.testing.assert_array_equal(out[0:4], [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)])
    np.testing.assert_array_equal(out[4:7], [(0, 0), (2, 0), (0, 1)])
    np.testing.assert_array_equal(out[7:], near)
    # none to drop: the very arrays come back (the World's polygons stay as given, to the bit)
    box = np.array(split[:1] + split[4:])
    same = polygons.drop_collinear(box, np.array([0, 4]))
    assert same[0] is box


def test_the_world_solves_a_polygon_without_its_collinear_vertices():
    split = SPLIT_BOX
    body = sim.Body(vertices=split, position=(1.0, 0.5), angle=0.3)
    world = sim.World(sim.Scene(bodies=[body], floor_y=None, gravity=(0.0, 0.0)))
    box = sim.World(
        sim.Scene(
            bodies=[sim.Body.box(1, 1, position=(1.0, 0.5), angle=0.3)],
            floor_y=None,
            gravity=(0.0, 0.0),
        )
    )
    np.testing.assert_allclose(world.vertices(0), box.vertices(0), atol=1e-15)
    assert body.mass == world.masses[0]  # the mass properties are the given polygon's


def test_edge_normals_extent_and_width_of_many_polygons():
    polys = random_polygons(3)
    vertices, vert_start = packed(polys)
    np.testing.assert_array_equal(
        polygons.edge_normals_many(vertices, vert_start),
        np.concatenate([geometry.edge_normals(p) for p in polys]),
    )
    _, centroid, _ = polygons.mass_properties_many(vertices, vert_start, 1.0)
    local = [p - c for p, c in zip(polys, centroid)]
    lv, _ = packed(local)
    np.testing.assert_array_equal(
        polygons.extent_many(lv, vert_start), [np.max(np.hypot(q[:, 0], q[:, 1])) for q in local]
    )
    np.testing.assert_allclose(
        polygons.thinnest_width_many(lv, vert_start), [slow_width(q) for q in local], rtol=1e-12
    )


def test_thinnest_width_of_known_shapes():
    shapes = [
        sim.Body.box(3.0, 0.2).vertices,
        sim.Body.box(0.7, 5.0).vertices,
        sim.Body.regular(3, 1.0).vertices,
        sim.Body.regular(6, 1.0).vertices,
    ]
    vertices, vert_start = packed(shapes)
    np.testing.assert_allclose(
        polygons.thinnest_width_many(vertices, vert_start),
        [0.2, 0.7, 1.5, math.sqrt(3.0)],
        rtol=1e-14,
    )


STAR = [
    (math.cos(math.pi / 2 + 4 * math.pi * i / 5), math.sin(math.pi / 2 + 4 * math.pi * i / 5))
    for i in range(5)
]
BAD_POLYGONS = [
    BOX[::-1],  # clockwise
    [(0, 0), (2, 0), (1, 0.2), (2, 2), (0, 2)],  # reflex vertex
    [(0, 0), (1, 0), (1, 0), (0, 1)],  # repeated vertex
    [(0, 0), (1, 0), (2, 0)],  # zero area
    [(0, 0), (1, 0)],  # too few
    [(0, 0), (1, math.nan), (0, 1)],
    [(0, 0), (1, math.inf), (0, 1)],
    [(1, 1), (1, 1), (1, 1)],  # all coincide
    STAR,  # winds twice
    [
        (math.cos(2 * math.pi * i / 1025), math.sin(2 * math.pi * i / 1025))
        for i in range(geometry.MAX_VERTICES + 1)
    ],  # too many
    [(0, 0), (1e7, -1e-3), (1e7 + 1, 0), (1e7, 1e-3)],  # needle tip (a 1e7 m kite)
]


@pytest.mark.parametrize("bad", range(len(BAD_POLYGONS)))
@pytest.mark.parametrize("where", [0, 3, 6])
def test_validate_polygons_reports_the_first_bad_polygon_as_validate_polygon_does(bad, where):
    good = random_polygons(5, count=6, k_max=8)
    polys = good[:where] + [BAD_POLYGONS[bad]] + good[where:] + [BAD_POLYGONS[0]]
    vertices, vert_start = packed(polys)
    asked = []

    def names(i):
        asked.append(i)
        return f"crate {i}"

    got = message(polygons.validate_polygons, vertices, vert_start, names)
    assert got is not None
    assert got == message(
        polygons.validate_polygon, np.asarray(BAD_POLYGONS[bad], float), f"crate {where}"
    )
    assert asked == [where]  # names only the culprit


def test_validate_polygons_passes_valid_polygons_and_screens_none_of_them():
    vertices, vert_start = packed(random_polygons(9))
    assert polygons.validate_polygons(vertices, vert_start, str) is None
    assert not polygons.polygon_suspects(vertices, vert_start).any()


def borderline_polygons(seed):
    """Polygons at the edge of each tolerance of validate_polygon, on both sides."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(60):
        s = 10 ** rng.uniform(-3, 3)
        f = 10 ** rng.uniform(-1, 1)
        off = rng.uniform(-1e3, 1e3, 2) * rng.integers(0, 2)
        # a midpoint pushed in or out by about the reflex tolerance (sine of the turn 1e-9)
        dent = f * 1e-9 * s * rng.choice([-1, 1])
        out.append(np.array([(0, 0), (s, 0), (s, s), (0.5 * s, s + dent), (0, s)]) + off)
        # a sliver of area about the zero-area tolerance (1e-12 scale^2)
        h = f * 2e-12 * s
        out.append(np.array([(0, 0), (s, 0), (0.5 * s, h)]) + off)
        # an edge about as short as the repeated-vertex tolerance (1e-9 scale)
        e = f * 1e-9 * s
        out.append(np.array([(0, 0), (s, 0), (s, s), (e, s), (0, s)]) + off)
        # collinear vertices (allowed) and a slightly clockwise sliver
        out.append(np.array([(0, 0), (0.5 * s, 0), (s, 0), (s, s), (0, s)]) + off)
        out.append(np.array([(0, 0), (s, 0), (0.5 * s, -h)]) + off)
    return out


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_borderline_polygons_get_the_reference_verdict(seed):
    polys = borderline_polygons(seed)
    reference = [message(polygons.validate_polygon, p, f"p{i}") for i, p in enumerate(polys)]
    assert 0 < sum(r is None for r in reference) < len(polys)  # both sides are represented
    for i, p in enumerate(polys):
        vertices, vert_start = packed([p])
        got = message(polygons.validate_polygons, vertices, vert_start, lambda _: f"p{i}")
        assert got == reference[i], i
    vertices, vert_start = packed(polys)
    first = next(r for r in reference if r is not None)
    assert message(polygons.validate_polygons, vertices, vert_start, lambda i: f"p{i}") == first


def test_packed_layout_errors_are_clear():
    with pytest.raises(ValueError, match=r"vertices must have shape \(V, 2\)"):
        polygons.validate_polygons(np.zeros((4, 3)), [0, 4], str)
    with pytest.raises(ValueError, match="vert_start must rise from 0"):
        polygons.validate_polygons(np.zeros((4, 2)), [0, 3], str)
    with pytest.raises(ValueError, match="vert_start must be a 1-D integer array"):
        polygons.validate_polygons(np.zeros((4, 2)), [0.0, 4.0], str)


# ---- Scene.from_arrays ---------------------------------------------------------------------------
def body_list_scene(
    polys,
    position,
    angle,
    velocity,
    angular_velocity,
    density,
    friction,
    restitution,
    bullet,
    names=None,
    **scene_kwargs,
):
    """The Body-list twin of a from_arrays scene (per-body values as lists)."""
    bodies = [
        sim.Body(
            vertices=polys[i],
            position=tuple(position[i]),
            angle=angle[i],
            velocity=tuple(velocity[i]),
            angular_velocity=angular_velocity[i],
            density=density[i],
            friction=friction[i],
            restitution=restitution[i],
            bullet=bool(bullet[i]),
            name=names[i] if names else "",
        )
        for i in range(len(position))
    ]
    return sim.Scene(bodies=bodies, **scene_kwargs)


def array_fields(n, seed=0):
    rng = np.random.default_rng(seed)
    return dict(
        position=np.stack([3.0 * np.arange(n), 2.0 + rng.uniform(0, 1, n)], axis=1),
        angle=rng.uniform(-3, 3, n),
        velocity=rng.uniform(-2, 2, (n, 2)),
        angular_velocity=rng.uniform(-1, 1, n),
        density=rng.uniform(0.5, 5, n),
        friction=rng.uniform(0, 1, n),
        restitution=rng.uniform(0, 1, n),
        bullet=rng.uniform(0, 1, n) < 0.3,
    )


SCENE_FIELDS = dict(
    floor_y=-1.0,
    gravity=(0.5, -3.0),
    floor_friction=0.3,
    floor_restitution=0.2,
    name="arrays",
    params={"n": 12},
)


def statics():
    return [
        sim.Body.box(1.0, 8.0, position=(-3.0, 4.0), name="left"),
        sim.Body.regular(7, 0.8, position=(60.0, 0.0), angle=0.4),
    ]


@pytest.mark.parametrize("layout", ["shared", "per_body", "packed"])
def test_from_arrays_packs_like_the_same_bodies_as_a_list(layout):
    n = 12
    f = array_fields(n)
    rng = np.random.default_rng(4)
    if layout == "shared":
        shape = random_convex(rng, 6, 0.5, offset=(0.1, 0.05))
        polys, vertices, extra = [shape] * n, shape, {}
    elif layout == "per_body":
        polys = [random_convex(rng, 5, 0.5, offset=(0.1, 0.0)) for _ in range(n)]
        vertices, extra = np.stack(polys), {}
    else:
        polys = [random_convex(rng, 3 + i % 6, 0.5, offset=(0.0, 0.2)) for i in range(n)]
        vertices, vert_start = packed(polys)
        extra = {"vert_start": vert_start}
    names = [f"b{i}" if i % 3 else "" for i in range(n)]
    scene = sim.Scene.from_arrays(
        vertices, names=names, static_bodies=statics(), **f, **extra, **SCENE_FIELDS
    )
    twin = body_list_scene(polys, names=names, static_bodies=statics(), **f, **SCENE_FIELDS)
    assert scene.body_arrays is not None and scene.n_bodies == n
    assert_packed_equal(pack(scene), slow_pack(twin))
    assert_packed_equal(pack(scene), pack(twin)._asdict(), exact_size=True)
    assert [scene.body_name(i) for i in range(n)] == [twin.body_name(i) for i in range(n)]
    assert scene.body_arrays is not None  # none of this created Body objects
    assert (scene.floor_y, scene.gravity, scene.name, scene.params) == (
        -1.0,
        (0.5, -3.0),
        "arrays",
        {"n": 12},
    )


def test_scalars_broadcast_and_defaults_are_body_defaults():
    scene = sim.Scene.from_arrays(BOX, [(0.0, 0.5), (2.0, 0.5)], density=2.0, bullet=True)
    default = sim.Body(vertices=BOX)
    a = scene.body_arrays
    np.testing.assert_array_equal(a.density, [2.0, 2.0])
    np.testing.assert_array_equal(a.bullet, [True, True])
    assert (a.friction[1], a.restitution[1], a.angle[1]) == (
        default.friction,
        default.restitution,
        0.0,
    )
    np.testing.assert_array_equal(a.velocity, np.zeros((2, 2)))
    assert scene.floor_y == 0.0 and scene.gravity == (0.0, -9.81) and scene.static_bodies == []


def test_from_arrays_copies_its_inputs_and_is_read_only():
    position = np.array([[0.0, 0.5], [2.0, 0.5]])
    scene = sim.Scene.from_arrays(np.array(BOX), position)
    position[0, 0] = 99.0
    assert scene.body_arrays.position[0, 0] == 0.0
    with pytest.raises(ValueError, match="read-only"):
        scene.body_arrays.position[0, 0] = 1.0


# ---- the same messages as Body-list scenes -------------------------------------------------------
N_BAD = 4
BAD = 2  # the index of the bad body


def good_fields():
    return dict(
        position=[(3.0 * i, 0.5) for i in range(N_BAD)],
        angle=[0.0] * N_BAD,
        velocity=[(0.0, 0.0)] * N_BAD,
        angular_velocity=[0.0] * N_BAD,
        density=[1.0] * N_BAD,
        friction=[0.5] * N_BAD,
        restitution=[0.0] * N_BAD,
        bullet=[False] * N_BAD,
    )


BAD_FIELDS = [
    ("density", 0.0),
    ("density", -1.0),
    ("density", math.nan),
    ("density", math.inf),
    ("friction", -0.1),
    ("friction", math.nan),
    ("friction", math.inf),
    ("restitution", 1.5),
    ("restitution", -0.5),
    ("restitution", math.nan),
    ("restitution", math.inf),
    ("position", (0.0, math.nan)),
    ("position", (math.inf, 0.0)),
    ("position", (2 * MAX_COORDINATE, 0.0)),
    ("position", (0.0, -2 * MAX_COORDINATE)),
    ("velocity", (math.inf, 0.0)),
    ("velocity", (0.0, math.nan)),
    ("angle", math.nan),
    ("angular_velocity", math.inf),
    ("angular_velocity", math.nan),
    ("bullet", 1),
    ("bullet", "yes"),
    ("vertices", BOX[::-1]),
    ("vertices", BAD_POLYGONS[1]),
    ("vertices", BAD_POLYGONS[2]),
    ("vertices", BAD_POLYGONS[3]),
    ("vertices", BAD_POLYGONS[4]),
    ("vertices", BAD_POLYGONS[5]),
    ("vertices", STAR),
]


def array_message(fields, polys, names=None, **kwargs):
    vertices, vert_start = packed(polys)
    return message(
        lambda: sim.Scene.from_arrays(
            vertices, vert_start=vert_start, names=names, **fields, **kwargs
        )
    )


def body_list_message(field, value, name=""):
    """The message a Body-list scene gives when body BAD's ``field`` is ``value``."""
    bodies = [
        sim.Body(
            vertices=BOX,
            name=name if i == BAD else "",
            **{k: v[i] for k, v in good_fields().items()},
        )
        for i in range(N_BAD)
    ]
    scene = sim.Scene(bodies=bodies)
    setattr(bodies[BAD], field, value)  # bodies are mutable; the scene re-checks
    return message(scene.validate)


@pytest.mark.parametrize(
    "field,value", BAD_FIELDS, ids=[f"{f}-{i}" for i, (f, _) in enumerate(BAD_FIELDS)]
)
@pytest.mark.parametrize("name", ["", "crate 7"])
def test_from_arrays_refuses_a_bad_body_with_the_body_message(field, value, name):
    fields = good_fields()
    polys = [BOX] * N_BAD
    if field == "vertices":
        polys[BAD] = value
    else:
        fields[field][BAD] = value
    names = [name if i == BAD else "" for i in range(N_BAD)]
    expected = body_list_message(field, value, name)
    assert expected is not None and expected.split(":")[1].strip() == (name or f"body {BAD}")
    assert array_message(fields, polys, names) == expected
    if name:  # a named body refuses the same value at creation, with the same message
        assert (
            message(lambda: sim.Body(**{"vertices": BOX, "name": name, field: value})) == expected
        )


def test_the_first_bad_body_is_reported_polygon_before_fields():
    fields = good_fields()
    polys = [BOX] * N_BAD
    fields["density"][3] = -1.0
    polys[1] = BOX[::-1]
    assert array_message(fields, polys) == body_list_message("vertices", BOX[::-1]).replace(
        f"body {BAD}", "body 1"
    )
    fields = good_fields()
    fields["friction"][1] = -1.0
    polys = [BOX] * N_BAD
    polys[3] = BOX[::-1]
    assert "body 1: friction must be >= 0" in array_message(fields, polys)
    fields = good_fields()  # one body, two problems
    fields["density"][BAD] = -1.0
    polys = [BOX] * N_BAD
    polys[BAD] = STAR
    assert array_message(fields, polys) == message(polygons.validate_polygon, STAR, f"body {BAD}")


def test_a_bad_shared_polygon_names_body_0():
    got = message(lambda: sim.Scene.from_arrays(BOX[::-1], [(0, 0.5), (3, 0.5)]))
    bodies = [sim.Body.box(1, 1, position=(0, 0.5)), sim.Body.box(1, 1, position=(3, 0.5))]
    scene = sim.Scene(bodies=bodies)
    for b in bodies:
        b.vertices = BOX[::-1]
    assert got == message(scene.validate) and "body 0: vertices are clockwise" in got


@pytest.mark.parametrize(
    "kwargs,problem",
    [
        (
            {"static_bodies": [sim.Body.box(1, 1, position=(9, 0.5), velocity=(1.0, 0.0))]},
            "static body 0: static bodies cannot move",
        ),
        ({"static_bodies": ["wall"]}, "static body 0: expected sim.Body"),
        ({"gravity": (0.0, math.nan)}, "scene: gravity is not finite"),
        ({"floor_friction": -1.0}, "scene: floor_friction must be >= 0"),
        ({"floor_restitution": 2.0}, "scene: floor_restitution must be in"),
        ({"floor_y": math.inf}, "scene: floor_y is not finite"),
    ],
)
def test_scene_fields_of_an_array_scene_are_checked_like_a_body_list_scene(kwargs, problem):
    got = message(lambda: sim.Scene.from_arrays(BOX, [(0.0, 0.5)], **kwargs))
    assert problem in got
    assert got == message(
        lambda: sim.Scene(bodies=[sim.Body(vertices=BOX, position=(0.0, 0.5))], **kwargs)
    )


@pytest.mark.parametrize(
    "kwargs,problem",
    [
        ({"position": [(0, 0.5, 1.0)]}, r"position must have shape \(N, 2\), got shape \(1, 3\)"),
        ({"position": (0.0, 0.5)}, r"position must have shape \(N, 2\)"),
        ({"position": np.zeros((0, 2))}, "scene: needs at least one body"),
        ({"position": [("a", "b")]}, "position must be numbers"),
        (
            {"vertices": np.zeros((2, 4, 2))},
            r"vertices must have shape .*\(N, K, 2\) = \(1, K, 2\)",
        ),
        ({"vertices": np.zeros((4, 3))}, r"vertices must have shape"),
        ({"vertices": [[(0, 0), (1, 0), (0, 1)], [(0, 0), (1, 0)]]}, "vertices must be numbers"),
        (
            {"vertices": np.array(BOX), "vert_start": [0, 2, 4]},
            r"vert_start must have shape \(N\+1,\) = \(2,\)",
        ),
        ({"vertices": np.array(BOX), "vert_start": [0, 3]}, "vert_start must rise from 0 to len"),
        (
            {"vertices": np.zeros((1, 4, 2)), "vert_start": [0, 4]},
            r"vertices must have shape \(V, 2\)",
        ),
        (
            {"density": [1.0, 2.0]},
            r"density must be a number or have shape \(N,\) = \(1,\), got shape \(2,\)",
        ),
        ({"friction": [[0.5]]}, r"friction must be a number or have shape \(N,\)"),
        ({"angle": "steep"}, "angle must be numbers"),
        (
            {"velocity": (1.0, 2.0, 3.0)},
            r"velocity must be a pair or have shape \(N, 2\) = \(1, 2\)",
        ),
        ({"bullet": [True, False]}, r"bullet must be a bool or have shape \(N,\) = \(1,\)"),
        ({"names": ["a", "b"]}, "names must be None or N = 1 strings"),
        ({"names": "a"}, "names must be None or N = 1 strings"),
        ({"names": [3]}, "names must be None or N = 1 strings"),
    ],
)
def test_bad_argument_shapes_name_the_argument(kwargs, problem):
    args = {"vertices": BOX, "position": [(0.0, 0.5)], **kwargs}
    with pytest.raises(ValueError, match=problem) as err:
        sim.Scene.from_arrays(args.pop("vertices"), args.pop("position"), **args)
    if "needs at least one" not in problem:
        assert str(err.value).startswith("Scene.from_arrays: ")


def test_a_valid_array_scene_is_not_checked_body_by_body(monkeypatch):
    """Only screened-in bodies get the one-body checks (their cost is what arrays avoid)."""
    import sim.scene as scene_module

    calls = []
    monkeypatch.setattr(scene_module, "check_fields", lambda *a: calls.append(a))
    monkeypatch.setattr(scene_module, "validate_polygon", lambda *a: calls.append(a))
    f = array_fields(50)
    f["bullet"] = np.asarray(f["bullet"])
    vertices, vert_start = packed(random_polygons(11, count=50, k_max=9))
    sim.Scene.from_arrays(vertices, vert_start=vert_start, **f)
    sim.Scene.from_arrays(BOX, f["position"], bullet=[True] * 50)
    assert calls == []


def test_bullet_lists_are_read_element_by_element():
    got = message(lambda: sim.Scene.from_arrays(BOX, [(0, 0.5), (3, 0.5)], bullet=[True, 1]))
    assert got == "ValueError: body 1: bullet must be True or False, got 1"
    scene = sim.Scene.from_arrays(BOX, [(0, 0.5), (3, 0.5)], bullet=np.array([True, False]))
    assert scene.body_arrays.bullet.dtype == bool


# ---- array scenes as Body lists and files --------------------------------------------------------
def array_scene(n=5):
    f = array_fields(n, seed=3)
    f["bullet"] = [True, False] + [False] * (n - 2)
    return sim.Scene.from_arrays(
        sim.Body.regular(5, 0.4).vertices,
        names=["", "named"] + [""] * (n - 2),
        static_bodies=statics(),
        **f,
        **SCENE_FIELDS,
    )


def test_bodies_are_created_on_first_use_and_then_are_the_truth():
    scene = array_scene()
    before = pack(scene)
    bodies = scene.bodies
    assert (
        scene.body_arrays is None and scene.bodies is bodies and len(bodies) == scene.n_bodies == 5
    )
    assert all(isinstance(b, sim.Body) for b in bodies)
    a = before
    for i, b in enumerate(bodies):  # each field as the Body path would hold it
        assert type(b.position) is tuple and type(b.position[0]) is float
        assert type(b.angle) is float and type(b.bullet) is bool
        fresh = sim.Body(
            vertices=b.vertices.copy(),
            position=b.position,
            angle=b.angle,
            velocity=b.velocity,
            angular_velocity=b.angular_velocity,
            density=b.density,
            friction=b.friction,
            restitution=b.restitution,
            name=b.name,
            bullet=b.bullet,
        )
        assert fresh.to_dict() == b.to_dict()
    assert (
        bodies[1].name == "named"
        and scene.body_name(1) == "named"
        and scene.body_name(2) == "body 2"
    )
    assert_packed_equal(pack(scene), a._asdict(), exact_size=True)  # same packing, now from Bodies
    scene.validate()  # cheap: fingerprints match
    bodies[3].vertices[0, 0] += 0.01  # edits in place are seen
    assert pack(scene).local_verts[3 * 5 : 4 * 5].tolist() != a.local_verts[3 * 5 : 4 * 5].tolist()
    bodies[4].density = -1.0
    with pytest.raises(ValueError, match="body 4: density must be > 0, got -1.0"):
        scene.validate()


def test_bodies_do_not_share_vertex_rows():
    scene = sim.Scene.from_arrays(BOX, [(0.0, 0.5), (3.0, 0.5)])
    a, b = scene.bodies
    a.vertices[:] = a.vertices[::-1].copy()
    assert b.vertices.tolist() == [list(p) for p in BOX]
    with pytest.raises(ValueError, match="body 0: vertices are clockwise"):
        scene.validate()


def test_to_dict_of_an_array_scene_equals_its_body_list_form(tmp_path):
    scene = array_scene()
    as_dict = scene.to_dict()
    assert scene.body_arrays is not None  # writing did not create the bodies
    path = tmp_path / "arrays.toml"
    scene.to_file(path)
    loaded = sim.Scene.from_file(path)
    assert loaded.to_dict() == as_dict == array_scene().to_dict()
    assert_packed_equal(pack(loaded), pack(array_scene())._asdict(), exact_size=True)
    materialised = array_scene()
    materialised.bodies  # noqa: B018 (creates them)
    assert materialised.to_dict() == as_dict


def test_repr_does_not_create_bodies():
    scene = array_scene()
    assert "<5 bodies in arrays>" in repr(scene) and scene.body_arrays is not None


# ---- Body.bullet -------------------------------------------------------------------------------
def test_bullet_is_a_bool_and_written_only_when_true(tmp_path):
    with pytest.raises(ValueError, match="crate: bullet must be True or False, got 1"):
        sim.Body(vertices=BOX, bullet=1, name="crate")
    assert "bullet" not in sim.Body(vertices=BOX).to_dict()
    assert sim.Body(vertices=BOX, bullet=np.bool_(True)).bullet is True
    scene = sim.Scene(
        bodies=[
            sim.Body(vertices=BOX, position=(0, 0.5), bullet=True),
            sim.Body(vertices=BOX, position=(3, 0.5)),
        ]
    )
    path = tmp_path / "b.toml"
    scene.to_file(path)
    assert path.read_text().count("bullet = true") == 1 and "bullet = false" not in path.read_text()
    assert [b.bullet for b in sim.Scene.from_file(path).bodies] == [True, False]
    body = scene.bodies[1]
    body.bullet = "no"
    with pytest.raises(ValueError, match="body 1: bullet must be True or False"):
        scene.validate()


def test_a_remembered_polygon_does_not_hide_a_later_edit():
    """Body skips re-checking a polygon it saw pass; a body whose polygon differs by one value
    is still checked in full."""
    sim.Body(vertices=BOX)
    almost = [list(p) for p in BOX]
    almost[2][0] = -0.6  # now reflex at vertex 2
    assert message(lambda: sim.Body(vertices=almost, name="e")) == message(
        polygons.validate_polygon, almost, "e"
    )
    assert message(lambda: sim.Body(vertices=almost, name="e")) is not None


# ---- one polygon shared by every body -----------------------------------------------------------
def _as_dict(packed):
    return {name: getattr(packed, name) for name in Packed._fields}


def _bits_equal(a, b):
    for name in Packed._fields:
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        assert x.shape == y.shape and x.dtype == y.dtype, name
        assert x.tobytes() == y.tobytes(), name  # -0.0 and 0.0 differ here


def test_a_shared_polygon_is_computed_once_with_the_same_bits():
    # 50 copies of a box with collinear vertices (dropped once, for all), turned and placed each
    # its own way, beside static bodies of their own shapes: packed sharing the polygon, the
    # arrays are those of packing it body by body, to the bit
    rng = np.random.default_rng(7)
    scene = sim.Scene.from_arrays(
        np.array(SPLIT_BOX),
        rng.uniform(-20.0, 20.0, (50, 2)) + (0.0, 30.0),
        angle=rng.uniform(-3.0, 3.0, 50),
        density=2.5,
        static_bodies=[
            sim.Body.box(0.5, 6.0, position=(-30.0, 3.0), angle=0.1),
            sim.Body.regular(7, 1.0, position=(30.0, 1.0)),
        ],
    )
    shared, alone = pack(scene), pack(scene, share=False)
    _bits_equal(shared, alone)
    assert len(shared.local_verts) == 50 * 4 + 4 + 7  # each split box a box again: 4 corners
    # (slow_pack keeps collinear vertices: test_pack_equals_the_per_body_loop compares a shared
    # polygon with it on pyramid, whose boxes all share one)


def test_bodies_that_differ_in_one_bit_or_density_are_not_shared():
    box = np.array(BOX, float)
    other = box.copy()
    other[0, 0] = np.nextafter(other[0, 0], 0.0)
    for vertices, density in (
        (np.stack([box, other, box]), 1.0),  # one coordinate one ulp apart
        (np.stack([box, box, box]), [1.0, 1.0, 2.0]),  # one density apart
    ):
        scene = sim.Scene.from_arrays(vertices, [(0, 1), (3, 1), (6, 1)], density=density)
        _bits_equal(pack(scene), pack(scene, share=False))
        assert pack(scene).mass[2] != pack(scene).mass[0] or density == 1.0
