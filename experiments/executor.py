"""One executor for the independent runs of a sweep (DESIGN section 6).

``run_tasks(fn, tasks)`` calls ``fn(task)`` for every task and returns the results in task order,
with a tqdm bar. By default the runs go to a local process pool (one worker per core); with
``workers=1`` they run in this process (what timing runs need: they stay serial, on one machine).

``fn`` must be a module-level function and every task and result picklable; each task should carry
everything its run needs (scene parameters, system, settings), so a run is reproducible alone.
"""
import os
from concurrent.futures import ProcessPoolExecutor

from tqdm import tqdm


def default_workers():
    return max(1, os.cpu_count() or 1)


def run_tasks(fn, tasks, desc="runs", workers=None):
    """[fn(t) for t in tasks], in order, on ``workers`` local processes (default: one per core;
    1 = serially in this process). An exception in any run is raised here, naming the task."""
    tasks = list(tasks)
    workers = default_workers() if workers is None else int(workers)
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    results = [None] * len(tasks)
    with tqdm(total=len(tasks), desc=desc, unit="run") as bar:
        if workers == 1 or len(tasks) <= 1:
            for i, task in enumerate(tasks):
                results[i] = _call(fn, task)
                bar.update()
            return results
        with ProcessPoolExecutor(max_workers=min(workers, len(tasks))) as pool:
            futures = {pool.submit(_call, fn, task): i for i, task in enumerate(tasks)}
            for future in _as_completed(futures):
                results[futures[future]] = future.result()
                bar.update()
    return results


def _as_completed(futures):
    from concurrent.futures import as_completed
    return as_completed(futures)


def _call(fn, task):
    try:
        return fn(task)
    except Exception as exc:
        raise RuntimeError(f"run {task!r} failed: {type(exc).__name__}: {exc}") from exc
