"""table_extremes' time budget: a run stopped part way is "not run" and says what it had shown by
then, unless a rule whose verdict no later step can take back had already failed it
(study.extremes.rules.classify; runs.simulate stops the run)."""

import numpy as np
import pytest

from experiments import table_extremes as T
from study.extremes import rules, runs
from study.extremes.record import Measurement


def _result(**kw):
    """A run that passed every rule, with ``kw`` changed."""
    base = {
        "finite": True,
        "exploded": False,
        "outcome": "stands",
        "energy_growth": 0.0,
        "ke_max_rel": 0.5,
        "penetration_rel": 0.01,
        "drift_rel": 0.001,
    }
    return Measurement(**{**base, **kw})


TIMEOUT = "timeout: 120 s of wall time reached at step 240 of 300"


def _timed_out(**kw):
    return _result(status_hint="not run", error=TIMEOUT, steps_done=240, **kw)


def test_a_run_stopped_by_its_budget_says_what_it_had_shown_by_then():
    """A timed-out run is "not run": its outcome is the pose at the timeout, not at the end, so a
    collapse by then is not a verdict; the reason says it, and the running maxima seen."""
    ref = _result()
    assert rules.classify(_timed_out(), ref) == ("not run", TIMEOUT)
    status, reason = rules.classify(_timed_out(outcome="collapsed", drift_rel=1.27), ref)
    assert status == "not run"
    assert reason == TIMEOUT + "; by then: outcome collapsed (reference stands); drift 1.27 x width"
    # a cell never started (a cost cap has no Measurement; a hint with no steps) is unchanged
    assert rules.classify(_result(status_hint="not run", error="cap"), ref) == ("not run", "cap")


@pytest.mark.parametrize(
    "lasting, words",
    [
        ({"finite": False}, "non-finite"),
        ({"ke_max_rel": 2.5}, "explosion (KE 2.5 x E_avail)"),
        ({"tunnelled": "projectile passed through body 2"}, "tunnelling (projectile passed"),
        ({"chattering": "a body woken 3 times"}, "chattering (a body woken 3 times)"),
    ],
)
def test_a_run_failed_for_good_before_its_budget_ran_out_is_failed(lasting, words):
    """A rule whose verdict no later step takes back (a running maximum or an event) fails a
    timed-out run, and the reason says it was before the timeout."""
    status, reason = rules.classify(_timed_out(drift_rel=0.5, **lasting), _result())
    assert status == "failed"
    assert reason.startswith(words) and "drift 0.5 x width" in reason
    assert reason.endswith(f"(before the {TIMEOUT})")


def test_a_timed_out_run_counts_its_wakes():
    task = {"kind": "rest"}
    assert rules.chattering(task, _timed_out(wakes_max=3)) == "a body woken 3 times"
    assert rules.chattering(task, _result(status_hint="rejected", wakes_max=3)) == ""


def test_a_run_past_its_budget_is_stopped_and_marked_not_run():
    """runs.simulate stops a run at the first sample past budget_s and marks it "not run" with the
    step it reached; the end-of-run floor check is not made (there was no end)."""
    task = runs.run_task("stack_height", 10, "sim-off", T.QUICK)
    out = runs.simulate({**task, "budget_s": 0.0})
    assert out.status_hint == "not run" and out.steps_done == task["sample_every"]
    reached = f"reached at step {out.steps_done} of {task['steps']}"
    assert out.error == f"timeout: 0 s of wall time {reached}"
    assert rules.classify(out, None) == ("not run", out.error)


def test_only_a_run_that_reached_its_end_is_judged_below_the_floor(monkeypatch):
    """Ending below the floor is judged on the last pose (a centre can dip under and come back):
    not made on a run stopped by its budget, which would otherwise be failed for good by it."""
    monkeypatch.setattr(runs.Judge, "through_floor", lambda self: "body 0 ends below the floor")
    task = {**runs.run_task("stack_height", 10, "sim-off", T.QUICK), "steps": 4, "sample_every": 2}
    assert runs.simulate(task).tunnelled == "body 0 ends below the floor"
    out = runs.simulate({**task, "budget_s": 0.0})
    assert out.status_hint == "not run" and out.tunnelled == ""
    assert rules.classify(out, None)[0] == "not run"


def test_a_peer_that_refuses_a_non_finite_state_fails_the_cell_with_its_words(monkeypatch):
    """A peer raises SimulationError as its state is read once it is non-finite
    (study.peers.guards): the run is failed as non-finite, in the peer's words, not stopped with
    a traceback (the judge reads the state; before, the peers handed out NaN)."""
    from sim import SimulationError
    from study.peers.pymunk_runner import PymunkRunner

    def refuse(self):
        if self.step_count:
            raise SimulationError(f"pymunk: body 0 is non-finite after step {self.step_count}")
        return np.zeros((self.scene.n_bodies, 2))

    monkeypatch.setattr(PymunkRunner, "velocities", property(refuse))
    task = {**runs.run_task("stack_height", 10, "pymunk", T.QUICK), "steps": 4, "sample_every": 2}
    out = runs.simulate(task)
    assert not out.finite and out.steps_done == 2
    assert out.error == "SimulationError: pymunk: body 0 is non-finite after step 2"
    status, reason = rules.classify(out, None)
    assert status == "failed" and "non-finite" in reason
