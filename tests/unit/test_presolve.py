"""The initial solve's budget (``sim.presolve``): the default count is held to ``WORK``
contact-sweeps, a count the caller asks for is spent as asked, and a default solve the budget
cut short, unconverged, says so; ``World.inspect()`` reports the sweeps and the convergence."""

import warnings

import pytest

import sim
from sim import presolve
from sim.scenes import rest_row
from study.extremes import scenes


def test_the_budget_holds_only_the_default_count():
    cap = presolve.sweep_cap
    assert cap(5000, True, presolve.WORK // 1000) == 1000  # the budget binds
    assert cap(5000, True, 10) == 5000  # a small scene: the count binds
    assert cap(5000, False, presolve.WORK) == 5000  # asked for: spent as asked
    assert cap(0, True, 10**9) == 0  # no solve stays none
    assert cap(5000, True, 10**12) == presolve.ROUND  # at least one round
    assert cap(5000, True, presolve.WORK // 1234) == 1230  # in whole rounds


def _column(budget, monkeypatch, **kw):
    # a 50-box column: its default solve needs all 5000 sweeps (it does not converge to the
    # tolerance in them), so a small budget cuts it short
    monkeypatch.setattr(presolve, "WORK", budget)
    return sim.World(scenes.column(50), **kw)


def test_a_default_solve_the_budget_cuts_short_warns(monkeypatch):
    with pytest.warns(RuntimeWarning, match=r"50 contacts stopped unconverged after 100 sweeps"):
        w = _column(5000, monkeypatch)
    report = w.inspect()
    assert report.presolve_sweeps == 100
    assert not report.presolve_converged


def test_a_count_asked_for_is_spent_as_asked_and_says_nothing(monkeypatch):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        w = _column(5000, monkeypatch, initial_iterations=300)
    assert w.inspect().presolve_sweeps == 300  # not the budget's 100
    # a count that is not a whole number of rounds is what it says
    assert _column(5000, monkeypatch, initial_iterations=15).inspect().presolve_sweeps == 15


def test_a_converged_solve_says_so_and_nothing_else():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        report = sim.World(rest_row(10)).inspect()
    assert report.presolve_converged
    assert 0 < report.presolve_sweeps < 5000


def test_no_solve_reports_none():
    report = sim.World(rest_row(3), initial_iterations=0).inspect()
    assert report.presolve_sweeps == 0
    assert not report.presolve_converged
