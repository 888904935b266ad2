"""Every path the study uses, derived from the repository root in this one place.

Two environment variables move the outputs, read once, at import (the Makefile sets both for
``make reproduce QUICK=1`` so that quick results never overwrite full ones; tests point them into
temporary folders):

    FREEZE2D_RESULTS    the results tree: data/, partial/, recordings/   (default <root>/results;
                        an experiment run with --quick and without it writes into
                        <root>/results/quick instead: ``results_tree``)
    FREEZE2D_PAPER_OUT  what analysis writes for the paper: figures/, generated/, paper.pdf
                        (default <root>/paper, beside paper.typ, for the default results tree;
                        <results>/paper for any other, as the Makefile's QUICK=1 does:
                        ``paper_out``)
"""

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: whether FREEZE2D_RESULTS names the results tree (then every run, quick or full, writes there)
RESULTS_GIVEN = bool(os.environ.get("FREEZE2D_RESULTS"))
RESULTS = Path(os.environ.get("FREEZE2D_RESULTS") or ROOT / "results").resolve()
DATA = RESULTS / "data"  # experiments -> <name>.csv + <name>.json
RECORDINGS = RESULTS / "recordings"  # <scene>__<policy>.rrd
BENCH = RESULTS / "bench"  # raw timing logs
PAPER = ROOT / "paper"  # paper.typ, the source


def paper_out(results, given=None):
    """Where analysis writes for the paper: ``given`` (FREEZE2D_PAPER_OUT) if set, else beside
    paper.typ for the default results tree and ``<results>/paper`` for any other. (It was always
    beside paper.typ: ``FREEZE2D_RESULTS=results/quick python -m analysis.paper`` put the quick
    tree's figures and numbers into the full paper's folders.)"""
    if given:
        return Path(given).resolve()
    return PAPER if Path(results).resolve() == (ROOT / "results").resolve() else results / "paper"


PAPER_OUT = paper_out(RESULTS, os.environ.get("FREEZE2D_PAPER_OUT"))
FIGURES = PAPER_OUT / "figures"  # analysis -> <name>.svg
GENERATED = PAPER_OUT / "generated"  # analysis -> <name>.csv tables, <name>.json numbers
PDF = PAPER_OUT / "paper.pdf"


def results_tree(quick):
    """The results tree a run writes into (data/, partial/). A ``--quick`` run started by hand
    (``python -m experiments.<name> --quick``) gets its own RESULTS/quick, the tree `make
    reproduce QUICK=1` uses, so that it never replaces a full result in RESULTS/data, where make
    would take it for one; when FREEZE2D_RESULTS names the tree (the Makefile always does), that
    tree is used as it is."""
    return RESULTS / "quick" if quick and not RESULTS_GIVEN else RESULTS


def ensure(folder):
    """Create ``folder`` (and its parents) if missing; return it as a Path."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def _not_a_folder(folder):
    """The nearest existing ancestor of ``folder`` (itself included) if it is a file, else None."""
    for place in (folder, *folder.parents):
        if place.exists():
            return None if place.is_dir() else place
    return None


def creatable(folder):
    """``ensure(folder)``, or a ValueError saying in one line why it cannot be made (for command
    lines, which turn a ValueError into one line and exit status 2)."""
    folder = Path(folder)
    blocker = _not_a_folder(folder)
    if blocker is not None:
        raise ValueError(f"cannot make the folder {folder}: {blocker} is a file")
    try:
        return ensure(folder)
    except OSError as exc:
        raise ValueError(f"cannot make the folder {folder}: {exc.strerror or exc}") from None


def writable(path):
    """A ValueError, in one line, if the file ``path`` or its partial file (``partial_path``)
    cannot be written; checked before the work that writes it. Unchecked, analysis.trace given
    a folder as --out failed only at the final rename, after the whole run, and left its partial
    file behind; an unwritable place, or a file where a folder must be, came out as a traceback."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"cannot write {path}: it is a folder")
    creatable(path.parent)
    partial = partial_path(path)
    try:
        existed = partial.exists()  # (a name too long for the file system raises here)
        with open(partial, "ab"):
            pass
        if not existed:
            partial.unlink()
    except OSError as exc:
        raise ValueError(f"cannot write {path}: {exc.strerror or exc}") from None


def partial_path(path):
    """Where a file written in steps goes until it is whole (then renamed to ``path``): beside
    it, in the same folder (so the rename is atomic), ``<stem>.partial<suffix>``."""
    path = Path(path)
    return path.with_name(f"{path.stem}.partial{path.suffix}")
