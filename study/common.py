"""What every study experiment shares: the comparable settings of the systems, building a runner,
compiling the kernels before any timing, short scene labels, the standard command line and writing
the results with their provenance.

An experiment script (one per figure or table, docs/ARCHITECTURE.md §5) looks like::

    def run(config, args) -> (pandas.DataFrame, scenes, parameters)
    main = common.entry(NAME, __doc__, FULL, QUICK, run)
"""

import argparse
import hashlib
import math
import os
import sys
from pathlib import Path

import numpy as np
import pandas as pd

import sim
from sim.tolerances import body_slop
from study import executor, paths, systems
from study.cli import first_paragraph
from study.metadata import code_state, jsonable, collect, package_versions, write_results
from study.peers import engine_of, make_runner
from study.timing import timed

DT = 1 / 60  # s, every system's step unless an experiment sweeps it
SLOP = 0.005  # m, sim's slop (a cap: see comparable_slop) and pymunk's collision_slop at 1 m
#: settings that make the systems comparable (iterations: each engine's default, see peers)
#: (Box2D's slop, b2_linearSlop, is compiled in: 0.005 m, the same; its runner records it)
SYSTEM_SETTINGS = {
    "sim": {"slop": SLOP},
    "pymunk": {"collision_slop": SLOP},
    "pybullet": {},
    "box2d": {},
    "box2d3": {},  # Box2D v3's linear slop is compiled in too: 0.005 m (benchmarks only)
}
#: every system of the study, and each one's sleeping-off reference (the registry's)
SYSTEMS = systems.SYSTEMS
REFERENCE = systems.REFERENCE
#: what "frozen" means in every table (the metadata says so)
FROZEN_MEANS = "sim: out of the awake list (World.frozen); pymunk/pybullet/box2d: asleep"


def compile_kernels():
    """Compile (or load from Numba's cache) every kernel, for every policy, on a tiny World, so
    that no timing includes JIT compilation."""
    for policy in sim.POLICY_NAMES:
        sim.World(sim.scenes.rest_row(2), dt=DT, freeze=policy).step(3)


def build(system, scene, dt=DT, **settings):
    """The runner of ``system`` on ``scene`` with the comparable settings (SYSTEM_SETTINGS;
    pymunk's slop that of ``scene``'s smallest body, ``comparable_slop``), overridden by
    ``settings``."""
    comparable = dict(SYSTEM_SETTINGS[engine_of(system)])
    if "collision_slop" in comparable:
        comparable["collision_slop"] = comparable_slop(scene)
    return make_runner(system, scene, dt=dt, **{**comparable, **settings})


def comparable_slop(scene):
    """m: pymunk's ``collision_slop`` matched to sim's on ``scene``. sim's slop (SLOP) is a cap:
    each pair's is SLOP_FRACTION of its smaller body's size below 1 m (``sim.tolerances``), while
    pymunk's is one length for the whole space. So pymunk gets the slop of the scene's smallest
    body: a 1 cm box sank 2.7 mm (27% of its size) into the floor under the flat 5 mm, where sim's
    sank nothing, and the extremes table marked pymunk's 1 cm stack as tunnelling. Where sizes
    differ, pymunk's larger bodies then get a smaller slop than sim's (stiffer, never softer)."""
    sizes = [body.size for body in (*scene.bodies, *scene.static_bodies)]
    return float(body_slop(min(sizes), SLOP)) if sizes else SLOP


def label(scene):
    """A short readable name of a scene: rest_row(50), drop(30,seed=1), mix(frozen=..,awake=..)."""
    p = scene.params
    if scene.name == "drop":
        return f"drop({p['n']},seed={p['seed']})"
    if scene.name in ("rest_row", "pyramid", "stack"):
        key = {"rest_row": "n", "pyramid": "base", "stack": "height"}[scene.name]
        return f"{scene.name}({p[key]})"
    if scene.name == "mix":
        return f"mix(frozen={p['n_frozen']},awake={p['n_awake']})"
    if scene.name in ("fall", "drift"):
        return f"{scene.name}({p['n']})"
    return scene.name


def awake_mask(runner):
    """(N,) bool: the bodies the system still works on: not ``asleep`` (for sim, ``asleep`` is
    ``World.frozen``, out of the awake list; under ``paper`` a pivoting VERTICAL_STABLE or a sliding
    ROTATION_STABLE body is still awake)."""
    return ~np.asarray(runner.asleep, dtype=bool)


def n_awake(runner):
    return int(awake_mask(runner).sum())


def step_until_frozen(runner, cap_steps):
    """Step one step at a time until no body is solved; returns the step count reached then
    (the runner's step_count), or None at the cap."""
    while runner.step_count < cap_steps:
        runner.step(1)
        if not awake_mask(runner).any():
            return runner.step_count
    return None


def calibrate(runner, target_s, probe=10, lo=10, hi=10**6):
    """Steps per repeat so that one repeat lasts about ``target_s`` (from ``probe`` untimed-ish
    steps, which also serve as warm-up). For a step of nanoseconds (a frozen sim scene) the probe
    times mostly the call, so its repeats come out shorter (a few ms for sim's ~15 us call: the
    call under 1% of a repeat). Capped at 5000 steps, a frozen sim repeat lasted ~0.1 ms, a tenth
    of it the call, and the frozen speed-ups came out ~10% low."""
    t = timed(runner, probe) / probe
    return int(min(hi, max(lo, round(target_s / max(t, 1e-9)))))


def pose_error(positions, angles, ref_positions, ref_angles):
    """(largest centre distance m, largest angle difference rad) between two poses of the same
    bodies; angles compared modulo 2 pi."""
    d = np.hypot(*(np.asarray(positions) - np.asarray(ref_positions)).T)
    a = np.abs(np.angle(np.exp(1j * (np.asarray(angles) - np.asarray(ref_angles)))))
    return float(d.max()), float(a.max())


def data_folder(quick, data_dir=None):
    """Where an experiment writes ``<name>.csv`` + ``.json``: ``data_dir`` if given (tests), else
    data/ in its results tree (``paths.results_tree``: a --quick run's own, never the full one)."""
    return Path(data_dir) if data_dir is not None else paths.results_tree(quick) / "data"


def store_path(name, args):
    """The incremental store of experiment ``name``'s untimed sweep runs (see executor): in
    partial/ beside the run's data folder (``args.data_dir``, set by ``entry``), so a quick run
    and a full one never share a results tree's store."""
    suffix = "-quick" if args.quick else ""
    return Path(args.data_dir).parent / "partial" / f"{name}{suffix}.jsonl"


def sweep_store(name, args, config):
    """(path, header) for ``executor.run_tasks(..., store=path, header=header)``: the header names
    the configuration, a hash of the solver's, the study library's and the scripts' sources and
    the versions of the packages a result records, so a store left by other code (uncommitted
    edits included) or by other engines (a changed pin: pymunk's, numba's) is never resumed. Not
    the commit: the sources are what runs, and a commit that changed none of them (the README's
    results block, a note) threw away an interrupted sweep's finished runs."""
    digest = hashlib.sha256()
    for f in sorted(
        list((paths.ROOT / "sim").rglob("*.py"))
        + list((paths.ROOT / "study").rglob("*.py"))
        + list((paths.ROOT / "experiments").rglob("*.py"))
    ):
        digest.update(f.read_bytes())
    header = {
        "config": jsonable(config),
        "source": digest.hexdigest()[:16],
        "packages": package_versions(),
    }
    return store_path(name, args), header


def interrupted(name, folder):
    """The one line a timed experiment (no store: timings are never resumed) prints when Ctrl-C
    stops it; returns the exit status, 130 as the shell's. Without it bench_step, bench_freeze
    and peer_agreement printed a 14-frame traceback."""
    table = Path(folder) / f"{name}.csv"
    kept = f" ({table} left as it was)" if table.exists() else ""
    print(f"python -m experiments.{name}: stopped (Ctrl-C); nothing kept{kept}", file=sys.stderr)
    return 130


def stopped(name, args):
    """What a run of experiment ``name`` stopped by Ctrl-C leaves: its results are written only at
    the end, but a sweep's finished runs are in its store (``store_path``), resumed by the next
    run."""
    store = store_path(name, args)
    try:
        runs = len(store.read_text().splitlines()) - 1  # the first line is the header
    except OSError:
        runs = 0
    if runs <= 0:
        table = Path(args.data_dir) / f"{name}.csv"
        return "stopped (Ctrl-C); nothing kept" + (
            f" ({table} left as it was)" if table.exists() else ""
        )
    return (
        f"stopped (Ctrl-C); {runs} finished run(s) kept in {store}: the same command resumes "
        "from them"
    )


def subset_folder(args):
    """Where a run of part of an experiment's table (``entry``'s ``subset``) writes it: only/
    beside the data folder, which make and analysis never read, so that a part never replaces the
    whole table."""
    return Path(args.data_dir).parent / "only"


def entry(name, doc, full, quick, run, extra_args=None, subset=None, sweep=False):
    """The standard command line of an experiment: ``python -m experiments.<name> [--quick]``.

    run(config, args) -> (table DataFrame, scenes, parameters dict); the returned ``main(argv=None,
    data_dir=None)`` parses, runs, writes ``<data_dir>/<name>.csv`` + ``.json`` (data_dir defaults
    to results/data, results/quick/data for --quick: ``data_folder``; ``args.data_dir`` tells
    ``run`` which) and prints the table. ``extra_args(parser)`` may add options.

    ``subset(config, args)`` -> bool says whether the options leave part of the table out (e.g.
    ``--only``): such a run writes into ``subset_folder`` instead and keeps the sweep's store,
    whose other runs the whole table still needs.

    ``sweep``: the experiment sends untimed runs through ``executor.run_tasks``; only then does it
    offer --scheduler and record its executor (a script without a sweep never uses one)."""

    def main(argv=None, data_dir=None):
        parser = argparse.ArgumentParser(
            prog=f"python -m experiments.{name}", description=first_paragraph(doc)
        )
        parser.add_argument(
            "--quick",
            action="store_true",
            help="the same code on small sizes (CI, `make reproduce QUICK=1`)",
        )
        if sweep:
            parser.add_argument(
                "--scheduler",
                default=None,
                metavar="ADDRESS",
                help="run the sweep's untimed runs on this Dask scheduler (default: "
                f"${executor.SCHEDULER_ENV}, else a local process pool); timed "
                "runs always stay serial on this machine",
            )
        if extra_args is not None:
            extra_args(parser)
        args = parser.parse_args(argv)
        started = code_state()  # the code that runs (collect says if it changes before the end)
        args.data_dir = data_folder(args.quick, data_dir)
        if getattr(args, "scheduler", None):
            os.environ[executor.SCHEDULER_ENV] = args.scheduler
        config = quick if args.quick else full
        try:
            table, scenes, parameters = run(config, args)
        except executor.SchedulerError as exc:  # the user's address, not a bug: one line
            raise SystemExit(f"python -m experiments.{name}: {exc}") from None
        except KeyboardInterrupt:  # Ctrl-C: what was kept, in one line, status 130 as the shell's
            print(f"python -m experiments.{name}: {stopped(name, args)}", file=sys.stderr)
            raise SystemExit(130) from None
        if not isinstance(table, pd.DataFrame) or table.empty:
            raise RuntimeError(f"{name}: the experiment produced no rows")
        parameters = {"quick": args.quick, "config": config, **parameters}
        if sweep:
            parameters["executor"] = os.environ.get(executor.SCHEDULER_ENV) or "local process pool"
        metadata = collect(
            scenes, parameters, script=name, seed=parameters.get("seed"), started=started
        )
        partial = subset is not None and subset(config, args)
        folder = subset_folder(args) if partial else args.data_dir
        csv_path, _ = write_results(name, table, metadata, folder=folder)
        if not partial:
            # the results are written: an incremental store has nothing left to resume
            store_path(name, args).unlink(missing_ok=True)
        with pd.option_context(
            "display.width", 200, "display.max_columns", 30, "display.max_rows", 60
        ):
            print(table.to_string(index=False, float_format=lambda x: f"{x:.4g}"))
        print(f"wrote {csv_path}")
        if partial:
            print(f"(part of the table only: {args.data_dir / (name + '.csv')} is left as it was)")
        return table

    return main


def finite_or_nan(x):
    x = float(x)
    return x if math.isfinite(x) else math.nan
