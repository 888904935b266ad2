"""The marks of the extremes table (experiments/table_extremes.py, "Rules"): a run is stable,
degraded, failed, rejected or not run, by the thresholds here, given its measurement and its
reference's (study.extremes.record.Measurement)."""

#: the rules (see table_extremes' docstring)
EXPLOSION_FACTOR = 2.0  # KE > this x E_avail: failed
PENETRATION_REL = 0.10  # deeper than this fraction of the thinner body: degraded
DRIFT_REL = 0.01  # resting body moved more than this fraction of its width: degraded
ENERGY_GROWTH = 0.05  # energy created, fraction of E_avail: degraded
MAX_WAKES = 2  # a resting body woken more often: chattering (failed)
MAX_STATE_CHANGES = 3  # impact scene, one sim body: chattering above this

STATUSES = ("stable", "degraded", "failed", "rejected", "not run")


def classify(res, ref):
    """(status, reason) of one run (a Measurement) by the stated rules, given its reference's
    Measurement (or None)."""
    hint = res.status_hint
    if hint in ("rejected", "not run"):
        return hint, res.error
    failed, degraded = [], []
    if res.error:
        failed.append(f"error ({res.error[:120]})")
    if not res.finite:
        failed.append("non-finite")
    if res.exploded or (res.ke_max_rel > EXPLOSION_FACTOR):
        failed.append(f"explosion (KE {res.ke_max_rel:.3g} x E_avail)")
    if res.tunnelled:
        failed.append(f"tunnelling ({res.tunnelled})")
    if res.chattering:
        failed.append(f"chattering ({res.chattering})")
    if ref_valid(ref) and res.outcome and res.outcome != ref.outcome:
        failed.append(f"outcome {res.outcome} (reference {ref.outcome})")
    if res.penetration_rel > PENETRATION_REL:
        degraded.append(f"penetration {res.penetration_rel:.3g} x width")
    if res.drift_rel > DRIFT_REL:
        degraded.append(f"drift {res.drift_rel:.3g} x width")
    if res.energy_growth > ENERGY_GROWTH:
        degraded.append(f"energy growth {res.energy_growth:.3g} x E_avail")
    if failed:
        return "failed", "; ".join(failed + degraded)
    if degraded:
        return "degraded", "; ".join(degraded)
    return "stable", ""


def ref_valid(ref):
    """Whether a reference (a Measurement, or None) can judge outcomes: it ran, stayed finite and
    whole, and has an outcome."""
    return (
        ref is not None
        and ref.status_hint == ""
        and not ref.error
        and ref.finite
        and not ref.tunnelled
        and not ref.exploded
        and bool(ref.outcome)
    )


def chattering(task, res):
    """The chattering rule (table_extremes' docstring) for a run task (a dict) and its
    Measurement, as text, or ''."""
    kind = task["kind"]
    if kind not in ("rest", "impact") or res.status_hint:
        return ""
    why = []
    if res.wakes_max > MAX_WAKES:
        why.append(f"a body woken {res.wakes_max} times")
    if kind == "impact" and res.state_changes_max > MAX_STATE_CHANGES:
        why.append(f"a body changed state {res.state_changes_max} times")
    return ", ".join(why)
