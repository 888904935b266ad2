"""Every path the study uses, derived from the repository root in this one place.

``FREEZE2D_RESULTS`` (environment variable) moves the whole results tree, e.g. into a temporary
folder for tests or onto a scratch disk; it is read once, at import.
"""
import os
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = Path(os.environ.get("FREEZE2D_RESULTS") or ROOT / "results").resolve()
DATA = RESULTS / "data"                  # experiments -> <name>.csv + <name>.json
RECORDINGS = RESULTS / "recordings"      # <scene>__<policy>.rrd
BENCH = RESULTS / "bench"                # raw timing logs
PAPER = ROOT / "paper"
FIGURES = PAPER / "figures"              # analysis -> <name>.svg
GENERATED = PAPER / "generated"          # analysis -> <name>.csv tables read by the paper


def ensure(folder):
    """Create ``folder`` (and its parents) if missing; return it as a Path."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return folder
