"""A rerun recording of a run opens with rerun's own tools and holds what it should."""
import os
import re
import subprocess
import sys
from pathlib import Path

import sim
from analysis import trace

RERUN = Path(sys.executable).with_name("rerun")
ENV = {**os.environ, "RERUN_ANALYTICS": "0"}


def rows_per_entity(path):
    out = subprocess.run([str(RERUN), "rrd", "print", "-v", str(path)], capture_output=True,
                         text=True, check=True, env=ENV).stdout
    rows = {}
    for n, entity in re.findall(r"with (\d+) rows .*? - (/\S+) - data columns", out):
        rows[entity] = rows.get(entity, 0) + int(n)
    return rows


def test_recording_verifies_and_has_every_entity_and_frame(tmp_path):
    path = tmp_path / "seed_fig3__paper.rrd"
    steps = 40
    world = trace.record(sim.scenes.seed_fig3(), "paper", steps, path)
    check = subprocess.run([str(RERUN), "rrd", "verify", str(path)], capture_output=True,
                           text=True, env=ENV)
    assert check.returncode == 0, check.stderr
    rows = rows_per_entity(path)
    for entity in ("/world/bodies", "/world/contacts", "/world/impulses", "/timeline/awake",
                   "/timeline/kinetic_energy"):
        assert rows.get(entity) == steps + 1, (entity, rows)       # step 0 and every step
    assert rows["/timeline/step_ms"] == steps
    assert rows["/world/floor"] == 1                                # static
    assert rows["/events"] == len(world.events) > 0                 # one log entry per event


def test_trace_command_writes_the_named_file(tmp_path):
    out = trace.main(["single_box", "extended", "--steps", "5", "--out", str(tmp_path / "x.rrd")])
    assert Path(out).stat().st_size > 1000


def test_every_scene_builder_can_be_traced_by_name(tmp_path):
    for name in sim.scenes.BUILDERS:                  # `make trace SCENE=<name>` needs defaults
        trace.main([name, "off", "--steps", "1", "--out", str(tmp_path / f"{name}.rrd")])
    trace.main(["pyramid", "sleep", "--size", "4", "--steps", "2",
                "--out", str(tmp_path / "p4.rrd")])
