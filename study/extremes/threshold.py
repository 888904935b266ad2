"""The impulse threshold of the impact axis (experiments/table_extremes.py, ``impact_threshold``):
the throw-down speed v* of the hammer at which sim-paper's or sim-extended's impulse test flips,
found by bisection (``find_threshold``, an executor task), and the ``Decision`` watched in every
run of that axis."""

import math

import sim
from study.common import DT
from study.extremes.scenes import impact


class Decision:
    """Watches, step by step, the impulse test of sim-``policy`` in the impact scene: paper: is the
    hammer (body 1) left FREE at the step it first touches the anvil (not held: it "bounces by
    its impulse")? extended: is the frozen anvil (body 0) woken by an impact? ``crossed`` is
    None until decided."""

    def __init__(self, policy):
        self.policy = policy
        self.crossed = None

    def watch(self, world):
        if self.crossed is not None:
            return
        if self.policy == "extended":
            if any(b == 0 and cause == "impact" for _, b, _, _, cause in world.events):
                self.crossed = True
            return
        c = world.contacts()
        pair = ((c["body_a"] == 0) & (c["body_b"] == 1)) | ((c["body_a"] == 1) & (c["body_b"] == 0))
        if (pair & (c["end_separation"] <= c["slop"]) & (c["normal_impulse"] > 0)).any():
            self.crossed = bool(world.states[1] == sim.State.FREE)

    def finish(self):
        """After the run: extended's anvil never woken means not crossed."""
        if self.crossed is None and self.policy == "extended":
            self.crossed = False
        return self.crossed

    def label(self):
        crossed = self.finish()
        if crossed is None:
            return "hammer never touched"
        if self.policy == "paper":
            return "bounces" if crossed else "held"
        return "anvil woken" if crossed else "anvil stays frozen"


def impact_decision(policy, v0, steps):
    """Under sim-``policy``, does the hammer thrown down at v0 m/s cross the impulse test
    (Decision)? True / False, or None if the hammer never touched."""
    world = sim.World(impact(v0), dt=DT, freeze=policy)
    decision = Decision(policy)
    for _ in range(steps):
        world.step(1)
        decision.watch(world)
        if decision.crossed is not None:
            break
    return decision.finish()


def find_threshold(task):
    """Executor task: the v0 (m/s) at which the policy's impact decision flips, by bisection
    (v0 in [0, 20] m/s; the decision must be False at 0 and True at 20)."""
    policy, steps, n_bisect = task["policy"], task["steps"], task["bisection_steps"]
    lo, hi = 0.0, 20.0
    at_lo, at_hi = impact_decision(policy, lo, steps), impact_decision(policy, hi, steps)
    if at_lo is not False or at_hi is not True:
        return {
            "policy": policy,
            "v_star": math.nan,
            "bracket": [lo, hi],
            "note": f"no crossing in [{lo}, {hi}] m/s (decision {at_lo} at {lo}, {at_hi} at {hi})",
        }
    for _ in range(n_bisect):
        mid = 0.5 * (lo + hi)
        if impact_decision(policy, mid, steps):
            hi = mid
        else:
            lo = mid
    return {
        "policy": policy,
        "v_star": 0.5 * (lo + hi),
        "bracket": [lo, hi],
        "note": "hammer bounces above v*" if policy == "paper" else "anvil wakes above v*",
    }
