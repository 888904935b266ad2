"""The one dispatch point from the step loop to the freeze policies (compiled)."""
from ..jit import kernel
from ..layout import EXTENDED, PAPER, SLEEP
from . import sleep


@kernel
def update_freeze(policy, count, settings, bodies, geometry, contacts, activity):
    """Run the policy's per-step update after the step's positions are final: decide transitions,
    record events, freeze and wake bodies. ``count`` manifolds of this step are in ``contacts``."""
    if policy == SLEEP:
        sleep.update(count, settings, bodies, contacts, activity)
    elif policy == PAPER:
        pass
    elif policy == EXTENDED:
        pass
