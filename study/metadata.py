"""What every results file records besides its numbers, and how results files are written.

``collect`` gathers the provenance of a run (scenes, parameters, seed, code version, packages,
machine, date); ``write_results`` writes ``<name>.csv`` and ``<name>.json`` atomically, the .json
recording the CSV's row count and SHA-256 (``csv``); ``read_results`` reads them back for analysis
and refuses (``ResultsError``, one line naming the file and the experiment to rerun) a file that is
missing, damaged, cut short or not the one its .json describes: each file is written whole, but
the pair is two files, and a copy, an edit or a full disk can still break one of them.
Nothing here may crash a finished experiment: anything unknowable is recorded as "unknown".
"""

import datetime
import hashlib
import importlib.metadata
import json
import math
import os
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from sim.files import write_text_atomically

from . import paths

#: Distributions whose versions can change a result or a timing (pip names): every one the code
#: imports (tests/pipeline/test_code_provenance.py reads the imports)
PACKAGES = (
    "numpy",
    "numba",
    "llvmlite",  # numba's code generator, and sim.clock's IR
    "pymunk",
    "pybullet",
    "box2d",
    "pyb2d3",
    "pandas",
    "matplotlib",
    "rerun-sdk",
    "typst",
    "tqdm",
    "dask",
    "distributed",
    "tomli-w",  # writes scene files (sim.Scene.to_file)
)


def collect(scene_or_scenes, parameters, script, seed=None, started=None):
    """Provenance of one run as a JSON-ready dict.

    scene_or_scenes  a sim.Scene, a list of them, or None
    parameters       the run's settings (dt, iterations, sizes, ...) as given on the command line
    script           the experiment's name, e.g. "bench_step"
    seed             a seed (or seeds) the run used beyond its scenes' own (a drift scene's random
                     velocities, piles run but not listed as scenes); the record's ``seed`` is
                     these and the scenes' seeds together, sorted (None: no seed at all)
    started          ``code_state()`` taken when the run started (default: now)

    ``git`` is the code's state when the run started: the code that ran (read at the end, an edit
    or a commit made during a long run was named as the results' code). If the commit or the
    working tree changed before the end, the results may come from more than one version of the
    code: ``code_changed_during_run`` says so, ``git.dirty`` is then true (no clean commit made
    them) and ``git_at_end`` is the state at the end.
    """
    return {
        "script": script,
        "scenes": _describe_scenes(scene_or_scenes),
        "parameters": jsonable(dict(parameters)),
        "seed": _seeds_of(scene_or_scenes, seed),
        **code_provenance(started or code_state()),
        "packages": package_versions(),
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
    text = dataframe.to_csv(index=False)
    metadata = {**metadata, "csv": {"rows": len(dataframe), "sha256": _sha256(text.encode())}}
    write_text_atomically(csv_path, text)
    write_text_atomically(json_path, json.dumps(jsonable(metadata), indent=2) + "\n")
    if metadata.get("code_changed_during_run") is True:
        # The code changed while this ran: the results may mix two versions of it. Dated now,
        # they were newer than the edit, and make took them as up to date. Dated at the epoch,
        # the next make reruns the experiment (the files stay, marked in their metadata).
        for path in (csv_path, json_path):
            os.utime(path, (0, 0))
    return csv_path, json_path


class ResultsError(Exception):
    """A results file that analysis must not read; the message is one line for the user."""


def make_quick(folder):
    """ " QUICK=1" when ``folder`` (a data folder) lies in a quick results tree, else "": what a
    make command named in a message needs (the hint named the full-size command for quick
    data)."""
    return " QUICK=1" if folder is not None and Path(folder).parent.name == "quick" else ""


def rerun_hint(script=None, folder=None):
    """What to do about a results file that cannot be read: rerun the experiment that wrote it,
    at quick sizes when the file lies in a quick tree (``folder``: its data folder; the hint
    named the full-size command for quick data)."""
    make = make_quick(folder)
    flag = " --quick" if make else ""
    if script is None:
        return (
            f"rerun the experiment that wrote it (`make reproduce{make}` reruns every missing one)"
        )
    return f"rerun the experiment: `make {script}{make}` or `python -m experiments.{script}{flag}`"


def read_metadata(json_path, script=None, required=()):
    """The metadata dict in ``json_path``, or ResultsError naming the file (missing, a folder,
    not JSON, or without one of the ``required`` keys its reader takes: the paper read
    ``meta["cpu"]`` of a file that lacked it, a KeyError instead of a one-line error)."""
    hint = rerun_hint(script, json_path.parent)
    try:
        meta = json.loads(json_path.read_text())
    except FileNotFoundError:
        raise ResultsError(f"{json_path} is missing: {hint}") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ResultsError(f"{json_path} is damaged ({exc}): {hint}") from None
    if not isinstance(meta, dict):
        raise ResultsError(f"{json_path} is not an experiment's metadata: {hint}")
    missing = [key for key in required if key not in meta]
    if missing:
        raise ResultsError(
            f"{json_path} is not an experiment's metadata (no {', '.join(missing)}): {hint}"
        )
    return meta


def read_results(folder, name, script=None):
    """(table, metadata) of ``<folder>/<name>.csv`` + ``.json``, made by experiment ``script``
    (default ``name``). Refuses (ResultsError) a missing or damaged file, and a CSV whose row
    count or SHA-256 is not what its .json recorded when both were written (a truncated copy, an
    edit, a CSV from another run)."""
    script = script or name
    csv_path, json_path = folder / f"{name}.csv", folder / f"{name}.json"
    meta = read_metadata(json_path, script)
    hint = rerun_hint(script, folder)
    try:
        raw = csv_path.read_bytes()
    except FileNotFoundError:
        raise ResultsError(f"{csv_path} is missing: {hint}") from None
    except OSError as exc:  # a folder of that name, no permission: one line, not a traceback
        raise ResultsError(f"{csv_path} cannot be read ({exc.strerror or exc}): {hint}") from None
    record = meta.get("csv")
    # the types too: rows "3" gave "has 3 rows where its .json records 3"
    if (
        not isinstance(record, dict)
        or not {"rows", "sha256"} <= set(record)
        or not isinstance(record["rows"], int)
        or isinstance(record["rows"], bool)
        or not isinstance(record["sha256"], str)
    ):
        raise ResultsError(
            f"{json_path} records no row count and checksum of {csv_path.name} (made by older "
            f"code, or edited): {hint}"
        )
    try:
        table = pd.read_csv(csv_path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ResultsError(f"{csv_path} is damaged ({exc}): {hint}") from None
    if len(table) != record["rows"]:
        raise ResultsError(
            f"{csv_path} has {len(table)} rows where its .json records {record['rows']} (cut "
            f"short or changed since it was written): {hint}"
        )
    if _sha256(raw) != record["sha256"]:
        raise ResultsError(
            f"{csv_path} is not the file its .json describes (its SHA-256 differs: changed "
            f"since it was written): {hint}"
        )
    return table, meta


def _sha256(data):
    return hashlib.sha256(data).hexdigest()


# ---- pieces ------------------------------------------------------------------------------------
def _seeds_of(scene_or_scenes, given=None):
    """Every seed a run used, sorted, or None if none: ``given`` (an int or a list: the script's
    own) and its scenes' (their ``params["seed"]``). The top-level seed was null in 11 of 15
    results files (2026-12-07), fig_time_to_rest's random piles among them; and a script that
    gave its own seed hid its scenes' (bench_freeze recorded its drift seed 0, not the seeds 0-2
    of its piles; fig_time_to_rest's catalogue seeds, not its 100-pile sample's)."""
    seeds = set()
    if given is not None:
        seeds.update([given] if np.ndim(given) == 0 else list(given))
    if scene_or_scenes is not None:
        scenes = [scene_or_scenes] if hasattr(scene_or_scenes, "bodies") else scene_or_scenes
        seeds.update(s.params["seed"] for s in scenes if s.params.get("seed") is not None)
    return sorted(int(s) for s in seeds) or None


def _describe_scenes(scene_or_scenes):
    """Each scene's name, params and body count, and the setting every runner takes from it:
    pymunk's collision_slop is matched to the scene's smallest body (``study.common.build``), so
    the ``system_settings`` a script records from one probe scene do not say what ran on the
    others."""
    from study.common import comparable_slop  # (study.common imports this module)

    if scene_or_scenes is None:
        return []
    scenes = [scene_or_scenes] if hasattr(scene_or_scenes, "bodies") else list(scene_or_scenes)
    return [
        {
            "name": s.name,
            "params": jsonable(dict(s.params)),
            "bodies": len(s.bodies),
            "pymunk_collision_slop_m": comparable_slop(s),
        }
        for s in scenes
    ]


def code_state():
    """(git_state(), fingerprint of the working tree) now; ``collect`` compares the two taken at
    a run's start and end."""
    return git_state(), tree_fingerprint()


def code_provenance(started):
    """The metadata's ``git``, ``code_changed_during_run`` (true, false or "unknown" without git)
    and, if it changed, ``git_at_end``, from ``code_state()`` at the start and now."""
    (git_start, print_start), (git_end, print_end) = started, code_state()
    if "unknown" in (print_start, print_end):
        return {"git": git_start, "code_changed_during_run": "unknown"}
    if print_start == print_end:
        return {"git": git_start, "code_changed_during_run": False}
    return {
        "git": {**git_start, "dirty": True},
        "code_changed_during_run": True,
        "git_at_end": git_end,
    }


def tree_fingerprint():
    """SHA-256 of the commit, the status (changed and untracked files) and the diff against the
    commit: what differs if the code is edited or committed ("unknown" without git). Untracked
    files count by name, not content."""
    digest = hashlib.sha256()
    try:
        for args in (
            ("rev-parse", "HEAD"),
            ("status", "--porcelain", "--untracked-files=normal"),
            ("diff", "HEAD", "--binary"),
        ):
            digest.update(_git(*args).encode())
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return digest.hexdigest()


def _git(*args):
    return subprocess.run(
        ["git", *args], cwd=paths.ROOT, capture_output=True, text=True, timeout=10, check=True
    ).stdout.strip()


def git_state():
    """Commit hash and whether tracked or untracked files differ from it ("unknown" without git)."""
    try:
        commit = _git("rev-parse", "HEAD")
    except (OSError, subprocess.SubprocessError):
        return {"commit": "unknown", "dirty": "unknown"}
    try:
        dirty = bool(_git("status", "--porcelain", "--untracked-files=normal"))
    except (OSError, subprocess.SubprocessError):
        dirty = "unknown"
    return {"commit": commit, "dirty": dirty}


def package_versions():
    """{distribution: installed version} of PACKAGES ("not installed" for one that is not)."""
    return {name: _version(name) for name in PACKAGES}


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
