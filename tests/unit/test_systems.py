"""The registry of systems (study/systems.py) is what every experiment and figure reads: its
derived lists must agree with its records, and each record with the runner it names."""

import pytest

import sim
from study import common, systems
from study.peers import make_runner


def test_every_reference_is_its_engine_with_nothing_frozen():
    for s in systems.REGISTRY:
        ref = systems.get(s.reference)
        assert ref.engine == s.engine and not ref.freezes, s
        assert systems.REFERENCE[s.name] == ref.name
    assert systems.OFF == {
        "sim": "sim-off",
        "pymunk": "pymunk",
        "pybullet": "pybullet",
        "box2d": "box2d",
    }
    assert set(systems.FREEZING) == {s.name for s in systems.REGISTRY if s.name != s.reference}
    assert systems.SLEEPING_PEERS == ("pymunk-sleep", "pybullet-sleep", "box2d-sleep")


def test_the_study_and_the_figures_read_the_registry():
    assert common.SYSTEMS == systems.SYSTEMS and common.REFERENCE == systems.REFERENCE
    looks = {
        (st["color"], st["marker"], st["linestyle"]) for st in map(systems.style, systems.SYSTEMS)
    }
    assert len(looks) == len(systems.SYSTEMS)  # every system drawn its own way
    assert systems.style("not a system")["color"] == "#777777"
    with pytest.raises(ValueError, match="unknown system 'box3d'.*box2d-sleep"):
        systems.get("box3d")


@pytest.mark.parametrize("name", systems.SYSTEMS)
def test_every_record_builds_the_runner_it_names(name):
    record = systems.get(name)
    with make_runner(name, sim.scenes.single_box()) as runner:
        assert runner.name == name and runner.settings["engine"] == record.engine
        runner.step(40)  # 0.67 s: past every sleep timer but
        asleep = bool(runner.asleep.all())  # pybullet's fixed 2 s
        if not record.freezes:
            assert not asleep, name
        elif record.engine != "pybullet":
            assert asleep, name  # a box placed at rest is frozen
