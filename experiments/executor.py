"""One executor for the independent runs of a sweep (docs/ARCHITECTURE.md §5).

``run_tasks(fn, tasks)`` calls ``fn(task)`` for every task and returns the results in task order,
with a tqdm bar. Where the runs go:

    default                      a local process pool, one worker per core
    workers=1                    serially in this process (what timing runs need: they stay serial,
                                 on one machine, and never go through a pool)
    scheduler=ADDRESS, or the    a Dask distributed cluster (``distributed.Client(ADDRESS)``), e.g.
    FREEZE2D_SCHEDULER env var   tcp://10.0.0.5:8786 from `dask scheduler` + `dask worker` on each host

Incremental results: with ``store=PATH`` every finished run is appended to a JSON-lines file as
soon as it arrives (flushed and fsynced), keyed by ``key(task)``. A sweep that is interrupted and
started again reads the file and runs only what is missing; nothing finished is lost or redone.
The file's first line records what the runs were made by (``header``, e.g. the commit and the
sweep's configuration); a file with a different header is set aside (renamed ``*.stale``), not
mixed in. JSON-ready results are stored as JSON (readable); any other picklable result (numpy
arrays, say) as base64 pickle on its line, restored exactly.

``fn`` must be a module-level function and every task picklable; each task should carry
everything its run needs (scene parameters, system, settings), so a run is reproducible alone.
"""
import base64
import json
import os
import pickle
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from tqdm import tqdm

SCHEDULER_ENV = "FREEZE2D_SCHEDULER"


def default_workers():
    return max(1, os.cpu_count() or 1)


class ResultStore:
    """Finished runs of one sweep in a JSON-lines file: line 1 the header, then one
    ``{"key": ..., "result": ...}`` per run. A torn last line (a run killed mid-write) is ignored."""

    def __init__(self, path, header):
        self.path = Path(path)
        self.header = json.loads(json.dumps(header))      # compare as JSON would store it
        self.done = {}
        if self.path.exists():
            self._load()
        if not self.path.exists():
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._append({"header": self.header})

    def _load(self):
        lines = self.path.read_text().splitlines()
        try:
            first = json.loads(lines[0]) if lines else {}
        except json.JSONDecodeError:
            first = {}
        if first.get("header") != self.header:
            stale = self.path.with_suffix(self.path.suffix + ".stale")
            os.replace(self.path, stale)
            print(f"{self.path}: made by a different commit or configuration; moved to {stale}, "
                  f"starting afresh")
            return
        for line in lines[1:]:
            try:
                entry = json.loads(line)
            except json.JSONDecodeError:
                continue                                  # torn write: that run is redone
            if "pickle" in entry:
                self.done[entry["key"]] = pickle.loads(base64.b64decode(entry["pickle"]))
            else:
                self.done[entry["key"]] = entry["result"]

    def _append(self, entry):
        with open(self.path, "a") as f:
            f.write(json.dumps(entry) + "\n")
            f.flush()
            os.fsync(f.fileno())

    def add(self, key, result):
        self.done[key] = result
        try:
            json.dumps(result, allow_nan=True)
            entry = {"key": key, "result": result}
        except (TypeError, ValueError):
            entry = {"key": key, "pickle": base64.b64encode(pickle.dumps(result)).decode("ascii")}
        self._append(entry)


def run_tasks(fn, tasks, desc="runs", workers=None, scheduler=None, store=None, header=None,
              key=repr):
    """[fn(t) for t in tasks], in task order.

    workers    local processes (default one per core; 1 = serially in this process)
    scheduler  a Dask scheduler address; default the FREEZE2D_SCHEDULER environment variable.
               Given a scheduler, ``workers`` is ignored: the cluster's workers run the tasks.
    store      a JSON-lines file for incremental results (see the module docstring), with
               ``header`` (what made the runs) and ``key(task)`` -> str naming a run
    An exception in any run is raised here naming the task (finished runs stay in the store)."""
    tasks = list(tasks)
    keys = [key(t) for t in tasks]
    if len(set(keys)) != len(keys):
        raise ValueError("two tasks of the sweep have the same key; keys must name runs uniquely")
    scheduler = scheduler if scheduler is not None else os.environ.get(SCHEDULER_ENV) or None
    workers = default_workers() if workers is None else int(workers)
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    results = {}
    saved = ResultStore(store, header or {}) if store is not None else None
    if saved is not None:
        results.update({k: saved.done[k] for k in keys if k in saved.done})
    todo = [i for i, k in enumerate(keys) if k not in results]

    def finish(i, result):
        results[keys[i]] = result
        if saved is not None:
            saved.add(keys[i], result)
        bar.update()

    with tqdm(total=len(tasks), initial=len(tasks) - len(todo), desc=desc, unit="run") as bar:
        if scheduler:
            _run_dask(fn, tasks, todo, scheduler, finish)
        elif workers == 1 or len(todo) <= 1:
            for i in todo:
                finish(i, _call(fn, tasks[i]))
        else:
            with ProcessPoolExecutor(max_workers=min(workers, len(todo))) as pool:
                futures = {pool.submit(_call, fn, tasks[i]): i for i in todo}
                for future in as_completed(futures):
                    finish(futures[future], future.result())
    return [results[k] for k in keys]


def _run_dask(fn, tasks, todo, address, finish):
    try:
        from distributed import Client, as_completed as dask_completed
    except ImportError as exc:        # pinned, so only a broken environment gets here
        raise RuntimeError("a Dask scheduler was given but `distributed` is not installed") from exc
    with Client(address) as client:
        futures = {}
        for i in todo:
            futures[client.submit(_call, fn, tasks[i], pure=False)] = i
        for future in dask_completed(list(futures)):
            finish(futures[future], future.result())


def _call(fn, task):
    try:
        return fn(task)
    except Exception as exc:
        raise RuntimeError(f"run {task!r} failed: {type(exc).__name__}: {exc}") from exc
