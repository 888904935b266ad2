"""What every results file records besides its numbers, and how results files are written.

``collect`` gathers the provenance of a run (scenes, parameters, seed, code version, packages,
machine, date); ``write_results`` writes ``<name>.csv`` and ``<name>.json`` atomically.
Nothing here may crash a finished experiment: anything unknowable is recorded as "unknown".
"""

import datetime
import importlib.metadata
import json
import math
import os
import platform
import subprocess
import sys

from sim.files import write_text_atomically

from . import paths

#: Distributions whose versions can change a result or a timing (pip names).
PACKAGES = (
    "numpy",
    "numba",
    "pymunk",
    "pybullet",
    "box2d",
    "pandas",
    "matplotlib",
    "rerun-sdk",
    "typst",
    "tqdm",
    "dask",
    "distributed",
)


def collect(scene_or_scenes, parameters, script, seed=None):
    """Provenance of one run as a JSON-ready dict.

    scene_or_scenes  a sim.Scene, a list of them, or None
    parameters       the run's settings (dt, iterations, sizes, ...) as given on the command line
    script           the experiment's name, e.g. "bench_step"
    """
    return {
        "script": script,
        "scenes": _describe_scenes(scene_or_scenes),
        "parameters": jsonable(dict(parameters)),
        "seed": seed,
        "git": git_state(),
        "packages": {name: _version(name) for name in PACKAGES},
        "python": sys.version.split()[0],
        "platform": platform.platform(),
        "cpu": _cpu_model(),
        "cpu_count": os.cpu_count(),
        "date_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }


def write_results(name, dataframe, metadata, folder=None):
    """Write ``<folder>/<name>.csv`` and ``<folder>/<name>.json`` (folder defaults to
    results/data) and return the two paths. Each file is written to a temporary file beside it
    and renamed over the target, so an interrupted run leaves the old file or the new one, never
    half of one."""
    folder = paths.ensure(paths.DATA if folder is None else folder)
    csv_path = folder / f"{name}.csv"
    json_path = folder / f"{name}.json"
    write_text_atomically(csv_path, dataframe.to_csv(index=False))
    write_text_atomically(json_path, json.dumps(jsonable(metadata), indent=2) + "\n")
    return csv_path, json_path


# ---- pieces ------------------------------------------------------------------------------------
def _describe_scenes(scene_or_scenes):
    if scene_or_scenes is None:
        return []
    scenes = [scene_or_scenes] if hasattr(scene_or_scenes, "bodies") else list(scene_or_scenes)
    return [
        {"name": s.name, "params": jsonable(dict(s.params)), "bodies": len(s.bodies)}
        for s in scenes
    ]


def git_state():
    """Commit hash and whether tracked or untracked files differ from it ("unknown" without git)."""

    def git(*args):
        return subprocess.run(
            ["git", *args], cwd=paths.ROOT, capture_output=True, text=True, timeout=10, check=True
        ).stdout.strip()

    try:
        commit = git("rev-parse", "HEAD")
    except (OSError, subprocess.SubprocessError):
        return {"commit": "unknown", "dirty": "unknown"}
    try:
        dirty = bool(git("status", "--porcelain", "--untracked-files=normal"))
    except (OSError, subprocess.SubprocessError):
        dirty = "unknown"
    return {"commit": commit, "dirty": dirty}


def _version(name):
    try:
        return importlib.metadata.version(name)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


def _cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.lower().startswith(("model name", "hardware", "cpu model")):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def jsonable(value):
    """Turn numpy scalars/arrays, tuples, paths and non-finite floats into plain JSON values."""
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if hasattr(value, "tolist"):  # numpy scalar or array
        return jsonable(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)  # JSON has no inf/nan
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    return str(value)
