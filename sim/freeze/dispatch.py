"""The one dispatch point from the step loop to the freeze policies (compiled).

Each policy has two hooks: ``before_solve`` (after collision detection: wake bodies that this
step's contacts disturb, so the collision is solved with them moving; returns how many woke) and
``after_solve`` (positions final: decide transitions, record events, freeze bodies)."""
from ..jit import kernel
from ..layout import EXTENDED, PAPER, SLEEP
from . import extended, paper, sleep


@kernel
def freeze_before_solve(policy, count, settings, bodies, contacts, activity):
    if policy == SLEEP:
        return sleep.before_solve(count, settings, bodies, contacts, activity)
    if policy == EXTENDED:
        return extended.before_solve(count, settings, bodies, contacts, activity)
    if policy == PAPER:
        return paper.before_solve(count, settings, bodies, contacts, activity)
    return 0


@kernel
def freeze_after_solve(policy, count, settings, bodies, contacts, activity):
    if policy == SLEEP:
        sleep.after_solve(count, settings, bodies, contacts, activity)
    elif policy == EXTENDED:
        extended.after_solve(count, settings, bodies, contacts, activity)
    elif policy == PAPER:
        paper.after_solve(count, settings, bodies, contacts, activity)
