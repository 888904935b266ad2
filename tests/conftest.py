"""Shared helpers for the tests."""

import math
import os

import pytest
from hypothesis import settings

import sim

# Property tests draw the same examples on every run (CI must not turn red by luck); set
# HYPOTHESIS_PROFILE=explore to search with fresh random examples.
settings.register_profile("repeatable", derandomize=True, deadline=None)
settings.register_profile("explore", derandomize=False, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "repeatable"))

G = 9.81
#: a unit box about its centre whose bottom edge is given in four parts (three collinear vertices)
SPLIT_BOX = [(-0.5, -0.5), (-0.25, -0.5), (0, -0.5), (0.25, -0.5), (0.5, -0.5)]
SPLIT_BOX += [(0.5, 0.5), (-0.5, 0.5)]


def tilted_box(width, height, angle, friction=0.6):
    """A width x height box rotated CCW by ``angle`` and standing on its lowest corner on the floor
    (y = 0), so that it starts exactly touching."""
    lowest = -0.5 * width * math.sin(angle) - 0.5 * height * math.cos(angle)
    return sim.Body.box(width, height, position=(0.0, -lowest), angle=angle, friction=friction)


def assert_timed_on_engine_alone(runner, steps):
    """study.timing.timed of a runner that does Python work of its own around its engine's step
    calls (``engine_seconds``) returns the engine's time, not the call's: equal to what
    ``engine_seconds`` gained, and under half the whole call, where the runner's work is several
    times the engine's (the caller picks such a scene)."""
    import time

    from study.timing import timed

    before, t0 = runner.engine_seconds, time.perf_counter()
    engine = timed(runner, steps)
    whole = time.perf_counter() - t0
    assert engine == pytest.approx(runner.engine_seconds - before)
    assert 0 < engine < whole / 2, (engine, whole)


def run_until(world, seconds):
    world.step(int(round(seconds / world.dt)))
    return world


@pytest.fixture(scope="session", autouse=True)
def _compile_once():
    """Compile (or load from the cache) every kernel once, before timing-sensitive tests."""
    sim.World(sim.scenes.stack(2)).step(2)


#: The slow tier, skipped by ``make test-fast`` (``pytest -m "not slow"``): every test under
#: tests/pipeline/, which runs a pipeline rather than a unit of code -- ``make`` itself, an
#: experiment, analysis or recording script end to end at quick sizes, or the compiled kernels'
#: machine code. About two thirds of the suite's time. The other folders: tests/unit/ (the solver,
#: the policies and the study library, against known answers and the slow references in
#: tests/naive*.py) and tests/adapters/ (the peers behind the Runner interface).
SLOW_FOLDER = "pipeline"


def pytest_collection_modifyitems(config, items):
    for item in items:
        if SLOW_FOLDER in item.path.relative_to(config.rootpath).parts:
            item.add_marker(pytest.mark.slow)
