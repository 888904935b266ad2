"""The certificate's small linear feasibility test (``sim.freeze.feasibility``) against the slow
reference (``naive.nnls``: A x = b has a solution x >= 0 exactly when the non-negative least
squares residual is zero)."""

import numpy as np
import pytest

import naive
from sim.freeze.feasibility import MAX_COLUMNS, MAX_ROWS, PRICING, solvable


def _system(rng, rows, cols, feasible):
    a = rng.normal(size=(rows, cols))
    if feasible:
        x = rng.uniform(0.0, 1.0, cols) * (rng.uniform(size=cols) < 0.4)  # sparse, >= 0
        return a, a @ x
    return a, rng.normal(size=rows)


@pytest.mark.parametrize("pricing", PRICING)
@pytest.mark.parametrize("seed", range(6))
def test_solvable_agrees_with_non_negative_least_squares(seed, pricing):
    rng = np.random.default_rng(seed)
    answers = []
    for _ in range(200):
        # up to a group of 4 bodies (12 equations); seed 5: 4 to 12 bodies, as a pile's groups
        if seed == 5:
            rows = int(rng.integers(12, 37))
            cols = int(rng.integers(rows, 2 * rows))
        else:
            rows = int(rng.integers(1, 13))
            cols = int(rng.integers(1, 25))
        a, b = _system(rng, rows, cols, feasible=bool(rng.integers(2)))
        ok, left = solvable(a, b, pricing)
        _, residual = naive.nnls(a.T, b)
        scale = max(np.abs(b).sum(), 1e-300)
        if residual / scale < 1e-10:
            assert ok, (rows, cols, left)
        elif residual / scale > 1e-6:
            assert not ok, (rows, cols, residual / scale)
        answers.append(ok)
    assert 40 < sum(answers) < 160  # both answers are exercised


@pytest.mark.parametrize("pricing", PRICING)
def test_degenerate_systems(pricing):
    # repeated columns, zero rows and a zero right-hand side: the pivots Bland's rule exists for
    a = np.array([[1.0, 1.0, 0.0, -1.0], [0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 1.0, 0.0]])
    assert solvable(a, np.zeros(3), pricing)[0]
    assert solvable(a, np.array([1.0, 0.0, 2.0]), pricing)[0]
    assert not solvable(a, np.array([1.0, 1.0, 2.0]), pricing)[0]  # the zero row cannot make 1
    assert not solvable(np.array([[1.0, 2.0]]), np.array([-1.0]), pricing)[0]  # x >= 0


def _beale(top):
    """Beale's cycling example (1955) as a phase one: rows 1-2 hold with zero slack at the start
    (degenerate), and row 4 makes the phase-one reduced costs Beale's objective (-3/4, 20,
    -1/2, 6): Dantzig's rule alone pivots round a cycle there and never lowers the sum.
    Columns x4 x5 x6 x7 and two slacks; solvable exactly when ``top`` <= 1/4."""
    a = np.array(
        [
            [0.25, -8.0, -1.0, 9.0, 1.0, 0.0],
            [0.5, -12.0, -0.5, 3.0, 0.0, 1.0],
            [0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, -18.0, -1.0, -1.0],
        ]
    )
    return a, np.array([0.0, 0.0, 1.0, top])


def test_dantzig_hands_over_to_bland_where_it_would_cycle():
    a, b = _beale(0.2)
    x = np.array([14 / 15, 0.0, 1.0, 0.0, 23 / 30, 1 / 30])  # a solution (x4, x6, s1, s2)
    assert np.allclose(a @ x, b) and (x >= 0).all()
    # without the hand-over the sum stayed at 1 (the cycle never left the start) and the
    # system was called unsolvable (measured 2026-12-08)
    assert solvable(a, b) == (True, pytest.approx(0.0, abs=1e-12))
    assert solvable(a, b, pricing="bland")[0]
    ok, left = solvable(*_beale(0.3))
    assert not ok and left == pytest.approx(1.0 / 26.0)  # the same answer as Bland's
    assert solvable(*_beale(0.3), pricing="bland")[1] == pytest.approx(left)


def test_a_box_held_by_two_walls_by_friction_alone():
    # A box of weight 1 squeezed between two vertical walls: each wall pushes with a force in its
    # friction cone (normal 1, friction +-mu); held when 2 mu N can carry the weight for some N.
    def system(mu):
        # columns: the left wall's two cone edges, then the right wall's; rows: x, y
        a = np.array([[1.0, 1.0, -1.0, -1.0], [mu, -mu, mu, -mu]])
        return a, np.array([0.0, 1.0])

    assert solvable(*system(0.3))[0]
    assert not solvable(*system(0.0))[0]


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="must be"):
        solvable(np.zeros((2, 2)), np.zeros(3))
    with pytest.raises(ValueError, match="finite"):
        solvable(np.array([[np.nan]]), np.zeros(1))
    with pytest.raises(ValueError, match="at most"):
        solvable(np.zeros((MAX_ROWS + 1, 2)), np.zeros(MAX_ROWS + 1))
    with pytest.raises(ValueError, match="at most"):
        solvable(np.zeros((2, MAX_COLUMNS + 1)), np.zeros(2))
    with pytest.raises(ValueError, match="pricing must be one of"):
        solvable(np.zeros((2, 2)), np.zeros(2), pricing="steepest")
