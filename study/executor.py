"""One executor for the independent runs of a sweep (docs/ARCHITECTURE.md §5).

``run_tasks(fn, tasks)`` calls ``fn(task)`` for every task and returns the results in task order,
with a tqdm bar. Where the runs go:

    default                      a local process pool, one worker per core
    workers=1                    serially in this process (what timing runs need: they stay serial,
                                 on one machine, and never go through a pool)
    scheduler=ADDRESS, or the    a Dask distributed cluster (``distributed.Client(ADDRESS)``), e.g.
    FREEZE2D_SCHEDULER env var   tcp://10.0.0.5:8786 from `dask scheduler` + `dask worker` on each
    host

Incremental results: with ``store=PATH`` every finished run is appended to a JSON-lines file as
soon as it arrives (flushed and fsynced), keyed by ``key(task)``. A sweep that is interrupted and
started again reads the file and runs only what is missing; nothing finished is lost or redone.
The file's first line records what the runs were made by (``header``, e.g. the commit and the
sweep's configuration); a file with a different header is set aside (renamed ``*.stale``), not
mixed in. JSON-ready results are stored as JSON (readable); any other picklable result (numpy
arrays, say) as base64 pickle on its line, restored exactly.

A store cannot lie: every run's line carries the SHA-256 of its content, and a line that fails it
(a flipped bit), is not a run of the expected shape, or is torn (a run killed mid-write) is dropped
with a warning naming the line, its run is redone, and the file is rewritten without it (atomically)
before anything is appended, so a later line is never glued onto a fragment.

Interrupts: Ctrl-C (SIGINT) stops a sweep at once: queued runs are cancelled, running workers are
terminated, every finished run is already in the store, and KeyboardInterrupt propagates. Pool
workers die with their parent, however it died (SIGTERM, SIGKILL): no orphaned processes. On
Linux the kernel kills each worker when its parent dies (PR_SET_PDEATHSIG), at once, even inside
a kernel that holds the GIL; elsewhere a thread in each worker checks every WATCH_S seconds, which
needs the GIL (a worker inside compiled code outlived its parent by seconds, or by its whole run).

``fn`` must be a module-level function and every task picklable; each task should carry
everything its run needs (scene parameters, system, settings), so a run is reproducible alone.
"""

import base64
import ctypes
import hashlib
import json
import os
import pickle
import signal
import sys
import threading
import time
import warnings
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from tqdm import tqdm

SCHEDULER_ENV = "FREEZE2D_SCHEDULER"
#: s: how often a pool worker checks that the process that started it is still alive
WATCH_S = 0.2


class SchedulerError(Exception):
    """The Dask scheduler given cannot be used (unreachable, not an address); one line."""


def default_workers():
    return max(1, os.cpu_count() or 1)


class ResultStore:
    """Finished runs of one sweep in a JSON-lines file: line 1 the header, then one
    ``{"key": ..., "result": ..., "sha256": ...}`` (or ``"pickle"`` instead of ``"result"``) per
    run. Lines that are torn, of the wrong shape or fail their checksum are dropped (see the module
    docstring): ``dropped`` lists them as (line number, why)."""

    def __init__(self, path, header):
        self.path = Path(path)
        self.header = json.loads(json.dumps(header))  # compare as JSON would store it
        self.done = {}
        self.dropped = []
        if self.path.exists():
            self._load()
        if not self.path.exists():
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._append({"header": self.header})

    def _load(self):
        lines = self.path.read_bytes().decode("utf-8", errors="replace").split("\n")
        torn = lines[-1] != ""  # no newline after the last line
        lines = lines[:-1] if not torn else lines
        try:
            first = json.loads(lines[0]) if lines else {}
        except json.JSONDecodeError:
            first = {}
        if not isinstance(first, dict) or first.get("header") != self.header:
            stale = self.path.with_suffix(self.path.suffix + ".stale")
            os.replace(self.path, stale)
            print(
                f"{self.path}: made by a different commit or configuration; moved to {stale}, "
                f"starting afresh"
            )
            return
        kept = [lines[0]]
        for number, line in enumerate(lines[1:], start=2):
            why = self._read(line)
            if why is None:
                kept.append(line)
            else:
                self.dropped.append((number, why))
        if torn and self.dropped and self.dropped[-1][0] == len(lines):
            self.dropped[-1] = (len(lines), "torn (no end of line): a run killed mid-write")
        if self.dropped:
            warnings.warn(
                f"{self.path}: dropped {len(self.dropped)} stored run(s), to be redone: "
                + "; ".join(f"line {n}: {why}" for n, why in self.dropped[:5])
                + (" ..." if len(self.dropped) > 5 else ""),
                stacklevel=3,
            )
        if self.dropped or torn:
            tmp = self.path.with_suffix(self.path.suffix + ".tmp")
            tmp.write_text("".join(line + "\n" for line in kept))
            os.replace(tmp, self.path)

    def _read(self, line):
        """Take one stored run into ``done``; returns None, or why the line is not a run."""
        try:
            entry = json.loads(line)
        except json.JSONDecodeError:
            return "not JSON"
        if (
            not isinstance(entry, dict)
            or set(entry) not in ({"key", "result", "sha256"}, {"key", "pickle", "sha256"})
            or not isinstance(entry["key"], str)
        ):
            return "not a stored run (expected key, result or pickle, sha256)"
        if entry["sha256"] != _digest(entry):
            return "checksum mismatch: the line was changed after it was written"
        if "pickle" in entry:
            try:
                self.done[entry["key"]] = pickle.loads(base64.b64decode(entry["pickle"]))
            except Exception as exc:  # a valid checksum makes this a bug, not damage
                return f"pickle unreadable ({type(exc).__name__})"
        else:
            self.done[entry["key"]] = entry["result"]
        return None

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
        entry["sha256"] = _digest(entry)
        self._append(entry)


def _digest(entry):
    """SHA-256 of a stored run's content (everything but the digest), as its JSON is written."""
    content = {k: v for k, v in entry.items() if k != "sha256"}
    return hashlib.sha256(json.dumps(content, sort_keys=True).encode("utf-8")).hexdigest()


def _watch_parent(parent):
    """Pool worker initializer: exit as soon as the process that started the pool is gone (a
    parent killed by SIGTERM or SIGKILL cannot shut its pool down)."""
    if _die_with_parent(parent):
        return

    def watch():
        while os.getppid() == parent:
            time.sleep(WATCH_S)
        os._exit(1)

    threading.Thread(target=watch, daemon=True).start()


#: prctl(2) option: the signal the kernel sends this process when its parent dies
PR_SET_PDEATHSIG = 1


def _die_with_parent(parent):
    """Ask the kernel to SIGKILL this worker when its parent dies (Linux); True if it will. The
    "parent" is the thread that forked the worker: the pool forks its workers from the thread that
    submits the runs (run_tasks' caller), which lives until the pool is shut down."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) != 0:
            return False
    except (OSError, AttributeError):  # no prctl in this C library: the thread watches instead
        return False
    if os.getppid() != parent:  # the parent died before the request was made
        os._exit(1)
    return True


def run_tasks(
    fn, tasks, desc="runs", workers=None, scheduler=None, store=None, header=None, key=repr
):
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
            _run_pool(fn, tasks, todo, min(workers, len(todo)), finish)
    return [results[k] for k in keys]


def _run_pool(fn, tasks, todo, workers, finish):
    pool = ProcessPoolExecutor(
        max_workers=workers, initializer=_watch_parent, initargs=(os.getpid(),)
    )
    try:
        futures = {pool.submit(_call, fn, tasks[i]): i for i in todo}
        for future in as_completed(futures):
            finish(futures[future], future.result())
    except BaseException:
        # Ctrl-C or a failed run: stop now. Waiting for the queue (the default) ran every queued
        # run to the end and threw it away; finished runs are already in the store.
        # the pool's public API cannot stop a run in progress (cancel_futures only drops queued
        # ones), so its worker processes are terminated directly
        processes = list(getattr(pool, "_processes", {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            process.terminate()
        for process in processes:
            process.join(timeout=5)
        raise
    pool.shutdown(wait=True)


def _run_dask(fn, tasks, todo, address, finish):
    try:
        from distributed import Client, as_completed as dask_completed
    except ImportError as exc:  # pinned, so only a broken environment gets here
        raise RuntimeError("a Dask scheduler was given but `distributed` is not installed") from exc
    try:
        client = Client(address)
    except (OSError, ValueError, TypeError) as exc:  # unreachable, refused, not an address
        raise SchedulerError(f"cannot use the Dask scheduler {address!r}: {exc}") from None
    with client:
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
