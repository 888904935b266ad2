"""Wall-clock timing shared by every benchmark (docs/ARCHITECTURE.md §5): the garbage collector
paused, compared systems interleaved repeat by repeat so that machine noise hits them alike."""

import gc
import time


def timed(runner, steps):
    """Wall time of ``runner.step(steps)``, s, with the garbage collector paused (as timeit does:
    a collection landing inside one system's repeat would be charged to that system).

    A runner that does work of its own around its engine's steps (Box2D's reads every body's
    velocity through Python to catch its motion cap; pybullet's with sleeping reads every pose
    before the last step to tell sleep) keeps the time inside the engine's step calls in
    ``engine_seconds``: that is what is returned for it, so that every system is timed on its
    engine's stepping alone. Every other runner (and a sim.World) is timed whole."""
    engine = getattr(runner, "engine_seconds", None)
    gc_was_on = gc.isenabled()
    gc.disable()
    try:
        t0 = time.perf_counter()
        runner.step(steps)
        elapsed = time.perf_counter() - t0
    finally:
        if gc_was_on:
            gc.enable()
    return elapsed if engine is None else runner.engine_seconds - engine


def interleaved(runners, steps, repeats, progress=None):
    """Per-step times (ms) of each runner over ``repeats`` repeats of ``steps[k]`` steps,
    round-robin over the runners (order reversed every other repeat). Returns a list of lists."""
    times = [[] for _ in runners]
    order = list(range(len(runners)))
    for r in range(repeats):
        for k in order if r % 2 == 0 else order[::-1]:
            times[k].append(1e3 * timed(runners[k], steps[k]) / steps[k])
            if progress is not None:
                progress.update()
    return times
