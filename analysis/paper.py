"""Compile the write-up: paper/paper.typ -> paper/paper.pdf with the ``typst`` Python package.

Before compiling, writes ``generated/setup.json`` (machine, versions, commit, date, sizes: read
from the experiments' own metadata, so the set-up section is generated too). The paper reads only
``figures/`` and ``generated/`` beside it. When the outputs live elsewhere
(``study.paths.PAPER_OUT``: another results tree's paper/, e.g. the quick pipeline's), the source
is copied there first, so that both resolve the same way.

    python -m analysis.paper [--png DIR]     (--png: also render every page to DIR/page-N.png)
"""

import argparse
import inspect
import json
import math
import re
import shutil
from pathlib import Path

import typst

import sim
from sim import freeze
from sim.freeze import paper as freeze_paper
from study.peers import DEFAULT_ITERATIONS

from analysis.style import write_numbers
from study.metadata import ResultsError, make_quick, read_metadata
from study import paths
from study.cli import first_paragraph

SOURCES = ("paper.typ",)
#: the experiments whose metadata describes the set-up (the first one present is used)
SETUP_FROM = ("fig_speedup", "bench_step", "bench_freeze")


def world_defaults():
    """sim.World's keyword defaults (dt, iterations, slop, ...), as the paper quotes them."""
    return {
        name: p.default
        for name, p in inspect.signature(sim.World).parameters.items()
        if p.default is not inspect.Parameter.empty and isinstance(p.default, (int, float))
    }


def policy_parameters():
    """Each freeze policy's parameters and their defaults."""
    modules = {
        "off": freeze.off,
        "sleep": freeze.sleep,
        "paper": freeze.paper,
        "extended": freeze.extended,
    }
    return {name: dict(getattr(modules[name], "PARAMETERS", {})) for name in sim.POLICY_NAMES}


def provenance(metadata):
    """Which commit produced which results: ``metadata`` {result name: its metadata}. A list of
    {"commit": the first 10 hex digits, "+dirty" when the tree had uncommitted changes,
    "results": [names]}, the commit that produced the most results first (then by name), so that
    a results set remade in part says so instead of naming one commit for all of it."""
    by_commit = {}
    for name, m in sorted(metadata.items()):
        git = m.get("git", {})
        label = git.get("commit", "unknown")[:10] + ("+dirty" if git.get("dirty") else "")
        by_commit.setdefault(label, []).append(name)
    order = sorted(by_commit.items(), key=lambda kv: (-len(kv[1]), kv[0]))
    return [{"commit": label, "results": names} for label, names in order]


#: what the set-up numbers take from the first of SETUP_FROM's metadata
SETUP_KEYS = ("cpu", "cpu_count", "platform", "python", "packages", "date_utc")


def setup_numbers():
    """Machine, versions and provenance from the experiments' metadata."""
    quick, meta, metadata = set(), None, {}
    for path in sorted(paths.DATA.glob("*.json")):
        m = read_metadata(path)
        metadata[path.stem] = m
        quick.add(bool(m.get("parameters", {}).get("quick", False)))
    for name in SETUP_FROM:
        path = paths.DATA / f"{name}.json"
        if path.exists():
            meta = read_metadata(path, name, required=SETUP_KEYS)
            break
    if meta is None:
        raise ResultsError(
            f"no experiment metadata in {paths.DATA} (none of {', '.join(SETUP_FROM)}): "
            f"run `make reproduce{make_quick(paths.DATA)}`"
        )
    return meta, {
        "world": world_defaults(),
        "policies": policy_parameters(),
        "paper_floor_angle_deg": math.degrees(math.acos(freeze_paper.COS_FLOOR)),
        "peer_iterations": dict(DEFAULT_ITERATIONS),
        "cpu": meta["cpu"],
        "cpu_count": meta["cpu_count"],
        "platform": meta["platform"],
        "python": meta["python"],
        "packages": meta["packages"],
        "provenance": provenance(metadata),
        "quick": any(quick),
        "date_utc": meta["date_utc"],
    }


def compile_paper(png_dir=None):
    out = paths.ensure(paths.PAPER_OUT)
    if out != paths.PAPER:
        for name in SOURCES:
            shutil.copyfile(paths.PAPER / name, out / name)
    meta, numbers = setup_numbers()
    write_numbers("setup", numbers, meta)
    typeset(out, output=str(paths.PDF))
    print(f"wrote {paths.PDF}")
    if png_dir is not None:
        png_dir = paths.ensure(png_dir)
        typeset(out, output=str(png_dir / "page-{p}.png"), format="png", ppi=110)
        print(f"wrote {png_dir}/page-*.png")
    return paths.PDF


#: typst's error for a file the paper reads that is not there
NOT_FOUND = re.compile(r"file not found \(searched at (?P<path>[^)]+)\)")


def typeset(out, **options):
    """Compile ``out``/paper.typ; a figure, table or numbers file it reads that is missing is a
    ResultsError naming the file and what writes it (typst's error was a traceback)."""
    try:
        typst.compile(str(out / "paper.typ"), root=str(out), **options)
    except typst.TypstError as exc:
        found = NOT_FOUND.search(str(exc))
        if found is None:  # an error in paper.typ itself: a bug, with typst's own report
            raise
        raise ResultsError(missing_input(Path(found["path"]), out)) from None


def missing_input(path, out):
    """Why the paper cannot be compiled: ``path`` (under ``out``) is missing, and what remakes it:
    the analysis whose numbers list it among their outputs (``analysis.style.write_numbers``), or
    whose numbers it is."""
    try:
        relative = path.resolve().relative_to(out.resolve()).as_posix()
    except ValueError:
        relative = None
    writer = None
    for numbers in sorted(paths.GENERATED.glob("*.json")):
        try:
            if relative in json.loads(numbers.read_text()).get("outputs", []):
                writer = numbers.stem
        except (OSError, ValueError, AttributeError, TypeError):
            continue
    if writer is None and relative == f"generated/{path.stem}.json":
        writer = path.stem
    make = f"`make paper{make_quick(paths.DATA)}`"
    if writer is None:
        return f"{path} is missing, and no analysis records writing it: rerun the one that does"
    return f"{path} is missing: {make} draws it again, or `python -m analysis.{writer}`"


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python -m analysis.paper", description=first_paragraph(__doc__)
    )
    parser.add_argument("--png", default=None, help="also render each page to DIR/page-N.png")
    args = parser.parse_args(argv)
    try:
        return compile_paper(args.png)
    except ResultsError as exc:  # the user's data, not a bug: one line, no traceback
        raise SystemExit(f"python -m analysis.paper: {exc}") from None


if __name__ == "__main__":
    main()
