"""Every path the study uses, derived from the repository root in this one place.

Two environment variables move the outputs, read once, at import (the Makefile sets both for
``make reproduce QUICK=1`` so that quick results never overwrite full ones; tests point them into
temporary folders):

    FREEZE2D_RESULTS    the results tree: data/, recordings/         (default <root>/results)
    FREEZE2D_PAPER_OUT  what analysis writes for the paper: figures/, generated/, paper.pdf
                        (default <root>/paper, beside paper.typ)
"""

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = Path(os.environ.get("FREEZE2D_RESULTS") or ROOT / "results").resolve()
DATA = RESULTS / "data"  # experiments -> <name>.csv + <name>.json
RECORDINGS = RESULTS / "recordings"  # <scene>__<policy>.rrd
BENCH = RESULTS / "bench"  # raw timing logs
PAPER = ROOT / "paper"  # paper.typ, the source
PAPER_OUT = Path(os.environ.get("FREEZE2D_PAPER_OUT") or PAPER).resolve()
FIGURES = PAPER_OUT / "figures"  # analysis -> <name>.svg
GENERATED = PAPER_OUT / "generated"  # analysis -> <name>.csv tables, <name>.json numbers
PDF = PAPER_OUT / "paper.pdf"


def ensure(folder):
    """Create ``folder`` (and its parents) if missing; return it as a Path."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return folder
