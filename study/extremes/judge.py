"""The judge of one extremes run (experiments/table_extremes.py, "Measured in every run"): fed
the runner's observables sample by sample, it keeps finiteness, energy growth, the deepest
overlap, the drift of the bodies that should rest, wakes, tunnelling (the projectile's path
through a body, or a body ending below the floor) and the outcome ("stands" / "collapsed",
"stopped" / "passed", "stays" / "falls left" / "falls right"), the same code for every system."""

import math

import numpy as np

from sim import SimulationError
from study.extremes.geometry import clip_to_box, deepest_overlap
from study.extremes.scenes import ARRIVAL_S

#: the outcome rules (table_extremes' docstring, "outcome")
STAND_MOVE = 0.5  # outcome "stands": no body moved more than this x its width ...
STAND_TURN = 0.2  # ... nor turned more than this, rad
KNIFE_TURN = 0.1  # knife edge "stays": turned less than this, rad


class Judge:
    """Everything measured on one run, sample by sample (experiments/table_extremes.py's
    docstring, "Measured in every run")."""

    def __init__(self, scene, shapes):
        p = scene.params
        self.kind = p["kind"]
        self.resting = np.array(p["resting"], dtype=int)
        self.projectile = p["projectile"]
        self.rest_pose = (
            None if p.get("rest_pose") is None else np.asarray(p["rest_pose"], dtype=float)
        )  # (N,2) m
        self.shapes = shapes
        self.start = None
        self.finite = True
        self.error = ""  # what a system said when it refused to hand out a non-finite state
        self.tunnelled = ""
        self.e_avail = math.nan
        self.energy_growth = 0.0
        self.ke_max = 0.0
        self.pen_m = self.pen_rel = 0.0
        self.drift_m = self.drift_rel = 0.0
        self.wakes = np.zeros(shapes.n, dtype=int)
        self.asleep = None
        self.local_before = {}  # projectile: its centre in each body's frame at the last sample
        self.entered = {}  # projectile: the face of each body its centre entered through
        self.asleep_before_event = math.nan
        self.last = None

    def sample(self, runner, time_s=None, overlap=True):
        try:
            pos, ang = runner.positions, runner.angles
            vel, angvel = runner.velocities, runner.angular_velocities
        except SimulationError as exc:  # a peer refuses to hand out a non-finite state
            self.finite, self.error = False, f"{type(exc).__name__}: {exc}"
            return False
        asleep = np.asarray(runner.asleep, dtype=bool)
        if not (
            np.isfinite(pos).all()
            and np.isfinite(ang).all()
            and np.isfinite(vel).all()
            and np.isfinite(angvel).all()
        ):
            self.finite = False
            return False
        self.last = (pos, ang)
        ke, pe = self.shapes.energy(pos, vel, angvel)
        if self.start is None:
            self.start = (pos, ang, ke + pe)
            self.e_avail = ke + pe
            self.asleep = asleep
        self.energy_growth = max(self.energy_growth, (ke + pe - self.start[2]) / self.e_avail)
        self.ke_max = max(self.ke_max, ke / self.e_avail)
        if overlap:
            d, r = deepest_overlap(self.shapes, pos, ang)
            self.pen_m = max(self.pen_m, d)
            self.pen_rel = max(self.pen_rel, r)
        if len(self.resting):
            moved = np.hypot(*(pos[self.resting] - self.start[0][self.resting]).T)
            self.drift_m = max(self.drift_m, float(moved.max()))
            self.drift_rel = max(
                self.drift_rel, float((moved / self.shapes.width[self.resting]).max())
            )
        self.wakes += self.asleep & ~asleep
        self.asleep = asleep
        if self.projectile is not None:
            self._crossing(pos, ang)
            others = [i for i in range(self.shapes.n) if i != self.projectile]
            if time_s is not None and time_s < ARRIVAL_S - 1e-9 and others:
                self.asleep_before_event = float(asleep[others].mean())
        return True

    def _crossing(self, pos, ang):
        """Tunnelling: the projectile's centre passes through a box-shaped body: it enters through
        one face and leaves through the opposite one, within a step or over several (its path
        from the last sample to this one, each end in the body's frame at that time, clipped to
        the body's rectangle). Pushed back out, or out of a side face, is not counted."""
        p = self.projectile
        targets = [(i, pos[i], ang[i], self.shapes.half[i]) for i in range(self.shapes.n) if i != p]
        targets += [
            (self.shapes.n + k, q, a, h)
            for k, ((q, a), h) in enumerate(zip(self.shapes.static_pose, self.shapes.static_half))
        ]
        for k, q, a, half in targets:
            c, s = math.cos(a), math.sin(a)
            dx, dy = pos[p] - q
            now = np.array([c * dx + s * dy, -s * dx + c * dy])  # m, in the body's frame
            before = self.local_before.get(k)
            self.local_before[k] = now
            if before is None or self.tunnelled:
                continue
            hit = clip_to_box(before, now, half)
            if hit is None:
                continue
            entry, exit_ = hit  # faces (axis, sign), None where not crossed
            if entry is None and exit_ is None:  # inside all along
                continue
            if entry is not None and exit_ is not None:  # in and out within this step
                through = entry[0] == exit_[0] and entry[1] != exit_[1]
                self.entered.pop(k, None)
            elif entry is not None:  # in: remember the face
                self.entered[k] = entry
                through = False
            else:  # out: through the face opposite the entry?
                came = self.entered.pop(k, None)
                through = came is not None and came[0] == exit_[0] and came[1] != exit_[1]
            if through:
                what = "the wall" if k >= self.shapes.n else f"body {k}"
                self.tunnelled = f"projectile passed through {what}"

    def through_floor(self):
        """Tunnelling through the floor: a body's centre below the floor at the last sample (a
        fast body's centre can dip under it for a step and come back: that is penetration)."""
        if self.last is None or self.shapes.floor_y is None:
            return ""
        under = np.flatnonzero(self.last[0][:, 1] < self.shapes.floor_y)
        return f"body {int(under[0])} ends below the floor" if len(under) else ""

    def outcome(self):
        if self.last is None:
            return ""
        pos, ang = self.last
        pos0, ang0 = self.start[0], self.start[1]
        moved = np.hypot(*(pos - pos0).T)
        turned = np.abs(np.angle(np.exp(1j * (ang - ang0))))
        if self.kind == "knife":
            if turned[0] < KNIFE_TURN:
                return "stays"
            return "falls left" if pos[0, 0] < pos0[0, 0] else "falls right"
        if self.kind == "pile":  # no known rest pose: not judged
            return ""
        if self.kind == "projectile" and len(self.shapes.statics):
            wall_x = self.shapes.static_pose[0][0][0]
            return "passed" if pos[self.projectile, 0] > wall_x else "stopped"
        if self.rest_pose is not None:  # bodies that land first: judged where they
            moved = np.hypot(*(pos - self.rest_pose).T)  # should come to rest
        keep = np.array([i for i in range(self.shapes.n) if i != self.projectile], dtype=int)
        ok = (moved[keep] <= STAND_MOVE * self.shapes.width[keep]).all() and (
            turned[keep] <= STAND_TURN
        ).all()
        return "stands" if ok else "collapsed"
