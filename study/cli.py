"""What every script's command line shares: its --help description and its counts. Kept apart
from ``study.common`` (which builds runners, and so imports every engine) so that analysis, which
never simulates, can use it too."""

import argparse
import math


def first_paragraph(doc):
    """A module docstring's first paragraph on one line: a script's --help description (its
    first line alone stopped mid-sentence)."""
    return " ".join(doc.strip().split("\n\n")[0].split())


def positive_int(text):
    """The argparse type of a count (--repeats, --steps): an integer >= 1. A default is the
    option left out (None), never 0, which ``args.x or default`` had silently taken for it."""
    value = _parsed(text, int, "an integer")
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {value}")
    return value


def positive_float(text):
    """The argparse type of a scale (analysis.trace's --arrow-scale): a finite number > 0.
    ``float`` alone took "nan" (no arrows drawn) and negatives (arrows reversed) silently."""
    value = _parsed(text, float, "a number")
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
    return value


def _parsed(text, kind, what):
    """``kind(text)``, or the argparse error naming ``what`` it is not (one line, status 2)."""
    try:
        return kind(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not {what}: {text!r}") from None


def or_default(value, default):
    """An option's value, or ``default`` when it was left out (None; 0 is refused by
    ``positive_int``, never taken for the default)."""
    return default if value is None else value
