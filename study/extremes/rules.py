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
    Measurement (or None).

    A run stopped by its time budget part way (``timed_out``) is "not run", unless a rule whose
    verdict no later step can take back had already failed it (``_lasting_failures``): then it is
    "failed", and the reason says it was before the timeout. Either way the reason says what the
    run had shown by then (its outcome is the pose at the timeout, not at the end)."""
    hint = res.status_hint
    if timed_out(res):
        lasting = _lasting_failures(res)
        if lasting:
            return "failed", "; ".join(lasting + _degradations(res)) + f" (before the {res.error})"
        seen = _outcome_failure(res, ref) + _degradations(res)
        return hint, res.error + ("; by then: " + "; ".join(seen) if seen else "")
    if hint in ("rejected", "not run"):
        return hint, res.error
    failed, degraded = _failures(res, ref), _degradations(res)
    if failed:
        return "failed", "; ".join(failed + degraded)
    if degraded:
        return "degraded", "; ".join(degraded)
    return "stable", ""


def timed_out(res):
    """Whether a run was stopped by its time budget after it had started stepping (runs.simulate
    marks it "not run" with the step it reached)."""
    return res.status_hint == "not run" and res.steps_done > 0


def _lasting_failures(res):
    """The failure rules' verdicts that a longer run cannot take back, each a running maximum or an
    event: a non-finite state (the run stops), an explosion (the largest KE seen), a passage through
    a body, chattering (a count of wakes). Not the error rule (a timeout is not the system's error)
    nor the outcome (judged on the last pose)."""
    lasting = []
    if not res.finite:
        lasting.append("non-finite")
    if res.exploded or (res.ke_max_rel > EXPLOSION_FACTOR):
        lasting.append(f"explosion (KE {res.ke_max_rel:.3g} x E_avail)")
    if res.tunnelled:
        lasting.append(f"tunnelling ({res.tunnelled})")
    if res.chattering:
        lasting.append(f"chattering ({res.chattering})")
    return lasting


def _failures(res, ref):
    """The failure rules' verdicts (reasons): the error, the lasting ones, the outcome."""
    failed = [f"error ({res.error[:120]})"] if res.error else []
    return failed + _lasting_failures(res) + _outcome_failure(res, ref)


def _outcome_failure(res, ref):
    """The outcome rule's verdict: an outcome other than a valid reference's, or none."""
    if ref_valid(ref) and res.outcome and res.outcome != ref.outcome:
        return [f"outcome {res.outcome} (reference {ref.outcome})"]
    return []


def _degradations(res):
    """The degrading rules' verdicts (reasons); each reads a running maximum."""
    degraded = []
    if res.penetration_rel > PENETRATION_REL:
        degraded.append(f"penetration {res.penetration_rel:.3g} x width")
    if res.drift_rel > DRIFT_REL:
        degraded.append(f"drift {res.drift_rel:.3g} x width")
    if res.energy_growth > ENERGY_GROWTH:
        degraded.append(f"energy growth {res.energy_growth:.3g} x E_avail")
    return degraded


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
    # a wake count only grows: a run stopped by its time budget is judged on what it counted
    if kind not in ("rest", "impact") or (res.status_hint and not timed_out(res)):
        return ""
    why = []
    if res.wakes_max > MAX_WAKES:
        why.append(f"a body woken {res.wakes_max} times")
    if kind == "impact" and res.state_changes_max > MAX_STATE_CHANGES:
        why.append(f"a body changed state {res.state_changes_max} times")
    return ", ".join(why)
