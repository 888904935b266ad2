"""Freeze policies behind one dispatch point (DESIGN section 3).

Each policy is a module with ``NAME`` and ``PARAMETERS`` (name -> default). ``resolve`` validates a
policy name and its parameters for ``sim.World``.
"""
from . import off

#: Every policy the study compares, in the order of the paper.
POLICY_NAMES = ("off", "sleep", "paper", "extended")
_IMPLEMENTED = {off.NAME: off}


def resolve(name, params):
    """Return (policy module, parameters with defaults filled in), or raise.

    ValueError for an unknown name or a parameter the policy does not take; NotImplementedError for
    a policy named in the study whose implementation has not landed yet.
    """
    if not isinstance(name, str) or name not in POLICY_NAMES:
        raise ValueError(f"unknown freeze policy {name!r}; choose one of {', '.join(POLICY_NAMES)}")
    if name not in _IMPLEMENTED:
        raise NotImplementedError(f"freeze={name!r} is not implemented yet (only 'off' is)")
    policy = _IMPLEMENTED[name]
    unknown = sorted(set(params) - set(policy.PARAMETERS))
    if unknown:
        takes = ", ".join(policy.PARAMETERS) or "no parameters"
        raise ValueError(f"freeze={name!r} does not take {', '.join(unknown)} (it takes {takes})")
    return policy, {**policy.PARAMETERS, **params}
