"""Freeze policies behind one dispatch point (``dispatch.py``).

Each policy is a module with ``NAME`` and ``PARAMETERS`` (name -> default). ``resolve`` validates a
policy name and its parameters for ``sim.World``.
"""

import math
import numbers

import numpy as np

from ..arguments import number
from . import extended, off, paper, sleep

#: Every policy the study compares, in the order of the paper.
POLICY_NAMES = ("off", "sleep", "paper", "extended")
_IMPLEMENTED = {m.NAME: m for m in (off, sleep, paper, extended)}


def parameters_of(name):
    """The parameters (name -> default) of the implemented policy ``name``; {} for any other
    name (``resolve`` says what is wrong with it)."""
    policy = _IMPLEMENTED.get(name) if isinstance(name, str) else None
    return dict(policy.PARAMETERS) if policy is not None else {}


def renamed_in(name):
    """{old parameter name: what replaced it} of the implemented policy ``name`` (its RENAMED)."""
    policy = _IMPLEMENTED.get(name) if isinstance(name, str) else None
    return dict(getattr(policy, "RENAMED", {}))


def resolve(name, params):
    """Return (policy module, parameters with defaults filled in), or raise.

    ValueError for an unknown name or a parameter the policy does not take; NotImplementedError for
    a policy named in the study whose implementation has not landed yet.
    """
    if not isinstance(name, str) or name not in POLICY_NAMES:
        raise ValueError(f"unknown freeze policy {name!r}; choose one of {', '.join(POLICY_NAMES)}")
    if name not in _IMPLEMENTED:
        raise NotImplementedError(
            f"freeze={name!r} is not implemented yet (available: {', '.join(_IMPLEMENTED)})"
        )
    policy = _IMPLEMENTED[name]
    unknown = sorted(set(params) - set(policy.PARAMETERS))
    if unknown:
        takes = ", ".join(policy.PARAMETERS) or "no parameters"
        raise ValueError(f"freeze={name!r} does not take {', '.join(unknown)} (it takes {takes})")
    values = {**policy.PARAMETERS, **params}
    for key, value in values.items():
        integral = key in policy.INT_PARAMETERS
        if integral:
            # a count is an int, as the World's counts are (sim.arguments.count): 2.0 is refused
            # as a formula gone wrong, True as a switch; taken exactly (as a float, 2**62 - 1 was
            # 2**62 and 2**53 + 1 was 2**53); int64 in the step loop
            whole = isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))
            x = int(value) if whole else None
            bad = x is None or not 1 <= x < 2**62
        else:
            x = number(value, key)  # "0.1" is not taken as a number
            bad = not math.isfinite(x) or x < 0
        if bad:
            kind = "an integer >= 1 (and < 2**62)" if integral else "finite and >= 0"
            raise ValueError(f"{key} must be {kind}, got {value!r}")
        below = getattr(policy, "BELOW", {}).get(key)
        if below is not None and x >= below:
            raise ValueError(f"{key} must be below {below}, got {value!r}")
        values[key] = int(x) if integral else x
    return policy, values
