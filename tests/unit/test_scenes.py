"""Scene builders and scene files."""

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import sim
from sim import files, scenes


@pytest.mark.parametrize(
    "name,args",
    [
        ("single_box", ()),
        ("rest_row", (7,)),
        ("stack", (5,)),
        ("pyramid", (6,)),
        ("drop", (12, 3)),
        ("arch", ()),
        ("seed_fig1", ()),
        ("seed_fig2", ()),
        ("seed_fig3", ()),
        ("sliding_box", ()),
    ],
)
def test_every_builder_makes_a_valid_non_overlapping_scene(name, args):
    scene = scenes.BUILDERS[name](*args)
    assert scene.name == name
    world = sim.World(scene, overlap_tolerance=1e-9)  # starts touching, never overlapping
    world.step(5)
    assert np.all(np.isfinite(world.positions))


def test_body_counts():
    assert len(scenes.pyramid(20).bodies) == 210
    assert len(scenes.pyramid(40).bodies) == 820
    assert len(scenes.rest_row(1000).bodies) == 1000
    assert len(scenes.stack(5).bodies) == 5
    assert len(scenes.drop(25, seed=0).bodies) == 25


def test_drop_is_seeded():
    a, b, c = scenes.drop(10, seed=1), scenes.drop(10, seed=1), scenes.drop(10, seed=2)
    va = [x.vertices for x in a.bodies]
    assert all(np.array_equal(x, y.vertices) for x, y in zip(va, b.bodies))
    assert not all(
        np.array_equal(x, y.vertices) for x, y in zip(va, c.bodies) if x.shape == y.vertices.shape
    )


def test_random_polygons_have_several_vertex_counts():
    counts = {len(b.vertices) for b in scenes.drop(40, seed=0).bodies}
    assert len(counts) >= 4 and min(counts) >= 3


def test_scene_file_round_trip(tmp_path):
    scene = scenes.drop(6, seed=9)
    path = tmp_path / "drop.toml"
    scene.to_file(path)
    loaded = sim.Scene.from_file(path)
    assert loaded.name == scene.name and loaded.params == scene.params
    for a, b in zip(loaded.bodies + loaded.static_bodies, scene.bodies + scene.static_bodies):
        np.testing.assert_array_equal(a.vertices, b.vertices)
        assert (a.position, a.angle, a.density, a.friction) == (
            b.position,
            b.angle,
            b.density,
            b.friction,
        )
    w1, w2 = sim.World(scene), sim.World(loaded)
    w1.step(60)
    w2.step(60)
    np.testing.assert_array_equal(w1.positions, w2.positions)


def test_scene_file_with_box_shorthand_and_no_floor(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(
        'floor_y = "none"\ngravity = [0.0, 0.0]\n'
        "[[bodies]]\nbox = [2.0, 1.0]\nposition = [0.0, 3.0]\nvelocity = [1.0, 0.0]\n"
    )
    scene = sim.Scene.from_file(path)
    assert scene.floor_y is None
    world = sim.World(scene)
    world.step(60)
    np.testing.assert_allclose(world.positions[0], [1.0, 3.0], atol=1e-12)
    assert world.masses[0] == pytest.approx(2.0)


def test_positions_are_centres_of_mass():
    # a right triangle given with its right angle at the body origin: the COM is at (1/3, 1/3)
    tri = sim.Body(vertices=[(0, 0), (1, 0), (0, 1)], position=(2.0, 0.0))
    world = sim.World(sim.Scene(bodies=[tri]))
    np.testing.assert_allclose(world.positions[0], [2 + 1 / 3, 1 / 3], atol=1e-12)
    np.testing.assert_allclose(world.vertices(0), [(2, 0), (3, 0), (2, 1)], atol=1e-12)


# ---- any name and any params key round-trip; a failed write leaves the old file ------------------
_VALUES = st.one_of(
    st.text(max_size=12),
    st.booleans(),
    st.integers(-(2**63), 2**63 - 1),
    st.floats(allow_nan=False),
    st.lists(st.integers(-5, 5), max_size=3),
)


@settings(max_examples=150, deadline=None)
@given(
    name=st.text(max_size=20),
    body_name=st.text(max_size=20),
    params=st.dictionaries(st.text(max_size=10), _VALUES, max_size=5),
)
def test_any_name_and_params_key_round_trip_through_a_scene_file(
    tmp_path_factory, name, body_name, params
):
    # newlines, quotes, backslashes, dots and spaces in keys: the hand-written writer mangled
    # "a.b" keys and wrote names with a newline that did not read back
    scene = sim.Scene(
        bodies=[sim.Body.box(1, 1, position=(0, 0.5), name=body_name)], name=name, params=params
    )
    path = tmp_path_factory.mktemp("toml") / "scene.toml"
    scene.to_file(path)
    loaded = sim.Scene.from_file(path)
    assert loaded == scene
    assert loaded.name == name and loaded.params == params


def test_a_failed_write_leaves_the_old_file_whole(tmp_path, monkeypatch):
    path = tmp_path / "scene.toml"
    scenes.single_box().to_file(path)
    before = path.read_bytes()
    unwritable = sim.Scene(
        bodies=[sim.Body.box(1, 1, position=(0, 0.5))], params={"callback": None}
    )  # TOML has no null
    with pytest.raises(ValueError, match="cannot be written as TOML"):
        unwritable.to_file(path)
    assert path.read_bytes() == before

    def full_disk(fd):  # fails after the text is written
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(files.os, "fsync", full_disk)
    with pytest.raises(OSError, match="No space left"):
        scenes.drop(4, seed=1).to_file(path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]  # no temporary left


def test_a_scene_file_cut_short_or_edited_is_refused_and_one_written_by_hand_loads(tmp_path):
    """20 of 111 cuts at a line boundary of one file loaded without an error, as another scene: a
    static wall gone, a body gone, a body's friction and name back at their defaults (a
    reviewer, 2026-12-07). A file to_file writes now records the SHA-256 of its contents."""
    box = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
    scene = sim.Scene(
        bodies=[
            sim.Body(vertices=box, position=(0, 0.5), friction=0.1, name="slider"),
            sim.Body(vertices=box, position=(3, 0.5), friction=0.1, restitution=0.5),
        ],
        static_bodies=[sim.Body(vertices=box, position=(6, 0.5), name="wall")],
    )
    path = tmp_path / "scene.toml"
    scene.to_file(path)
    assert sim.Scene.from_file(path).to_dict() == scene.to_dict()
    lines = path.read_text().splitlines(keepends=True)
    cut = tmp_path / "cut.toml"
    for n in range(1, len(lines)):
        cut.write_text("".join(lines[:n]))
        with pytest.raises(ValueError, match=f"^{re.escape(str(cut))}: "):
            sim.Scene.from_file(cut)
    edited = path.read_text().replace("friction = 0.1", "friction = 0.2", 1)
    path.write_text(edited)
    with pytest.raises(ValueError, match="cut short or edited. If you edited it, delete its"):
        sim.Scene.from_file(path)
    # the edit kept: the sha256 line deleted, as the message says (its note line may stay)
    path.write_text("".join(ln for ln in edited.splitlines(True) if not ln.startswith("sha256 ")))
    assert sim.Scene.from_file(path).bodies[0].friction == 0.2
