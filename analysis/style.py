"""One look for every figure, and the few ways analysis reads data and writes paper inputs.

Every ``analysis/<name>.py`` turns ``results/data/<name>.csv`` (+ ``.json``) into some of:

    paper/figures/<name>.svg        matplotlib, Agg backend, this module's style
    paper/generated/<name>.csv      tables the Typst paper reads with csv(...)
    paper/generated/<name>.json     every number the paper's text quotes, read with json(...)

and never runs a simulation (re-plotting is cheap; Make rules on files keep it so).
``main = style.entry(NAME, draw)`` gives each module its command line; ``draw(table, meta)``
returns the dict of numbers written to ``<name>.json`` (always written: it is the Make target).
"""

import argparse
import json
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)

from study import paths, systems  # noqa: E402
from study.cli import first_paragraph  # noqa: E402
from study.metadata import ResultsError, jsonable, read_results  # noqa: E402
from sim.files import write_text_atomically  # noqa: E402

#: one colour, marker and line per system, everywhere (the registry's: study.systems)
SYSTEM_STYLE = {name: systems.style(name) for name in systems.SYSTEMS}
#: body state -> RGB 0..255 (FREE, VERTICAL_STABLE, ROTATION_STABLE, SLEEPING); the recordings use
#: the same colours, frozen bodies drawn darker
STATE_RGB = ((66, 135, 245), (245, 166, 35), (80, 190, 90), (150, 150, 150))
STATE_LABEL = ("free (vertical-unstable)", "vertical-stable", "rotation-stable", "sleeping")
WIDTH = 6.3  # in, the paper's text width
RC = {
    "figure.figsize": (WIDTH, 3.0),
    "figure.dpi": 100,
    "font.size": 8,
    "axes.titlesize": 9,
    "axes.labelsize": 8,
    "legend.fontsize": 7,
    "xtick.labelsize": 7,
    "ytick.labelsize": 7,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.5,
    "lines.linewidth": 1.2,
    "lines.markersize": 4,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "svg.hashsalt": "freeze2d",  # stable ids: an unchanged figure is an unchanged file
    "savefig.bbox": "tight",
}
plt.rcParams.update(RC)


def state_color(state, frozen=False):
    """Matplotlib colour of a body state (int), darker when frozen."""
    rgb = STATE_RGB[int(state)]
    scale = 0.5 if frozen else 1.0
    return tuple(scale * c / 255 for c in rgb)


def system_style(system):
    """Colour, marker and line of a system (grey dots for a name the registry does not know)."""
    return systems.style(system)


def load(name, script=None):
    """(table, metadata) of ``results/data/<name>.{csv,json}``, made by experiment ``script``
    (default ``name``); ``metadata.ResultsError`` naming the file when one is missing, damaged or
    not what the experiment wrote (``study.metadata.read_results``)."""
    return read_results(paths.DATA, name, script)


#: the figures and tables this analysis wrote, as "figures/<name>.svg" (beside paper.typ's
#: folders), recorded in its numbers' "outputs" (``write_numbers``): make reruns an analysis one of
#: whose outputs has gone missing since (tools/lost_outputs.py), as it reruns an experiment whose
#: data file has, and the paper names the analysis that writes a file it cannot find
_written = []


def _wrote(path):
    _written.append(f"{path.parent.name}/{path.name}")
    return path


def save_figure(fig, name):
    """Write ``paper/figures/<name>.svg`` (no date in the file, so reruns compare equal)."""
    path = paths.ensure(paths.FIGURES) / f"{name}.svg"
    fig.savefig(path, format="svg", metadata={"Date": None})
    plt.close(fig)
    return _wrote(path)


def write_table(table, name):
    """Write ``paper/generated/<name>.csv`` (a table the paper shows as is)."""
    path = paths.ensure(paths.GENERATED) / f"{name}.csv"
    write_text_atomically(path, table.to_csv(index=False))
    return _wrote(path)


def write_numbers(name, numbers, meta, source=None):
    """Write ``paper/generated/<name>.json``: the numbers the paper quotes, the experiment's
    parameters (so that the paper quotes those from data too) and where they came from (the data
    file ``source``, if they were read from one; commit, quick or full sizes) and the figures and
    tables written with them (``outputs``). Non-finite numbers become strings ("nan")."""
    outputs = sorted(set(_written))
    _written.clear()
    out = {
        "numbers": numbers,
        "outputs": outputs,
        "parameters": meta.get("parameters", {}),
        # the file actually read (it said results/data/<name>.csv for a quick tree's data too,
        # and for the set-up, which has no data file of its own)
        **({"source": _repository_path(source)} if source is not None else {}),
        "commit": meta.get("git", {}).get("commit", "unknown"),
        "quick": bool(meta.get("parameters", {}).get("quick", False)),
        "date_utc": meta.get("date_utc", "unknown"),
    }
    path = paths.ensure(paths.GENERATED) / f"{name}.json"
    write_text_atomically(path, json.dumps(jsonable(out), indent=2) + "\n")
    return path


def _repository_path(path):
    """``path`` relative to the repository when inside it (results/quick/data/x.csv), else
    absolute."""
    path = Path(path).resolve()
    return path.relative_to(paths.ROOT).as_posix() if path.is_relative_to(paths.ROOT) else str(path)


def fmt(x, digits=3):
    """A number as the paper prints it: ``digits`` significant figures, "n/a" when not finite."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "n/a"
    return f"{x:.{digits}g}"


def entry(name, draw):
    """The command line ``python -m analysis.<name>``: load, draw, write the numbers."""

    def main(argv=None):
        parser = argparse.ArgumentParser(
            prog=f"python -m analysis.{name}",
            description=first_paragraph(sys.modules[draw.__module__].__doc__ or name),
            epilog=f"Reads results/data/{name}.csv (+ .json); takes no options.",
        )
        parser.parse_args(argv)
        _written.clear()  # only what this run writes
        try:
            table, meta = load(name)
            numbers = draw(table, meta) or {}
        except ResultsError as exc:  # the user's data, not a bug: one line, no traceback
            raise SystemExit(f"python -m analysis.{name}: {exc}") from None
        path = write_numbers(name, numbers, meta, source=paths.DATA / f"{name}.csv")
        print(f"wrote {path}")
        return numbers

    return main
