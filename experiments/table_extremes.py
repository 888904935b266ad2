"""Table "table_extremes" (figure "fig_extremes"): numerical stability at the extremes.

Question: where does each system (sim under every freeze policy, pymunk and pybullet with sleeping
off and on) stop giving a usable answer when one thing at a time is pushed to an extreme, and is
freezing ever the thing that breaks it? Every run is marked stable / degraded / failed / rejected
/ not run by the rules below; the figure is a grid of those marks, rows = (axis, value), columns =
systems.

Axes (each row one value; values listed from benign to extreme; every scene starts at rest with
its bodies exactly touching unless said otherwise; unit boxes, density 1 kg/m^2, friction 0.6):
- ``mass_heavy_on_light`` / ``mass_light_on_heavy``: a column of 3 unit boxes whose top box is
  m_top/m_below = 1, 10, 100, 1000 (resp. 1, 1/10, 1/100, 1/1000) times as heavy as the two below
  (its density scaled). 3 s.
- ``mass_dropped``: the heavy-on-light column *dropped* (each box DROP_GAP = 0.1 m above the one
  below, as the ``dt`` axis's column), m_top/m_below = 1, 10, 100, 1000: the solver must build the
  column and then carry the load, with no presolved start to lean on (see ``dt``). Judged against
  the stacked pose. 3 s.
- ``size_small`` / ``size_large``: a column of 3 square boxes of side 1, 0.1, 0.01 m and, past the
  issue's 1 cm, 1 mm and 0.1 mm; resp. 1, 10, 100 m. Same gravity (9.81 m/s^2) and the same
  solver settings passed to every size (sim's slop 5 mm and speculative distance 2 cm, pymunk's
  collision_slop 5 mm). pymunk's slop stays absolute; sim takes its settings as caps and scales
  its tolerances down with the smaller body's size (``sim.tolerances``), and refuses a body too
  small for its step with a ValueError naming the substeps (or dt) that would resolve it: at dt
  1/60 s and 4 substeps, 1 mm boxes need substeps >= 11 and 0.1 mm boxes >= 34, so both are
  refused ("rejected" cells, not failures). 3 s.
- ``plank_flat``: a plank 2 m long and 2/a m thick (aspect a = 1, 3, 10, 30, 100; mass held at
  1 kg by its density, so only the shape changes) lying centred across a unit box. 3 s.
- ``plank_upright``: a plank 1 m tall and 1/a m wide (a = 1, 3, 10, 30, 100) standing on its end
  on the floor (stable: it tips only past atan(1/a)). 3 s.
- ``polygon_vertices``: a regular n-gon (n = 3, 4, 8, 16, 32, 64; circumradius 0.5 m) resting on
  its flat bottom edge on a unit box. 3 s.
- ``collinear``: a unit box whose bottom edge has a fifth vertex eps below its midpoint (eps = 1e-2,
  1e-4, 1e-6, 1e-9 m: nearly collinear edges, and the box starts balanced on that vertex, able to
  rock by 2 eps rad onto either half), with a unit box resting on it. 3 s.
- ``projectile_stack``: a 0.2 m box projectile (density 1) fired horizontally at 10, 30, 100,
  200 m/s into the middle of box 2 of a 5-box column. It starts v T m away (T = 2.5 s + half a
  step of 1/60 s: at dt 1/60 it is then half a step's travel short of touching at the end of a
  step, not exactly touching, a lucky phase that would hide tunnelling) on a ballistic arc that
  returns to the aim height at t = T (vertical speed g T / 2), so every system has had 2.5 s to
  freeze the column before it arrives (Bullet needs its fixed 2 s); the fraction of the column
  asleep just before arrival is recorded. sim sweeps fast bodies against static and frozen ones
  (continuous collision, ``sim.continuous``) and makes contacts ahead of fast approaching pairs;
  pymunk has no continuous collision and pybullet's (swept-sphere CCD) is not switched on by its
  runner. 3 s.
- ``projectile_wall``: the same projectile at a static wall 5 cm thick and 4 m tall. 3 s.
- ``dt``: a *dropped* column of 10 unit boxes, each starting 0.1 m above the one below (the lowest
  0.1 m above the floor): they fall together and land one on another, the lowest at ~1.4 m/s and
  the top one, having fallen 1 m in all, at ~4.4 m/s, so the solver builds the column rather than
  being handed it in equilibrium (sim solves a scene placed at rest to convergence before its
  first step, ``initial_iterations``: a placed column stands in sim at any dt, which would measure
  that presolve, not the step). Judged against the stacked pose. dt = 1/480 .. 1/15 s (every other
  axis runs at 1/60 s). 5 s.
- ``iterations``: the same dropped column with 50, 20, 10, 5, 2, 1 iterations of each engine's own
  solver setting (elsewhere each engine's default, experiments.peers.DEFAULT_ITERATIONS). The
  numbers are not the same work: pymunk and pybullet do that many sweeps per step; sim does that
  many biased sweeps *per substep*, at its default 4 substeps (plus 1 relaxing sweep per substep),
  so its value 1, the axis's extreme, is sim's default and does 4 biased sweeps per step. The
  ``iterations`` and ``substeps`` columns of each row say exactly what ran. 5 s.
- ``substeps`` (sim only: the knob soft step trades for accuracy, Box2D v3's; pymunk and pybullet
  have none, their nearest knob is the ``dt`` axis): the same dropped column at 16, 8, 4, 2, 1
  substeps per step of 1/60 s, 1 iteration per substep. No peer row (not applicable, rather than
  "not run"), and no "breaks first" is drawn from it (nothing to compare with). 5 s.
- ``stack_height``: a column of 10, 20, 50 unit boxes placed at rest (sim starts it in
  equilibrium, see ``dt``; the peers do not: see the no-presolve systems below). 5 s.
- ``pyramid_base``: sim.scenes.pyramid(base) for base 10, 20, 40, 60 (55 .. 1830 bodies). 5 s.
- ``bodies``: 10^4 bodies as 2000 five-box columns 1.5 m apart. 2 s.
- ``long_run``: a 3-box column for 10^5 steps (1667 s at 1/60): drift and energy over a long rest.
- ``impact_threshold``: a 0.5 m box (density 0.3: 0.075 kg) "hammer" HAMMER_GAP = 2 m above a
  unit-box "anvil" on the floor, thrown down at v0 = v* (1 + d), d = -1e-3, -1e-6, +1e-6, +1e-3.
  v* is found by bisection (45 halvings of [0, 20] m/s: ~1e-13 relative; through the executor) as
  the v0 at which the policy's impulse test flips: under sim-paper, whether the hammer is held on
  landing on the anvil's (rotation-stable, floor-like) top edge or bounces (impulse_threshold
  1 N s); under sim-extended, whether the impact wakes the frozen anvil (impulse_threshold
  0.5 N s). The other systems have no such test: they get sim-paper's v*. The question is whether
  a decision on a knife's edge makes states chatter. 2 s.
- ``knife_edge``: a unit box balanced on one corner with its centre of mass offset from exactly
  above the corner by a tilt of 1e-3, 1e-6, 1e-9 and 0 rad (0 = exact balance, an unstable
  equilibrium that only round-off breaks; with an offset the box must fall to that side: a tilt
  grows as cosh(3.2 t) here, from 1e-9 rad it falls in ~7 s). 10 s.

Systems: sim-off, sim-sleep, sim-paper, sim-extended (default policy parameters), pymunk,
pymunk-sleep, pybullet, pybullet-sleep (experiments.common.SYSTEMS; sim slop and pymunk
collision_slop 5 mm; each engine's default iterations, sim's default substeps), plus, on the
placed axes only (PLACED_AXES: the scenes that start with bodies resting on one another, where
sim's presolve puts them in equilibrium before step 1: mass_heavy_on_light, mass_light_on_heavy,
size_small, size_large, plank_flat, plank_upright, polygon_vertices, collinear, projectile_stack,
stack_height, pyramid_base, bodies, long_run), the four sim systems again with the presolve off
(``World(initial_iterations=0)``), named "sim-off (no presolve)" etc. (NO_PRESOLVE_SYSTEMS). The
peers have no presolve: an advantage only sim has is reported separately, so that sim without it
can be compared with them like for like (the analysis does both). Not placed, so not repeated: the
dropped columns (``dt``, ``iterations``, ``substeps``, ``mass_dropped``: nothing touches at the
start), the projectile into a wall (likewise), and the impact and knife-edge scenes (one body on
the floor by a face or a corner: the presolve only sets the first step's floor impulse).

pybullet is not run on scenes of more than ``pybullet_max_bodies`` = 250 bodies (pyramid 40 and
60, 10^4 bodies): measured on this machine, a pybullet step of pyramid(20) costs 58 ms, of
pyramid(40) 0.68 s, of pyramid(60) 5.3 s; those cells are marked "not run" with the reason, never
dropped. Any run is stopped after ``budget_s`` s of wall time and marked "not run" (timeout).

Reference (for the outcome): the same scene under sim-off at dt_ref = min(dt, 1/60) / ``fine``
(fine = 8; 32 for the projectiles, so that a 200 m/s projectile moves 0.1 m per step, less than
the 0.25 m it needs to cross the wall: the reference cannot tunnel even without the continuous
collision that the runs test) with sim's default REF_SUBSTEPS = 4 substeps and REF_ITERATIONS = 1
biased sweep per substep, presolve on, for the same simulated time; one run per distinct scene,
shared by all systems (and by the no-presolve runs: the reference is the best estimate of what the
scene does, and a scene placed at rest starts in equilibrium). Why: in soft step the substep is
the accuracy knob (a substep re-integrates positions and re-solves every contact from the new
separation; an extra iteration only re-sweeps the same linearisation), so a reference 8x finer in
dt is 8x the runs' substeps: 32 per 1/60 s. The old reference's 40 iterations were per *step* of a
solver without substeps; 40 per substep at dt/8 would be 1280 biased sweeps per 1/60 s, which is
not what was meant, and costs for nothing: checked when chosen, 4x the substeps (16), 4x finer dt
(fine 32) or 40 iterations per substep leave the outcome of every scene tried unchanged (dropped
10-box column, placed and dropped 1000:1 stacks, 100:1 dropped stack, knife edge 1e-6 rad, upright
plank 100:1; final poses within 3 cm, 8 cm for the dropped 1000:1 stack). A scene sim refuses at
that step (a body too small for it, e.g. 0.1 mm boxes at dt 1/480 s) gets its reference with the
substeps doubled until the World accepts it (the reference's ``substeps`` are in the metadata).
Shortcuts, both stated: the 10^4-body scene's reference is one five-box column (its columns never
touch: identical, independent systems), and the long run's reference lasts 60 s of simulated time
(a column placed at rest stands or falls within seconds; what the long run is about, drift and
energy over 10^5 steps, is measured in the run itself).

Measured in every run (from each system's own observables, by the same code for all; sampled
after every step for the projectile, impact and knife-edge scenes, else at ~``samples`` = 200
evenly spaced steps, fewer for big scenes: at most ``sample_budget`` = 20000 body-samples per run
and at least 10 samples, so a 10^4-body run is sampled 10 times and its penetration and wakes
are those seen at the samples):
- finite: every position, angle, velocity and angular velocity finite; a sim.SimulationError or
  any exception while stepping is recorded as the error;
- energy: E = kinetic + potential (m |g| (y - floor_y)); E_avail = E at the start = the most any
  motion can release. energy_growth = max(E(t) - E(0)) / E_avail; ke_max_rel = max KE(t) / E_avail;
- penetration: the deepest overlap at a sample (separating-axis test on the convex polygons, pairs
  from a sweep over bounding boxes, floor included), divided by the smaller of the two bodies'
  thinnest widths: penetration_rel; the metres too;
- drift: the largest displacement of a body that should rest (every body of the rest scenes, the
  anvil of the impact scene) from its start, divided by that body's thinnest width: drift_rel;
- tunnelling: a body's centre below the floor at the end of the run, or (projectile scenes,
  checked every step) the projectile's centre passing through a body: entering it through one
  face and leaving through the opposite face, within one step or over several (its path between
  samples clipped to the body's rectangle; pushed back out, or out of a side face, is not
  counted);
- outcome: rest, impact and projectile_stack scenes: "stands" if no (non-projectile) body moved
  more than half its thinnest width nor turned more than 0.2 rad, else "collapsed";
  projectile_wall: "stopped" / "passed" (projectile's final x before / beyond the wall);
  knife_edge: "stays" (turned less than 0.1 rad) / "falls left" / "falls right";
- wakes: the most times one body went from asleep to awake (the runners' ``asleep``) between
  samples; for sim also state_changes, the most state changes of one body in ``World.events``
  (equal-state events excluded);
- ms_per_step: wall time of the steps (the first step excluded, sampling excluded) over their
  count. Measured inside each run while other runs share the machine (a process pool): indicative
  only; the study's speed figures come from its serial benchmarks (bench_step, bench_freeze).

Rules (a run gets the worst mark any rule gives; reasons are listed in ``reason``):
- failed: an error raised while stepping; a non-finite state; explosion (KE > 2 E_avail at any
  sample: energy that no motion of the scene can release); tunnelling; chattering (a body woken
  more than 2 times in a rest or impact scene, or, in the impact scene, a sim body changing state
  more than 3 times: landing, being held, waking once and re-freezing take at most 3); or an outcome
  different from the reference's (skipped, with a note, when the reference itself is not valid:
  error, refused, non-finite or tunnelled);
- degraded: finite, same outcome, but penetration_rel > 0.10 (an overlap deeper than a tenth of
  the thinner body), drift_rel > 0.01 (a resting body moved more than 1 % of its thinnest width),
  or energy_growth > 0.05 (5 % of the available energy created);
- stable: otherwise;
- rejected: refused with a clear error: the scene or the settings were refused with a ValueError
  before the first step, recorded with its message (e.g. sim's "body 0 is 0.001 m thick ... Use
  substeps >= 11"). Not a result and not a failure of physics: the system said it cannot do this,
  rather than doing it wrong; the analysis lists these cells apart and never counts them as
  breaking;
- not run: cost cap or timeout.

Columns: axis, value, unit, system, scene, bodies, dt_s, iterations, substeps, steps, status,
reason, outcome, ref_outcome, ref_valid, error, finite, exploded, tunnelled, chattering,
energy_growth, ke_max_rel, penetration_max_m, penetration_rel, drift_max_m, drift_rel, wakes_max,
state_changes_max, asleep_before_event, decision, ms_per_step, steps_done, wall_s. ``iterations``
is the run's solver iterations as the runner reports them (sim: per substep); ``substeps`` sim's
substeps per step (empty for the peers). ``<name>.json`` holds the thresholds v* and the
reference runs.

Every untimed run goes through experiments.executor.run_tasks with an incremental store
(results/partial/table_extremes[-quick].jsonl): an interrupted sweep resumes where it stopped; the
store is removed once the CSV is written.

    python -m experiments.table_extremes [--quick]
writes results/data/table_extremes.csv and table_extremes.json. --quick: one or two values per
axis (the extreme ones), short runs (1 s; the projectiles 3 s, the knife edge 4 s), small sizes,
coarser references (fine 4, projectiles 8).
"""
import json
import math
import time

import numpy as np
import pandas as pd

import sim
from experiments import common
from experiments.common import DT, SYSTEMS, build
from experiments.executor import run_tasks
from experiments.peers import DEFAULT_ITERATIONS, engine_of
from experiments.overlap import pad as _pad, separation as _separation, world_vertices as _world
from sim.geometry import mass_properties

NAME = "table_extremes"
G = 9.81                       # m/s^2, |gravity| of every scene
FRICTION = 0.6
#: the reference's solver (module docstring, "Reference"): sim.World's defaults, written out so
#: that the reference is fixed here and never moves with a runner's or the World's defaults
REF_SUBSTEPS = 4               # substeps per reference step (doubled for a scene refused at it)
REF_ITERATIONS = 1             # biased solve sweeps per substep
REF_MAX_SUBSTEPS = 4096        # give up doubling here (the reference is then "rejected")
#: the sim systems again with the presolve off (module docstring, "Systems")
NO_PRESOLVE = " (no presolve)"
NO_PRESOLVE_SETTINGS = {"initial_iterations": 0}
NO_PRESOLVE_SYSTEMS = tuple(s + NO_PRESOLVE for s in SYSTEMS if engine_of(s) == "sim")
ALL_SYSTEMS = SYSTEMS + NO_PRESOLVE_SYSTEMS
#: the axes whose scenes start with bodies resting on one another (or on the floor), where sim's
#: presolve starts them in equilibrium: also run without it
PLACED_AXES = ("mass_heavy_on_light", "mass_light_on_heavy", "size_small", "size_large",
               "plank_flat", "plank_upright", "polygon_vertices", "collinear",
               "projectile_stack", "stack_height", "pyramid_base", "bodies", "long_run")
#: the axes of a knob only sim has: no peer row, no "breaks first"
SIM_ONLY_AXES = ("substeps",)
PROJECTILE_SIZE = 0.2          # m, side of the projectile box
#: s, the projectile's flight time to first touching its target: 2.5 s plus half a step at 1/60 s,
#: so that at dt 1/60 it is half a step's travel short of its target at a step's end (arriving
#: exactly at a step's end would be a lucky phase that hides tunnelling in some engines and not
#: in others)
ARRIVAL_S = 2.5 + 0.5 * DT
WALL = (0.05, 4.0)             # m, thin static wall: thickness, height
HAMMER = 0.5                   # m, side of the impact scene's falling box ...
HAMMER_DENSITY = 0.3           # kg/m^2 (0.075 kg: from rest it lands under both thresholds)
HAMMER_GAP = 2.0               # m, its starting height above the anvil, so that it arrives
                               # after extended has frozen the anvil (2 steps) even thrown at
                               # 20 m/s, the top of the bisection (6 steps); at 0.5 m it arrived
                               # in step 2, racing the freeze, once contacts were made ahead of
                               # fast bodies (solver v2)
COLUMN_PITCH = 1.5             # m, between the five-box columns of the 10^4-body scene
DROP_GAP = 0.1                 # m, between the boxes of the dropped column (dt, iterations axes)

#: the rules (see the module docstring)
EXPLOSION_FACTOR = 2.0         # KE > this x E_avail: failed
PENETRATION_REL = 0.10         # deeper than this fraction of the thinner body: degraded
DRIFT_REL = 0.01               # resting body moved more than this fraction of its width: degraded
ENERGY_GROWTH = 0.05           # energy created, fraction of E_avail: degraded
MAX_WAKES = 2                  # a resting body woken more often: chattering (failed)
MAX_STATE_CHANGES = 3          # impact scene, one sim body: chattering above this
STAND_MOVE = 0.5               # outcome "stands": no body moved more than this x its width ...
STAND_TURN = 0.2               # ... nor turned more than this, rad
KNIFE_TURN = 0.1               # knife edge "stays": turned less than this, rad

STATUSES = ("stable", "degraded", "failed", "rejected", "not run")

#: axis -> unit, scene kind, values (benign to extreme) in FULL and QUICK, simulated seconds
AXES = {
    "mass_heavy_on_light": ("m_top/m_below", [1, 10, 100, 1000], [1000]),
    "mass_light_on_heavy": ("m_top/m_below", [1, 0.1, 0.01, 0.001], [0.001]),
    "mass_dropped": ("m_top/m_below", [1, 10, 100, 1000], [1000]),
    "size_small": ("m", [1.0, 0.1, 0.01, 1e-3, 1e-4], [1.0, 0.01]),
    "size_large": ("m", [1.0, 10.0, 100.0], [100.0]),
    "plank_flat": ("aspect", [1, 3, 10, 30, 100], [1, 100]),
    "plank_upright": ("aspect", [1, 3, 10, 30, 100], [100]),
    "polygon_vertices": ("vertices", [3, 4, 8, 16, 32, 64], [3, 64]),
    "collinear": ("m", [1e-2, 1e-4, 1e-6, 1e-9], [1e-9]),
    "projectile_stack": ("m/s", [10, 30, 100, 200], [200]),
    "projectile_wall": ("m/s", [10, 30, 100, 200], [200]),
    "dt": ("s", [1 / 480, 1 / 240, 1 / 120, 1 / 60, 1 / 30, 1 / 15], [1 / 15]),
    "iterations": ("iterations", [50, 20, 10, 5, 2, 1], [1]),
    "substeps": ("substeps", [16, 8, 4, 2, 1], [1]),
    "stack_height": ("boxes", [10, 20, 50], [20]),
    "pyramid_base": ("boxes", [10, 20, 40, 60], [5]),
    "bodies": ("bodies", [10000], [100]),
    "long_run": ("steps", [100000], [3000]),
    "impact_threshold": ("v0/v* - 1", [-1e-3, -1e-6, 1e-6, 1e-3], [-1e-6, 1e-6]),
    "knife_edge": ("rad", [1e-3, 1e-6, 1e-9, 0.0], [1e-6, 0.0]),
}
#: simulated seconds per axis (long_run: its value is the step count)
DURATION_S = {"dt": 5.0, "iterations": 5.0, "substeps": 5.0, "stack_height": 5.0,
              "pyramid_base": 5.0, "bodies": 2.0, "impact_threshold": 2.0, "knife_edge": 10.0}
DEFAULT_DURATION_S = 3.0



def applies(axis, system):
    """Whether ``system`` (one of ALL_SYSTEMS) has a cell on ``axis``: the no-presolve systems
    only on PLACED_AXES, the sim-only axes only for sim. Elsewhere the cell is not applicable,
    which is not "not run": there is nothing to run."""
    base = runner_system(system)
    if axis in SIM_ONLY_AXES and engine_of(base) != "sim":
        return False
    return system == base or axis in PLACED_AXES


def runner_system(system):
    """The runner's system name of one of ALL_SYSTEMS ("sim-off (no presolve)" -> "sim-off")."""
    return system[:-len(NO_PRESOLVE)] if system.endswith(NO_PRESOLVE) else system


def system_settings(system):
    """The runner settings that make ``system`` what it is, beyond its runner's name."""
    return dict(NO_PRESOLVE_SETTINGS) if system.endswith(NO_PRESOLVE) else {}


FULL = {
    "axes": {axis: values for axis, (_, values, _) in AXES.items()},
    "duration_s": {axis: DURATION_S.get(axis, DEFAULT_DURATION_S) for axis in AXES},
    "fine": 8, "fine_projectile": 32, "long_run_reference_s": 60.0,
    "samples": 200, "sample_budget": 20000, "budget_s": 120.0, "pybullet_max_bodies": 250,
    "bisection_steps": 45,
}
QUICK = {
    "axes": {axis: quick for axis, (_, _, quick) in AXES.items()},
    "duration_s": {axis: (3.0 if axis.startswith("projectile") else
                          4.0 if axis == "knife_edge" else 1.0) for axis in AXES},
    "fine": 4, "fine_projectile": 8, "long_run_reference_s": 5.0,
    "samples": 50, "sample_budget": 20000, "budget_s": 20.0, "pybullet_max_bodies": 250,
    "bisection_steps": 45,
}


# ---- scenes ------------------------------------------------------------------------------------
def _box(w, h, x, y, **kw):
    return sim.Body.box(w, h, position=(x, y), friction=FRICTION, **kw)


def _scene(name, bodies, params, kind, resting=None, projectile=None, rest_pose=None,
           **kwargs):
    """A scene whose params record how it is judged: kind (rest | impact | projectile |
    knife), the bodies that should rest where they start (drift), the projectile's index, and
    where the bodies should come to rest (``rest_pose``, [[x, y], ...] m; None: where they
    start)."""
    n = len(bodies)
    params = {**params, "kind": kind,
              "resting": list(range(n)) if resting is None else list(resting),
              "projectile": projectile, "rest_pose": rest_pose}
    return sim.Scene(bodies=bodies, name=name, params=params, **kwargs)


def _require(ok, message):
    """Scene builders refuse out-of-range parameters with a ValueError (never garbage)."""
    if not ok:
        raise ValueError(message)


def _positive(x, what):
    _require(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)
             and x > 0, f"{what} must be a finite number > 0, got {x!r}")
    return float(x)


def mass_stack(ratio):
    """Column of 3 unit boxes; the top one ``ratio`` times as heavy as each below."""
    ratio = _positive(ratio, "mass ratio")
    bodies = [_box(1, 1, 0, 0.5), _box(1, 1, 0, 1.5), _box(1, 1, 0, 2.5, density=float(ratio))]
    return _scene("mass_stack", bodies, {"ratio": ratio}, "rest")


def size_stack(size):
    """Column of 3 square boxes of side ``size`` m."""
    scene = sim.scenes.stack(3, size=float(size), friction=FRICTION)
    return _scene("size_stack", scene.bodies, {"size": size}, "rest")


def plank_flat(aspect):
    """A 2 m plank of thickness 2/aspect, mass 1 kg, centred across a unit box."""
    t = 2.0 / _positive(aspect, "aspect")
    bodies = [_box(1, 1, 0, 0.5), _box(2.0, t, 0, 1.0 + t / 2, density=1.0 / (2.0 * t))]
    return _scene("plank_flat", bodies, {"aspect": aspect, "length": 2.0, "thickness": t}, "rest")


def plank_upright(aspect):
    """A plank 1 m tall and 1/aspect wide standing on its end on the floor."""
    bodies = [_box(1.0 / _positive(aspect, "aspect"), 1.0, 0, 0.5)]
    return _scene("plank_upright", bodies, {"aspect": aspect, "height": 1.0}, "rest")


def polygon_on_box(n):
    """A regular n-gon (circumradius 0.5 m) on its flat bottom edge on a unit box."""
    _require(isinstance(n, int) and not isinstance(n, bool) and n >= 3,
             f"a regular polygon needs an integer number of vertices >= 3, got {n!r}")
    r = 0.5
    poly = sim.Body.regular(n, r, friction=FRICTION)
    apothem = r * math.cos(math.pi / n)       # centre to the flat bottom edge
    poly.position = (0.0, 1.0 + apothem)
    bodies = [_box(1, 1, 0, 0.5), poly]
    return _scene("polygon_on_box", bodies, {"n": n, "radius": r}, "rest")


def collinear_box(eps):
    """A unit box whose bottom edge bulges by a vertex ``eps`` m below its midpoint (it starts
    balanced on that vertex), carrying a unit box."""
    eps = _positive(eps, "eps")
    v = [(-0.5, -0.5), (0.0, -0.5 - eps), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
    low = sim.Body(vertices=v, friction=FRICTION)
    c = low.centroid
    low = sim.Body(vertices=np.asarray(v) - c, position=(float(c[0]), 0.5 + eps + float(c[1])),
                   friction=FRICTION)
    bodies = [low, _box(1, 1, 0, 1.5 + eps)]
    return _scene("collinear_box", bodies, {"eps": eps}, "rest")


def _projectile(speed, aim_x, aim_y, arrival_s=ARRIVAL_S):
    """The projectile box, arrival_s s and speed*arrival_s m left of (aim_x, aim_y), on the arc
    that brings it back to aim_y at t = arrival_s."""
    speed = _positive(speed, "projectile speed")
    arrival_s = _positive(arrival_s, "arrival time")
    x0 = aim_x - PROJECTILE_SIZE / 2 - speed * arrival_s
    return sim.Body.box(PROJECTILE_SIZE, PROJECTILE_SIZE, position=(x0, aim_y),
                        velocity=(float(speed), G * arrival_s / 2), friction=FRICTION,
                        name="projectile")


def projectile_stack(speed):
    """A 5-box column and a projectile arriving at the middle of box 2 after ARRIVAL_S s."""
    bodies = list(sim.scenes.stack(5, friction=FRICTION).bodies)
    bodies.append(_projectile(speed, -0.5, 2.5))
    return _scene("projectile_stack", bodies, {"speed": speed, "arrival_s": ARRIVAL_S},
                  "projectile", resting=[], projectile=len(bodies) - 1)


def projectile_wall(speed, arrival_s=ARRIVAL_S):
    """A thin static wall and a projectile arriving at its middle after ``arrival_s`` s (the
    table: ARRIVAL_S; the regression tests vary the phase of its arrival within a step)."""
    t, h = WALL
    wall = sim.Body.box(t, h, position=(0.0, h / 2), friction=FRICTION, name="wall")
    bodies = [_projectile(speed, -t / 2, h / 2, arrival_s)]
    return _scene("projectile_wall", bodies, {"speed": speed, "arrival_s": arrival_s,
                                              "wall": list(WALL)},
                  "projectile", resting=[], projectile=0, static_bodies=[wall])


def column(height):
    scene = sim.scenes.stack(int(height), friction=FRICTION)
    return _scene("stack", scene.bodies, {"height": height}, "rest")


def dropped_column(height, gap=DROP_GAP):
    """``height`` unit boxes in a column, each ``gap`` m above the one below (the lowest ``gap``
    above the floor): they fall together and land one on another (box k, counted from 0 at the
    bottom, has fallen (k + 1) gap when it lands: with 0.1 m gaps the lowest lands at 1.4 m/s,
    the tenth at 4.4 m/s), so the column is built by the solver, not placed in equilibrium.
    Judged against the stacked pose."""
    bodies = [_box(1, 1, 0, 0.5 + k * (1.0 + gap) + gap) for k in range(int(height))]
    rest = [[0.0, 0.5 + k] for k in range(int(height))]
    return _scene("dropped_column", bodies, {"height": height, "gap": gap}, "rest", resting=[],
                  rest_pose=rest)


def dropped_mass_stack(ratio, gap=DROP_GAP):
    """mass_stack(ratio) dropped: 3 unit boxes, each ``gap`` m above the one below (the lowest
    ``gap`` above the floor), the top one ``ratio`` times as heavy as each below. The heavy box
    lands last (at ~2.4 m/s from 0.1 m gaps) on a column the solver has just built, with no
    presolved start. Judged against the stacked pose."""
    ratio = _positive(ratio, "mass ratio")
    bodies = [_box(1, 1, 0, 0.5 + k * (1.0 + gap) + gap, density=ratio if k == 2 else 1.0)
              for k in range(3)]
    rest = [[0.0, 0.5 + k] for k in range(3)]
    return _scene("dropped_mass_stack", bodies, {"ratio": ratio, "gap": gap}, "rest",
                  resting=[], rest_pose=rest)


def pile_drop(n=30, columns=10, height=35.0, size=0.5, seed=0):
    """``n`` boxes of side ``size`` m released from rest ``height`` m up (the lowest row; rows
    0.8 m apart, ``columns`` boxes per row 0.8 m apart, each jittered by up to 5 cm and 0.2 rad,
    from ``seed``) into a bin: the floor between two static walls 6 m tall. They land at
    ~26 m/s, row on row: the fast-pile case of the regression tests (not an axis of the table:
    where a pile comes to rest is not known in advance, so the outcome rule cannot judge it; its
    penetration can be)."""
    _require(isinstance(n, int) and n >= 1 and isinstance(columns, int) and columns >= 1,
             f"pile_drop needs integer n >= 1 and columns >= 1, got {n!r}, {columns!r}")
    height, size = _positive(height, "height"), _positive(size, "size")
    pitch = 0.8 * size / 0.5                       # m, between box centres (0.8 m at 0.5 m)
    rng = np.random.default_rng(seed)
    bodies = []
    for k in range(n):
        row, col = divmod(k, columns)
        x = (col - (columns - 1) / 2) * pitch + rng.uniform(-0.05, 0.05) * size / 0.5
        bodies.append(_box(size, size, x, height + row * pitch,
                           angle=float(rng.uniform(-0.2, 0.2))))
    inner = columns * pitch                        # m, the bin's inner width
    walls = [sim.Body.box(0.5, 6.0, position=(side * (inner / 2 + 0.25), 3.0), friction=FRICTION,
                          name="wall") for side in (-1, 1)]
    return _scene("pile_drop", bodies, {"n": n, "columns": columns, "height": height,
                                        "size": size, "seed": seed}, "pile", resting=[],
                  static_bodies=walls)


def pyramid(base):
    scene = sim.scenes.pyramid(int(base), friction=FRICTION)
    return _scene("pyramid", scene.bodies, {"base": base}, "rest")


def columns(n, height=5):
    """n bodies as n/height columns of ``height`` unit boxes, COLUMN_PITCH m apart."""
    if n % height:
        raise ValueError(f"columns: n={n} is not a multiple of the column height {height}")
    bodies = [_box(1, 1, c * COLUMN_PITCH, 0.5 + k) for c in range(n // height)
              for k in range(height)]
    return _scene("columns", bodies, {"n": n, "height": height, "pitch": COLUMN_PITCH}, "rest")


def impact(v0):
    """The hammer (HAMMER m box, density HAMMER_DENSITY) HAMMER_GAP m above the anvil (a unit
    box on the floor), thrown down at v0 m/s. Only the anvil must rest (drift)."""
    _require(isinstance(v0, (int, float)) and math.isfinite(v0) and v0 >= 0,
             f"v0 must be a finite speed >= 0 m/s, got {v0!r}")
    anvil = _box(1, 1, 0, 0.5, name="anvil")
    hammer = sim.Body.box(HAMMER, HAMMER, position=(0.0, 1.0 + HAMMER_GAP + HAMMER / 2),
                          velocity=(0.0, -float(v0)), density=HAMMER_DENSITY, friction=FRICTION,
                          name="hammer")
    return _scene("impact", [anvil, hammer], {"v0": v0, "gap": HAMMER_GAP}, "impact",
                  resting=[0], rest_pose=[[0.0, 0.5], [0.0, 1.0 + HAMMER / 2]])


def knife_edge(tilt):
    """A unit box on one corner, rotated 45 deg + ``tilt`` rad, the corner touching the floor."""
    _require(isinstance(tilt, (int, float)) and math.isfinite(tilt) and abs(tilt) < math.pi / 4,
             f"tilt must be finite and within +-pi/4 rad, got {tilt!r}")
    angle = math.pi / 4 + tilt
    lowest = -0.5 * math.sin(angle) - 0.5 * math.cos(angle)   # corner (-0.5, -0.5), rotated
    x_corner = -0.5 * math.cos(angle) + 0.5 * math.sin(angle)
    body = sim.Body.box(1, 1, position=(-x_corner, -lowest), angle=angle, friction=FRICTION)
    return _scene("knife_edge", [body], {"tilt": tilt}, "knife", resting=[])


BUILDERS = {f.__name__: f for f in (mass_stack, size_stack, plank_flat, plank_upright,
                                    polygon_on_box, collinear_box, projectile_stack,
                                    projectile_wall, column, dropped_column,
                                    dropped_mass_stack, pile_drop, pyramid, columns, impact,
                                    knife_edge)}


def make_scene(spec):
    """spec = {"builder": name, "args": [...]} -> sim.Scene."""
    if spec["builder"] not in BUILDERS:
        raise ValueError(f"unknown scene builder {spec['builder']!r}")
    return BUILDERS[spec["builder"]](*spec["args"])


def scene_spec(axis, value):
    """The scene of one row (the dt, iterations, substeps and long_run axes vary the run, not the
    scene)."""
    by_axis = {
        "mass_heavy_on_light": ("mass_stack", value), "mass_light_on_heavy": ("mass_stack", value),
        "mass_dropped": ("dropped_mass_stack", value),
        "size_small": ("size_stack", value), "size_large": ("size_stack", value),
        "plank_flat": ("plank_flat", value), "plank_upright": ("plank_upright", value),
        "polygon_vertices": ("polygon_on_box", value), "collinear": ("collinear_box", value),
        "projectile_stack": ("projectile_stack", value),
        "projectile_wall": ("projectile_wall", value),
        "dt": ("dropped_column", 10), "iterations": ("dropped_column", 10),
        "substeps": ("dropped_column", 10),
        "stack_height": ("column", value),
        "pyramid_base": ("pyramid", value), "bodies": ("columns", value),
        "long_run": ("column", 3), "knife_edge": ("knife_edge", value),
    }
    builder, arg = by_axis[axis]
    return {"builder": builder, "args": [arg]}


# ---- measuring ---------------------------------------------------------------------------------
class Shapes:
    """The scene's polygons about their centres of mass (padded to one vertex count by repeating
    the last vertex: a zero-length edge, skipped), masses, moments, thinnest widths, statics."""

    def __init__(self, scene):
        bodies = list(scene.bodies)
        self.n = len(bodies)
        k = max(len(b.vertices) for b in bodies + list(scene.static_bodies))
        self.local = np.empty((self.n, k, 2))          # (N,K,2) m, body frame about the COM
        self.mass = np.empty(self.n)                   # (N,) kg
        self.inertia = np.empty(self.n)                # (N,) kg m^2
        self.width = np.empty(self.n)                  # (N,) m, thinnest width
        self.half = np.empty((self.n, 2))              # (N,2) m, half extents in the body frame
        for i, b in enumerate(bodies):
            m, c, inertia = mass_properties(b.vertices, b.density)
            v = np.asarray(b.vertices, dtype=float) - c
            self.local[i] = _pad(v, k)
            self.mass[i], self.inertia[i] = m, inertia
            self.width[i] = thinnest_width(v)
            self.half[i] = np.abs(v).max(axis=0)
        statics = list(scene.static_bodies)
        self.statics = np.array([_pad(_world(b), k) for b in statics]).reshape(len(statics), k, 2)
        self.static_width = np.array([thinnest_width(b.vertices) for b in statics])
        self.static_pose = [(np.asarray(b.position, float), b.angle) for b in statics]
        self.static_half = np.array([np.abs(np.asarray(b.vertices, float)).max(axis=0)
                                     for b in statics]).reshape(len(statics), 2)
        self.floor_y = scene.floor_y
        self.g = float(np.hypot(*scene.gravity))

    def world(self, positions, angles):
        """(N,K,2) m world vertices at this pose."""
        c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
        x, y = self.local[..., 0], self.local[..., 1]
        return np.stack([c * x - s * y, s * x + c * y], axis=-1) + np.asarray(positions)[:, None]

    def energy(self, positions, velocities, angular_velocities):
        """(kinetic, potential relative to the floor) J."""
        ke = 0.5 * float(self.mass @ np.einsum("ij,ij->i", velocities, velocities)
                         + self.inertia @ (angular_velocities ** 2))
        floor = 0.0 if self.floor_y is None else self.floor_y
        pe = self.g * float(self.mass @ (positions[:, 1] - floor))
        return ke, pe


def thinnest_width(vertices):
    """m: the smallest extent of a convex polygon across any of its edge directions (the width)."""
    v = np.asarray(vertices, dtype=float)
    e = np.roll(v, -1, axis=0) - v
    length = np.hypot(e[:, 0], e[:, 1])
    keep = length > 0
    n = np.stack([e[keep, 1], -e[keep, 0]], axis=1) / length[keep, None]
    proj = n @ v.T                                      # (E, K)
    return float((proj.max(axis=1) - proj.min(axis=1)).min())


def clip_to_box(a, b, half):
    """The segment a -> b (m, (2,) each) against the rectangle |x| < half[0], |y| < half[1]
    (Liang-Barsky): None if it misses the rectangle's interior, else (entry face, exit face),
    each (axis, sign) of the face crossed within the segment, or None where the segment starts
    (entry) or ends (exit) inside."""
    t_in, t_out = 0.0, 1.0
    face_in = face_out = None
    d = b - a
    for axis in (0, 1):
        h = half[axis]
        if d[axis] == 0.0:
            if abs(a[axis]) >= h:
                return None
            continue
        t1, t2 = (-h - a[axis]) / d[axis], (h - a[axis]) / d[axis]
        near, far = (t1, t2) if t1 < t2 else (t2, t1)
        sign_near = -1 if d[axis] > 0 else 1           # moving +: enters through the - face
        if near > t_in:
            t_in, face_in = near, (axis, sign_near)
        if far < t_out:
            t_out, face_out = far, (axis, -sign_near)
    if t_in >= t_out:
        return None
    return face_in, face_out


def deepest_overlap(shapes, positions, angles):
    """(deepest overlap m, deepest overlap / thinner width) at this pose, over body pairs (found
    by a sweep over x-sorted bounding boxes), body-static pairs and bodies against the floor."""
    w = shapes.world(positions, angles)
    width = shapes.width
    depth, rel = 0.0, 0.0
    if shapes.floor_y is not None:
        below = shapes.floor_y - w[..., 1].min(axis=1)       # (N,) m
        depth, rel = max(depth, float(below.max())), max(rel, float((below / width).max()))
    polys = np.concatenate([w, shapes.statics]) if len(shapes.statics) else w
    widths = np.concatenate([width, shapes.static_width]) if len(shapes.statics) else width
    n_dyn = len(w)
    lo, hi = polys.min(axis=1), polys.max(axis=1)            # (M,2)
    order = np.argsort(lo[:, 0], kind="stable")
    lo_s, hi_s = lo[order], hi[order]
    # in x-sorted order, body k's candidates are k+1 .. last[k]-1 (their min x <= its max x)
    last = np.searchsorted(lo_s[:, 0], hi_s[:, 0], side="right")
    count = np.maximum(last - np.arange(len(order)) - 1, 0)
    if count.sum():
        first = np.repeat(np.arange(len(order)), count)
        offset = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        second = first + 1 + offset
        i, j = order[first], order[second]
        ok = (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1]) & ((i < n_dyn) | (j < n_dyn))
        i, j = i[ok], j[ok]
        if len(i):
            sep = np.maximum(_separation(polys[i], polys[j]), _separation(polys[j], polys[i]))
            over = np.maximum(-sep, 0.0)
            depth = max(depth, float(over.max()))
            rel = max(rel, float((over / np.minimum(widths[i], widths[j])).max()))
    return max(depth, 0.0), max(rel, 0.0)


class Judge:
    """Everything measured on one run, sample by sample (see the module docstring)."""

    def __init__(self, scene, shapes):
        p = scene.params
        self.kind = p["kind"]
        self.resting = np.array(p["resting"], dtype=int)
        self.projectile = p["projectile"]
        self.rest_pose = (None if p.get("rest_pose") is None else
                          np.asarray(p["rest_pose"], dtype=float))      # (N,2) m
        self.shapes = shapes
        self.start = None
        self.finite = True
        self.tunnelled = ""
        self.e_avail = math.nan
        self.energy_growth = 0.0
        self.ke_max = 0.0
        self.pen_m = self.pen_rel = 0.0
        self.drift_m = self.drift_rel = 0.0
        self.wakes = np.zeros(shapes.n, dtype=int)
        self.asleep = None
        self.local_before = {}   # projectile: its centre in each body's frame at the last sample
        self.entered = {}        # projectile: the face of each body its centre entered through
        self.asleep_before_event = math.nan
        self.last = None

    def sample(self, runner, time_s=None, overlap=True):
        pos, ang = runner.positions, runner.angles
        vel, angvel = runner.velocities, runner.angular_velocities
        asleep = np.asarray(runner.asleep, dtype=bool)
        if not (np.isfinite(pos).all() and np.isfinite(ang).all() and np.isfinite(vel).all()
                and np.isfinite(angvel).all()):
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
            self.drift_rel = max(self.drift_rel,
                                 float((moved / self.shapes.width[self.resting]).max()))
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
        targets = [(i, pos[i], ang[i], self.shapes.half[i]) for i in range(self.shapes.n)
                   if i != p]
        targets += [(self.shapes.n + k, q, a, h) for k, ((q, a), h) in
                    enumerate(zip(self.shapes.static_pose, self.shapes.static_half))]
        for k, q, a, half in targets:
            c, s = math.cos(a), math.sin(a)
            dx, dy = pos[p] - q
            now = np.array([c * dx + s * dy, -s * dx + c * dy])      # m, in the body's frame
            before = self.local_before.get(k)
            self.local_before[k] = now
            if before is None or self.tunnelled:
                continue
            hit = clip_to_box(before, now, half)
            if hit is None:
                continue
            entry, exit_ = hit                  # faces (axis, sign), None where not crossed
            if entry is None and exit_ is None:             # inside all along
                continue
            if entry is not None and exit_ is not None:     # in and out within this step
                through = entry[0] == exit_[0] and entry[1] != exit_[1]
                self.entered.pop(k, None)
            elif entry is not None:             # in: remember the face
                self.entered[k] = entry
                through = False
            else:                               # out: through the face opposite the entry?
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
        if self.kind == "pile":                  # no known rest pose: not judged
            return ""
        if self.kind == "projectile" and len(self.shapes.statics):
            wall_x = self.shapes.static_pose[0][0][0]
            return "passed" if pos[self.projectile, 0] > wall_x else "stopped"
        if self.rest_pose is not None:           # bodies that land first: judged where they
            moved = np.hypot(*(pos - self.rest_pose).T)   # should come to rest
        keep = np.array([i for i in range(self.shapes.n) if i != self.projectile], dtype=int)
        ok = (moved[keep] <= STAND_MOVE * self.shapes.width[keep]).all() and \
            (turned[keep] <= STAND_TURN).all()
        return "stands" if ok else "collapsed"


def _state_changes(runner, n):
    """Most state changes of one sim body (equal-state events excluded); nan for peers."""
    world = getattr(runner, "world", None)
    if world is None:
        return math.nan
    counts = np.zeros(n, dtype=int)
    for _, body, a, b, _ in world.events:
        if a != b:
            counts[body] += 1
    return int(counts.max()) if n else 0


def build_runner(task, scene):
    """The task's runner. A task with ``refine_substeps`` (the references) that sim refuses as
    too fine for its step (a ValueError naming the substeps needed) is built again with its
    substeps doubled, up to that many; any other ValueError propagates (refused)."""
    settings = dict(task.get("settings", {}))
    system = task.get("runner") or runner_system(task["system"])
    while True:
        try:
            return build(system, scene, dt=task["dt"], iterations=task["iterations"], **settings)
        except ValueError as exc:
            substeps = settings.get("substeps")
            cap = task.get("refine_substeps")
            if not cap or substeps is None or "substeps" not in str(exc) or 2 * substeps > cap:
                raise
            settings["substeps"] = 2 * substeps


def simulate(task):
    """One run (executor task, a plain dict): build, step with samples, judge. Never raises for
    what the simulated system does (a ValueError while building is recorded as 'rejected', an
    exception while stepping as the run's error); the measuring code's own errors propagate."""
    out = {"role": task["role"], "status_hint": "", "error": "", "steps_done": 0,
           "finite": True, "exploded": False, "tunnelled": "", "outcome": "",
           "energy_growth": math.nan, "ke_max_rel": math.nan, "penetration_max_m": math.nan,
           "penetration_rel": math.nan, "drift_max_m": math.nan, "drift_rel": math.nan,
           "wakes_max": math.nan, "state_changes_max": math.nan, "asleep_before_event": math.nan,
           "ms_per_step": math.nan, "wall_s": math.nan, "bodies": 0, "decision": "",
           "iterations": task["iterations"], "substeps": None}
    t_start = time.perf_counter()
    try:
        scene = scene_of(task["scene"])
        out["bodies"] = len(scene.bodies)
        shapes = Shapes(scene)
        runner = build_runner(task, scene)
    except ValueError as exc:
        out.update(status_hint="rejected", error=f"{type(exc).__name__}: {exc}")
        return out
    # what ran, as the runner reports it (sim: iterations per substep, and its substeps)
    out["iterations"] = runner.settings.get("iterations", task["iterations"])
    world = getattr(runner, "world", None)
    out["substeps"] = int(world.substeps) if world is not None else None
    judge = Judge(scene, shapes)
    decision = Decision(task["system"][len("sim-"):]) if task.get("watch_decision") else None
    steps, every, budget = task["steps"], task["sample_every"], task["budget_s"]
    stepping = 0.0

    def advance(n):
        """Step n steps; an exception from the system (sim.SimulationError, or anything a peer
        raises) is the run's result, recorded; an exception in the measuring code is a bug and
        propagates."""
        try:
            runner.step(n)
        except Exception as exc:
            out["error"] = f"{type(exc).__name__}: {exc}"
            return False
        return True

    try:
        judge.sample(runner, 0.0)
        done = 0
        while done < steps and judge.finite:
            k = min(every, steps - done)
            if done == 0:                       # the first step is not timed (the study's rule)
                if not advance(1):
                    break
                k -= 1
                done = 1
            t0 = time.perf_counter()
            if not advance(k):
                break
            stepping += time.perf_counter() - t0
            done += k
            out["steps_done"] = done
            judge.sample(runner, done * task["dt"],
                         overlap=(done // every) % task.get("overlap_every", 1) == 0
                         or done == steps)
            if decision is not None:
                decision.watch(runner.world)
            if judge.ke_max > EXPLOSION_FACTOR:
                out["exploded"] = True
                break
            if time.perf_counter() - t_start > budget and done < steps:
                out.update(status_hint="not run",
                           error=f"timeout: {budget:g} s of wall time reached at step {done} of "
                                 f"{steps}")
                break
    finally:
        out["state_changes_max"] = _state_changes(runner, shapes.n)
        runner.close()
    timed_steps = out["steps_done"] - 1
    tunnelled = "; ".join(t for t in (judge.tunnelled, judge.through_floor()) if t)
    out.update(finite=judge.finite, tunnelled=tunnelled, outcome=judge.outcome(),
               energy_growth=judge.energy_growth, ke_max_rel=judge.ke_max,
               penetration_max_m=judge.pen_m, penetration_rel=judge.pen_rel,
               drift_max_m=judge.drift_m if len(judge.resting) else math.nan,
               drift_rel=judge.drift_rel if len(judge.resting) else math.nan,
               wakes_max=int(judge.wakes.max()) if judge.start is not None else math.nan,
               asleep_before_event=judge.asleep_before_event,
               decision=decision.label() if decision is not None else "",
               ms_per_step=1e3 * stepping / timed_steps if timed_steps > 0 else math.nan,
               wall_s=time.perf_counter() - t_start)
    if not judge.finite and not out["error"]:
        out["error"] = "non-finite state (no error raised)"
    return out


# ---- the impulse threshold: bisection ----------------------------------------------------------
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
        pair = (((c["body_a"] == 0) & (c["body_b"] == 1)) |
                ((c["body_a"] == 1) & (c["body_b"] == 0)))
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
        return {"policy": policy, "v_star": math.nan, "bracket": [lo, hi],
                "note": f"no crossing in [{lo}, {hi}] m/s (decision {at_lo} at {lo}, {at_hi} "
                        f"at {hi})"}
    for _ in range(n_bisect):
        mid = 0.5 * (lo + hi)
        if impact_decision(policy, mid, steps):
            hi = mid
        else:
            lo = mid
    return {"policy": policy, "v_star": 0.5 * (lo + hi), "bracket": [lo, hi],
            "note": "hammer bounces above v*" if policy == "paper" else "anvil wakes above v*"}


# ---- the sweep ---------------------------------------------------------------------------------
_SCENES = {}


def scene_of(spec):
    """The scene of a spec, built once per process (the 10^4-body one takes a while)."""
    key = json.dumps(spec, sort_keys=True)
    if key not in _SCENES:
        _SCENES[key] = make_scene(spec)
    return _SCENES[key]


def _kind_and_size(spec):
    """(scene kind, body count); ("rejected", 0) when the scene itself is refused (the run then
    records the ValueError)."""
    try:
        scene = scene_of(spec)
    except ValueError:
        return "rejected", 0
    return scene.params["kind"], len(scene.bodies)


def _sample_every(steps, bodies, every_step, config):
    """Steps between samples: 1 where an event must be caught (projectiles, impacts, knife
    edges); else ~``samples`` samples per run, fewer for big scenes (at most ``sample_budget``
    body-samples, at least 10 samples: measuring a 10^4-body pose costs more than stepping it)."""
    if every_step:
        return 1
    samples = max(10, min(config["samples"], config["sample_budget"] // max(1, bodies)))
    return max(1, steps // samples)


def run_task(axis, value, system, config, v_star=None):
    """The executor task of one (axis, value, system) run; ``system`` is one of ALL_SYSTEMS."""
    dt = float(value) if axis == "dt" else DT
    iterations = int(value) if axis == "iterations" else None
    settings = system_settings(system)
    if axis == "substeps":
        settings["substeps"] = int(value)
    if axis == "impact_threshold":
        spec = {"builder": "impact", "args": [v_star * (1.0 + value)]}
    else:
        spec = scene_spec(axis, value)
    steps = int(value) if axis == "long_run" else int(round(config["duration_s"][axis] / dt))
    kind, bodies = _kind_and_size(spec)
    every_step = kind in ("projectile", "impact", "knife")
    return {"role": "run", "axis": axis, "value": value, "system": system,
            "runner": runner_system(system), "settings": settings, "scene": spec,
            "kind": kind, "bodies": bodies, "dt": dt, "iterations": iterations, "steps": steps,
            "sample_every": _sample_every(steps, bodies, every_step, config),
            "budget_s": config["budget_s"],
            "watch_decision": axis == "impact_threshold" and system in ("sim-paper",
                                                                        "sim-extended")}


def reference_task(run, config):
    """sim-off at a fine dt with REF_SUBSTEPS x REF_ITERATIONS, presolve on, same simulated time,
    whatever the run's own settings (module docstring); ``run`` is a run_task."""
    axis = run["axis"]
    fine = config["fine_projectile"] if axis.startswith("projectile") else config["fine"]
    dt = min(run["dt"], DT) / fine
    spec = run["scene"]
    duration = run["steps"] * run["dt"]
    if axis == "bodies":                       # independent identical columns: one suffices
        spec = {"builder": "column", "args": [5]}
    if axis == "long_run":
        duration = min(duration, config["long_run_reference_s"])
    steps = int(round(duration / dt))
    kind, bodies = _kind_and_size(spec)
    every_step = kind in ("projectile", "impact", "knife")
    return {"role": "ref", "axis": "reference", "value": 0, "system": "sim-off",
            "runner": "sim-off", "settings": {"substeps": REF_SUBSTEPS},
            "refine_substeps": REF_MAX_SUBSTEPS, "scene": spec,
            "kind": kind, "bodies": bodies, "dt": dt, "iterations": REF_ITERATIONS,
            "steps": steps, "sample_every": _sample_every(steps, bodies, every_step, config),
            "budget_s": 20 * config["budget_s"],
            # a reference's penetration is only reported: ~``samples`` overlap tests suffice
            # even where its poses are checked every step (tunnelling)
            "overlap_every": max(1, steps // config["samples"]) if every_step else 1}


def task_key(task):
    """The store's key of a task: a run by its cell, a reference by everything that makes it."""
    if task["role"] == "run":
        return f"run|{task['axis']}|{task['value']!r}|{task['system']}"
    return "ref|" + json.dumps([task["scene"], task["dt"], task["iterations"], task["steps"],
                                task["settings"]], sort_keys=True)


def classify(res, ref):
    """(status, reason) of one run by the stated rules, given its reference's result."""
    hint = res["status_hint"]
    if hint in ("rejected", "not run"):
        return hint, res["error"]
    failed, degraded = [], []
    if res["error"]:
        failed.append(f"error ({res['error'][:120]})")
    if not res["finite"]:
        failed.append("non-finite")
    if res["exploded"] or (res["ke_max_rel"] > EXPLOSION_FACTOR):
        failed.append(f"explosion (KE {res['ke_max_rel']:.3g} x E_avail)")
    if res["tunnelled"]:
        failed.append(f"tunnelling ({res['tunnelled']})")
    if res.get("chattering"):
        failed.append(f"chattering ({res['chattering']})")
    if ref_valid(ref) and res["outcome"] and res["outcome"] != ref["outcome"]:
        failed.append(f"outcome {res['outcome']} (reference {ref['outcome']})")
    if res["penetration_rel"] > PENETRATION_REL:
        degraded.append(f"penetration {res['penetration_rel']:.3g} x width")
    if res["drift_rel"] > DRIFT_REL:
        degraded.append(f"drift {res['drift_rel']:.3g} x width")
    if res["energy_growth"] > ENERGY_GROWTH:
        degraded.append(f"energy growth {res['energy_growth']:.3g} x E_avail")
    if failed:
        return "failed", "; ".join(failed + degraded)
    if degraded:
        return "degraded", "; ".join(degraded)
    return "stable", ""


def ref_valid(ref):
    return (ref is not None and ref["status_hint"] == "" and not ref["error"] and ref["finite"]
            and not ref["tunnelled"] and not ref["exploded"] and bool(ref["outcome"]))


def chattering(task, res):
    """The chattering rule (module docstring), as text, or ''."""
    kind = task["kind"]
    if kind not in ("rest", "impact") or res["status_hint"]:
        return ""
    why = []
    if res["wakes_max"] > MAX_WAKES:
        why.append(f"a body woken {res['wakes_max']} times")
    if kind == "impact" and res["state_changes_max"] > MAX_STATE_CHANGES:
        why.append(f"a body changed state {res['state_changes_max']} times")
    return ", ".join(why)


def run(config, args):
    common.compile_kernels()
    quick = bool(args.quick)
    store, header = common.sweep_store(NAME, quick, config)   # entry removes it once written

    # 1. the impulse thresholds (two bisections, through the executor)
    thresholds = {}
    if config["axes"].get("impact_threshold"):
        steps = int(round(config["duration_s"]["impact_threshold"] / DT))
        ttasks = [{"role": "threshold", "policy": p, "steps": steps,
                   "bisection_steps": config["bisection_steps"]} for p in ("paper", "extended")]
        for t, res in zip(ttasks, run_tasks(find_threshold, ttasks, desc=f"{NAME} thresholds",
                                            store=store, header=header,
                                            key=lambda t: f"threshold|{t['policy']}")):
            thresholds[t["policy"]] = res

    # 2. every run and every distinct reference, all independent: one executor call
    runs, not_run = [], []
    for axis, values in config["axes"].items():
        for value in values:
            for system in ALL_SYSTEMS:
                if not applies(axis, system):
                    continue
                if axis == "impact_threshold":
                    policy = "extended" if system == "sim-extended" else "paper"
                    v_star = thresholds[policy]["v_star"]
                    if not math.isfinite(v_star):
                        not_run.append((axis, value, system, "no threshold crossing found: "
                                        + thresholds[policy]["note"]))
                        continue
                    task = run_task(axis, value, system, config, v_star)
                else:
                    task = run_task(axis, value, system, config)
                n = task["bodies"]
                if engine_of(task["runner"]) == "pybullet" and n > config["pybullet_max_bodies"]:
                    not_run.append((axis, value, system,
                                    f"cost: pybullet not run above {config['pybullet_max_bodies']}"
                                    f" bodies ({n}; pyramid(40) costs ~0.7 s per step)"))
                    continue
                runs.append(task)
    refs = {}
    for task in runs:
        ref = reference_task(task, config)
        refs.setdefault(task_key(ref), ref)
    tasks = list(refs.values()) + runs
    results = dict(zip(map(task_key, tasks), run_tasks(simulate, tasks, desc=f"{NAME} runs",
                                                   store=store, header=header, key=task_key)))

    # 3. the table
    rows = []
    for task in runs:
        res = dict(results[task_key(task)])
        ref_key = task_key(reference_task(task, config))
        ref = results[ref_key]
        res["chattering"] = chattering(task, res)
        status, reason = classify(res, ref)
        if not ref_valid(ref) and status not in ("rejected", "not run"):
            reason = (reason + "; " if reason else "") + "reference not valid: outcome not compared"
        rows.append(_row(task, res, status, reason, ref))
    for axis, value, system, reason in not_run:
        rows.append({"axis": axis, "value": value, "unit": AXES[axis][0], "system": system,
                     "status": "not run", "reason": reason})
    table = pd.DataFrame(rows)
    order = {a: k for k, a in enumerate(AXES)}
    table["_a"] = table["axis"].map(order)
    table["_v"] = [config["axes"][a].index(v) for a, v in zip(table["axis"], table["value"])]
    table["_s"] = table["system"].map({s: k for k, s in enumerate(ALL_SYSTEMS)})
    table = table.sort_values(["_a", "_v", "_s"]).drop(columns=["_a", "_v", "_s"])
    table = table.reset_index(drop=True)

    references = [{"key": k, "scene": t["scene"], "dt_s": t["dt"], "iterations": t["iterations"],
                   "substeps": results[k].get("substeps"),
                   "steps": t["steps"], "outcome": results[k]["outcome"],
                   "valid": ref_valid(results[k]), "error": results[k]["error"],
                   "tunnelled": results[k]["tunnelled"],
                   "penetration_rel": results[k]["penetration_rel"],
                   "wall_s": results[k]["wall_s"]} for k, t in refs.items()]
    scenes = [scene_of(spec) for spec in
              {json.dumps(t["scene"], sort_keys=True): t["scene"] for t in runs
               if t["kind"] != "rejected"}.values()]
    parameters = {
        "dt": DT, "systems": list(SYSTEMS),
        "no_presolve": {"systems": list(NO_PRESOLVE_SYSTEMS), "settings": NO_PRESOLVE_SETTINGS,
                        "axes": [a for a in PLACED_AXES if a in config["axes"]]},
        "sim_only_axes": [a for a in SIM_ONLY_AXES if a in config["axes"]],
        "reference": {"system": "sim-off", "fine": config["fine"],
                      "fine_projectile": config["fine_projectile"], "substeps": REF_SUBSTEPS,
                      "iterations_per_substep": REF_ITERATIONS,
                      "substeps_doubled_up_to": REF_MAX_SUBSTEPS},
        "rules": {"explosion_factor": EXPLOSION_FACTOR, "penetration_rel": PENETRATION_REL,
                  "drift_rel": DRIFT_REL, "energy_growth": ENERGY_GROWTH,
                  "max_wakes": MAX_WAKES, "max_state_changes": MAX_STATE_CHANGES,
                  "stand_move": STAND_MOVE, "stand_turn_rad": STAND_TURN,
                  "knife_turn_rad": KNIFE_TURN},
        "axes": {a: {"unit": AXES[a][0], "values": config["axes"][a]} for a in AXES},
        "thresholds": thresholds, "references": references,
        "projectile": {"size_m": PROJECTILE_SIZE, "arrival_s": ARRIVAL_S, "wall_m": list(WALL)},
        "impact": {"hammer_m": HAMMER, "hammer_density": HAMMER_DENSITY, "gap_m": HAMMER_GAP},
        "store": str(store),
    }
    return table, scenes, parameters


def _row(task, res, status, reason, ref):
    axis = task["axis"]
    return {"axis": axis, "value": task["value"], "unit": AXES[axis][0], "system": task["system"],
            "scene": f"{task['scene']['builder']}("
                     f"{', '.join(f'{a:.6g}' for a in task['scene']['args'])})",
            "bodies": res["bodies"], "dt_s": task["dt"],
            "iterations": (res["iterations"] if res.get("iterations") is not None else
                           task["iterations"] if task["iterations"] is not None else
                           DEFAULT_ITERATIONS[engine_of(task["runner"])]),
            "substeps": res.get("substeps"), "steps": task["steps"], "status": status,
            "reason": reason,
            "outcome": res["outcome"], "ref_outcome": ref["outcome"],
            "ref_valid": ref_valid(ref), "error": res["error"], "finite": res["finite"],
            "exploded": res["exploded"], "tunnelled": res["tunnelled"],
            "chattering": res["chattering"], "energy_growth": res["energy_growth"],
            "ke_max_rel": res["ke_max_rel"], "penetration_max_m": res["penetration_max_m"],
            "penetration_rel": res["penetration_rel"], "drift_max_m": res["drift_max_m"],
            "drift_rel": res["drift_rel"], "wakes_max": res["wakes_max"],
            "state_changes_max": res["state_changes_max"],
            "asleep_before_event": res["asleep_before_event"], "decision": res["decision"],
            "ms_per_step": res["ms_per_step"], "steps_done": res["steps_done"],
            "wall_s": res["wall_s"]}


main = common.entry(NAME, __doc__, FULL, QUICK, run)

if __name__ == "__main__":
    main()
