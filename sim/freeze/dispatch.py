"""The one dispatch point from the step loop to the freeze policies (compiled).

Each policy has two hooks: ``before_solve`` (after collision detection: wake bodies that this
step's contacts disturb, so the collision is solved with them moving; returns how many woke) and
``after_solve`` (positions final: decide transitions, record events, freeze bodies). Both take
(settings, counters, bodies, contacts, activity) and walk this step's active contacts,
``contacts.active[:counters[N_ACTIVE]]``."""

from ..jit import inline_kernel
from . import extended, paper, sleep
from .codes import EXTENDED, PAPER, SLEEP


@inline_kernel
def freeze_before_solve(settings, counters, bodies, contacts, activity):
    policy = settings.policy
    if policy == SLEEP:
        return sleep.before_solve(settings, counters, bodies, contacts, activity)
    if policy == EXTENDED:
        return extended.before_solve(settings, counters, bodies, contacts, activity)
    if policy == PAPER:
        return paper.before_solve(settings, counters, bodies, contacts, activity)
    return 0


@inline_kernel
def freeze_after_solve(settings, counters, bodies, contacts, activity):
    policy = settings.policy
    if policy == SLEEP:
        sleep.after_solve(settings, counters, bodies, contacts, activity)
    elif policy == EXTENDED:
        extended.after_solve(settings, counters, bodies, contacts, activity)
    elif policy == PAPER:
        paper.after_solve(settings, counters, bodies, contacts, activity)
