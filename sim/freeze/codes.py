"""Policy codes: the index of each policy in ``sim.freeze.POLICY_NAMES`` (``settings.policy``)."""

OFF, SLEEP, PAPER, EXTENDED = range(4)
