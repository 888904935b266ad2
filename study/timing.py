"""Wall-clock timing shared by every benchmark (docs/ARCHITECTURE.md §5): the garbage collector
paused, compared systems interleaved repeat by repeat so that machine noise hits them alike."""

import gc
import time


def timed(runner, steps):
    """Wall time of ``runner.step(steps)``, s, with the garbage collector paused (as timeit does:
    a collection landing inside one system's repeat would be charged to that system).

    A peer's runner does work of its own around its engine's steps (each checks its arguments;
    Box2D's reads every body's velocity through Python to catch its motion cap; pybullet's with
    sleeping reads every pose before the last step to tell sleep) and keeps the time inside the
    engine's step calls in ``engine_seconds``: that is what is returned for it, so that every
    peer is timed on its engine's stepping alone (pymunk's since 2026-12-07; before, its whole
    call). sim's runner (and a sim.World) is timed whole."""
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


def _round_robin(runners, counts, repeats, measure, progress):
    """``measure(runner, counts[k])`` of each runner, ``repeats`` times, round-robin over the
    runners (order reversed every other repeat, so that slow drifts in machine load hit all
    alike). Returns a list of lists."""
    times = [[] for _ in runners]
    order = list(range(len(runners)))
    for r in range(repeats):
        for k in order if r % 2 == 0 else order[::-1]:
            times[k].append(measure(runners[k], counts[k]))
            if progress is not None:
                progress.update()
    return times


def interleaved(runners, steps, repeats, progress=None):
    """Per-step times (ms) of each runner over ``repeats`` repeats of ``steps[k]`` steps in one
    call, round-robin over the runners. Returns a list of lists."""
    return _round_robin(runners, steps, repeats, lambda r, n: 1e3 * timed(r, n) / n, progress)


def single_calls(runner, calls):
    """ms per call of ``runner.step(1)``, the mean over ``calls`` calls (each timed as ``timed``
    times it). What a program that steps one step per call (a viewer, a game loop, a controller
    reading the state every step) pays per step, call overhead included: sim's World runs many
    steps in one compiled call, which the engines' Python APIs (one step per call) cannot, so
    its per-step times in long calls leave out a cost those programs pay."""
    return 1e3 * sum(timed(runner, 1) for _ in range(calls)) / calls


def interleaved_calls(runners, calls, repeats, progress=None):
    """``single_calls`` of each runner over ``repeats`` repeats of ``calls[k]`` calls, round-robin
    over the runners. Returns a list of lists (ms per call)."""
    return _round_robin(runners, calls, repeats, single_calls, progress)
