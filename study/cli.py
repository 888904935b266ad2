"""What every script's command line shares: its --help description and its counts. Kept apart
from ``study.common`` (which builds runners, and so imports every engine) so that analysis, which
never simulates, can use it too."""

import argparse


def first_paragraph(doc):
    """A module docstring's first paragraph on one line: a script's --help description (its
    first line alone stopped mid-sentence)."""
    return " ".join(doc.strip().split("\n\n")[0].split())


def positive_int(text):
    """The argparse type of a count (--repeats, --steps): an integer >= 1. A default is the
    option left out (None), never 0, which ``args.x or default`` had silently taken for it."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {value}")
    return value


def or_default(value, default):
    """An option's value, or ``default`` when it was left out (None; 0 is refused by
    ``positive_int``, never taken for the default)."""
    return default if value is None else value
