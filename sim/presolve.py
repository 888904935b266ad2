"""The initial solve (``kernel.presolve``) as the World sets it up: how many sweeps it may spend,
and what it says when a large scene's default budget cuts it short.

The initial solve finds the contact impulses that hold the start pose (nothing moves), so that a
scene placed at rest starts in equilibrium instead of sagging while the soft contacts take up the
load. Its cost is sweeps times contacts, and Gauss-Seidel needs many sweeps on tall stacks (the
error falls by a factor ~1 - c / height^2 a sweep). Measured (2026-12-06; a sweep costs ~11 ns
per contact at 10^5 contacts, ~45 at 10^6, out of cache): a World of 10^6 unit boxes stacked 1000
high spent its 5000 default sweeps in 265 s of its 275 s set-up and had still not converged;
10^5 boxes stacked 100 high, 5000 sweeps in 11 s, not converged either. So the *default* count
is also held to ``WORK`` contact-sweeps in all (1-2 s), and a solve that this cut short and that
did not converge says so. A count the caller asks for is spent as asked.

Split from ``world.py`` by job: the facade builds and steps; this decides the solve's budget and
reports on it.
"""

import warnings

#: The solve stops when no contact's impulse changed by more than this fraction of the largest
#: over its last 10 sweeps.
TOLERANCE = 1e-6
#: Contact-sweeps the default solve may spend (10^6 contacts: 50 sweeps, ~2 s; 10^5: 500, under
#: 1 s). The study's largest initial solve, pyramid(60) of table_extremes (3600 contacts, all 5000
#: sweeps: it does not converge to TOLERANCE, nor do pyramid(40) and a 50-box column), is 1.8e7,
#: under it: no result of the study changes.
WORK = 5 * 10**7
#: The kernel sweeps in rounds of this many between its convergence tests.
ROUND = 10


def sweep_cap(requested, is_default, n_contacts):
    """Sweeps the solve may spend: ``requested`` (0: no solve), and for the default count at most
    WORK / n_contacts, in whole rounds, at least one round."""
    if not requested or not is_default or n_contacts <= 0:
        return requested
    affordable = max(ROUND, WORK // n_contacts // ROUND * ROUND)
    return min(requested, affordable)


def warn_if_cut(requested, cap, sweeps, converged, n_contacts):
    """A RuntimeWarning when the budget (``cap`` < ``requested``) cut the default solve short and
    it ended unconverged after ``sweeps`` sweeps over ``n_contacts`` contacts."""
    if cap >= requested or converged:
        return
    warnings.warn(
        f"the initial solve of this scene's {n_contacts} contacts stopped unconverged after "
        f"{sweeps} sweeps: the default spends at most {WORK:.0e} contact-sweeps (1-2 s; "
        f"sim.presolve.WORK), and tall stacks need many more. The start pose is not "
        f"held in equilibrium and settles in the first steps, as with initial_iterations=0. "
        f"Pass initial_iterations=N to spend N sweeps",
        RuntimeWarning,
        stacklevel=3,
    )
