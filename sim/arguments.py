"""Checks of settings given as arguments (a World's, a runner's): each returns the value
normalised or raises ValueError naming the argument.

One rule for every engine: a number is a number, not text (``float("0.01")`` would take
``dt="0.01"``, and ``"12"`` unpacks to a pair), and a switch is a bool (``bool("no")`` is True).
Body and Scene fields have their own checks (``sim.body``), which also name the body."""

import copy
import math
import numbers

import numpy as np

MAX_FLOAT = float(np.finfo(np.float64).max)  # the largest finite float (Python float: an
# int compares with it exactly, where a numpy float converts the int first and overflows)


def number(value, what):
    """``value`` as a float; ValueError for text, bools and what float() refuses."""
    if isinstance(value, (str, bytes, bool, np.bool_)):
        raise ValueError(f"{what} must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be a number, got {value!r}") from None
    except OverflowError:  # an int beyond float's range (10**400)
        raise ValueError(f"{what} must be finite, got {value!r}") from None


def positive(value, what, allow_zero=False):
    """A finite float > 0 (or >= 0 with ``allow_zero``)."""
    x = number(value, what)
    if not math.isfinite(x) or x < 0.0 or (x == 0.0 and not allow_zero):
        raise ValueError(
            f"{what} must be {'>= 0' if allow_zero else '> 0'} and finite, got {value!r}"
        )
    return x


def count(value, what, minimum, maximum=None, why=""):
    """An int >= ``minimum`` (and <= ``maximum``, refused with ``why``): a float such as 2.0 is
    refused too, since a count given as a float is usually a formula gone wrong."""
    if (
        isinstance(value, (bool, np.bool_))
        or not isinstance(value, numbers.Integral)
        or value < minimum
    ):
        raise ValueError(f"{what} must be an integer >= {minimum}, got {value!r}")
    if maximum is not None and value > maximum:
        raise ValueError(
            f"{what} must be at most {maximum:,}, got {value!r}" + (f": {why}" if why else "")
        )
    return int(value)


def flag(value, what):
    """A switch: True or False (numpy's bool too), nothing else."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{what} must be True or False, got {value!r}")
    return bool(value)


def numeric_array(value):
    """Is ``value`` (an array, or nested sequences) made of real numbers: integers or floats,
    not text, switches (bools), complex numbers or other objects? float64 conversion takes all
    of those ("2" becomes 2.0, True 1.0), so a check of types must come first. A switch among
    numbers in a list is looked for item by item: numpy reads [True, 2.5] as a float array."""
    try:
        kind = np.asarray(value).dtype.kind
    except (TypeError, ValueError):
        return False
    return kind in "iuf" and not holds_switch(value)


def kind_of(value):
    """What a value refused by ``numeric_array`` holds, for the message: "a switch (True or
    False)" when one hides among numbers, else "<dtype> values"."""
    if holds_switch(value):
        return "a switch (True or False)"
    return f"{np.asarray(value).dtype} values"  # (ragged sequences raise: the caller's message)


def holds_switch(value):
    """Does ``value`` (a number, an array, or nested lists and tuples) hold a bool anywhere?"""
    if isinstance(value, (bool, np.bool_)):
        return True
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "b":
            return True
        return value.dtype.kind == "O" and any(holds_switch(x) for x in value.ravel())
    if isinstance(value, (list, tuple)):
        return any(holds_switch(x) for x in value)
    return False


def beyond_float(value):
    """Does ``value`` (a number, an array, or nested sequences) hold an integer too large for a
    float (10**400)? numpy then keeps Python objects, and float64 conversion raises a bare
    OverflowError: callers name the field instead."""
    try:
        items = np.asarray(value, dtype=object).ravel()
    except (TypeError, ValueError):
        return False
    return any(
        isinstance(x, numbers.Integral) and not isinstance(x, bool) and abs(x) > MAX_FLOAT
        for x in items
    )


def plain_copy(value, what):
    """A deep copy of ``value``, a record of what built something (a Scene's params: it goes into
    results files), or ValueError naming ``what``: a lock, a file or a generator in it failed
    later, as a TypeError about pickling from deep inside World()."""
    try:
        return copy.deepcopy(value)
    except Exception as exc:  # whatever deepcopy refuses, in whatever words
        raise ValueError(
            f"{what} must be plain data that can be copied (numbers, text, lists, dicts); "
            f"deepcopy refused it: {type(exc).__name__}: {exc}"
        ) from None
