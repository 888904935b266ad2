"""What a recording replays: a scene, the systems run on it and how, resolved from a name.

A *target* is everything needed to rerun the same start state under several systems in lockstep:
the scene, the step dt (s), the steps, and per system its runner's name and settings. It is
resolved from one of

    a scene builder          sim.scenes.BUILDERS: single_box, pyramid, drop, seed_fig3, ...
    a scenario               the failure catalogue (study.scenarios): slope_creep, ...
    a scene file             any path ending in .toml (written by sim.Scene.to_file)
    a table cell             table_failures/<scenario>          (a row of the failure catalogue)
                             table_extremes/<axis>/<value>     (a row of the extremes table)

A table cell is run exactly as its table runs it (the same scene, dt, steps, each system's
settings: built by the table's own library functions, so the two cannot drift apart; a test checks
it against the scripts). A name that is none of these is an error listing what is available.

Scenes and scene files run ``DEFAULT_SYSTEMS`` at DT unless told otherwise, each system with the
study's comparable settings (study.common.build). A builder takes a size (``size``) only if it
has one (``SIZE_PARAMETERS``: the argument that sets its body count).

``Target.file_stem`` names a target's recording by what distinguishes its run, so that two runs
never share a default file: the name (a cell's path with ``__``, a scene file's stem and a hash
of its contents), then, joined by ``__``, a builder's size, a dt other than DT, the systems when
not the default ones, and the steps and sampling when asked for:
``pyramid__size40__dt0.004167__pymunk+sim-off__steps60``.
"""

import hashlib
import math
from dataclasses import dataclass, field
from pathlib import Path

import sim
from sim.arguments import positive
from study import common, scenarios
from study.common import DT
from study.extremes.axes import AXES, ALL_SYSTEMS, applies
from study.systems import NO_PRESOLVE_SYSTEMS, runner_system, system_settings
from study.extremes.runs import run_task
from study.extremes.scenes import scene_of
from study.extremes.threshold import find_threshold
from study.peers import SYSTEMS, engine_of

#: the systems a scene is recorded under when none are named: no freezing, the study's method, and
#: the engines' sleeping (what "where does freezing change the outcome" compares)
DEFAULT_SYSTEMS = ("sim-off", "sim-extended", "pymunk-sleep")
DEFAULT_STEPS = 300  # steps of a builder's scene or a scene file when none are given
TABLES = ("table_failures", "table_extremes")
#: a cell's value matches a row's when within this relative distance (the paper prints 3-4 digits)
VALUE_TOLERANCE = 0.01
#: table_extremes' bisection of the impact threshold: its own settings (experiments.table_extremes)
THRESHOLD_BISECTIONS = 45
PYBULLET_MAX_BODIES = 2000  # table_extremes does not run pybullet above this (its cost)
#: builder -> its size argument, the one that sets its body count (``resolve``'s ``size``); the
#: others' first arguments are not sizes (seed_fig3's is a speed, single_box's a length in m)
SIZE_PARAMETERS = {
    "rest_row": "n",
    "stack": "height",
    "pyramid": "base",
    "drop": "n",
    "arch": "n_blocks",
}


@dataclass
class System:
    """One system of a target: ``name`` as the tables print it (``"sim-off (no presolve)"``),
    ``runner`` the runner's system (``"sim-off"``), ``settings`` passed to it, or ``not_run``:
    the reason the table does not run it (then nothing is built). ``scene``: this system's own
    scene where the table gives it one (the impact threshold axis throws the hammer at each
    policy's own threshold), else None: the target's."""

    name: str
    runner: str
    settings: dict = field(default_factory=dict)
    not_run: str = ""
    scene: object = None

    def build(self, scene, dt):
        """The system's runner on its scene (``scene`` unless it has its own); a ValueError when
        the system refuses it."""
        return common.build(self.runner, self.scene or scene, dt=dt, **self.settings)


@dataclass
class Target:
    """A scene and the systems replayed on it, in lockstep from the same start state."""

    label: str  # what was asked for, e.g. "table_extremes/dt/0.0333"
    kind: str  # "builder", "scenario", "file", "table_failures", "table_extremes"
    scene: object  # sim.Scene
    dt: float  # s per step
    steps: int  # steps the table (or the default) runs
    systems: list  # [System], the first is the reference of the divergence
    #: what distinguishes the run beyond its label, in the order file_stem names them
    #: ("size", "dt"; set by ``resolve``), and a scene file's name with its hash ("file")
    options: dict = field(default_factory=dict)
    default_systems: tuple = ()  # the systems the target runs when none are named
    #: a scene file's full path and sha256, for the recording's provenance (with --out the file
    #: name no longer carries the hash, and a hand-edited file looked like its builder's)
    source: dict = field(default_factory=dict)

    @property
    def stem(self):
        """The label as a file name (no path separators)."""
        return self.label.replace("/", "__").replace(".toml", "")

    def file_stem(self, steps=None, every=None):
        """A file name for the recording of this run (no path separators; see the module
        docstring): ``steps`` when not the target's own, ``every`` when asked for."""
        parts = [self.options.get("file", self.stem)]
        if "size" in self.options:
            parts.append(f"size{self.options['size']}")
        if "dt" in self.options:
            dt = self.options["dt"]
            # short where that is exact, else every digit: 0.004 and 0.0040000001 shared a file
            short = f"{dt:.6g}"
            parts.append(f"dt{short if float(short) == dt else repr(float(dt))}")
        names = tuple(s.name for s in self.systems)
        if names != tuple(self.default_systems):
            parts.append("+".join(slug(n) for n in names))
        if steps is not None and steps != self.steps:
            parts.append(f"steps{steps}")
        if every is not None:
            parts.append(f"every{every}")
        return "__".join(parts)

    def select(self, names):
        """The target with only ``names`` (in that order; a name given twice runs twice, e.g. to
        see that a system repeats itself); unknown names are an error listing the target's
        systems."""
        have = {s.name: s for s in self.systems}
        unknown = [n for n in names if n not in have]
        if unknown:
            raise ValueError(
                f"{self.label}: no system {', '.join(map(repr, unknown))} here; it "
                f"has {', '.join(have)}"
            )
        self.systems = [have[n] for n in names]
        return self


def slug(system):
    """A system's name as a path part: "sim-off (no presolve)" -> "sim-off_no-presolve"."""
    return system.replace(" (", "_").replace(")", "").replace(" ", "-")


def available():
    """What can be named, as text for error messages and --help."""
    axes = ", ".join(AXES)
    return (
        f"scene builders: {', '.join(sim.scenes.BUILDERS)}\n"
        f"scenarios: {', '.join(scenarios.SCENARIOS)}\n"
        f"scene files: a path ending in .toml\n"
        f"table cells: table_failures/<scenario>, table_extremes/<axis>/<value> "
        f"(axes: {axes})"
    )


def resolve(name, systems=None, size=None, dt=None):
    """The Target called ``name`` (see the module docstring).

    systems  names to record (default: the table's systems for a cell, else DEFAULT_SYSTEMS);
             an empty list is an error
    size     a builder's size argument (SIZE_PARAMETERS: rest_row n, stack height, pyramid
             base, drop n, arch n_blocks); an error for a builder without one
    dt       s per step for a scene (a cell runs at its table's dt; giving another is an error)
    """
    if not isinstance(name, str) or not name:
        raise ValueError(f"name a scene or a table cell; available:\n{available()}")
    if systems is not None and not list(systems):  # an empty list fell back to the defaults
        raise ValueError(
            f"{name}: the list of systems is empty; name one or more of "
            f"{', '.join(tuple(SYSTEMS) + NO_PRESOLVE_SYSTEMS)}"
        )
    head = name.split("/", 1)[0]
    if head in TABLES:
        if size is not None or dt is not None:
            raise ValueError(
                f"{name}: a table cell runs as its table does; --size and --dt are for scenes"
            )
        target = _failure_cell(name) if head == "table_failures" else _extremes_cell(name)
        target.default_systems = tuple(s.name for s in target.systems)
        if systems is not None:
            target.select(list(systems))
        return target
    return _scene_target(name, size, dt, list(systems or DEFAULT_SYSTEMS))


def scene_system(name):
    """A System for a scene: any runner system (study.peers.SYSTEMS) or a sim system
    without its presolve ("sim-off (no presolve)"), with the study's comparable settings."""
    known = tuple(SYSTEMS) + NO_PRESOLVE_SYSTEMS
    if name not in known:
        raise ValueError(f"unknown system {name!r}; choose from {', '.join(known)}")
    return System(name, runner_system(name), system_settings(name))


# ---- scenes ------------------------------------------------------------------------------------
def _scene_target(name, size, dt, systems):
    dt = DT if dt is None else positive(dt, "dt")
    steps = DEFAULT_STEPS
    options = {} if dt == DT else {"dt": dt}
    source = {}
    if name.endswith(".toml"):
        if size is not None:
            raise ValueError(f"{name}: --size is a builder's argument, not a scene file's")
        if not Path(name).is_file():
            raise ValueError(f"scene file {name} not found")
        try:  # an unreadable file (permissions, a device) is the user's, not a bug: one line
            contents = Path(name).read_bytes()
            scene, kind = sim.Scene.from_file(name), "file"
        except OSError as exc:
            raise ValueError(f"cannot read scene file {name}: {exc.strerror or exc}") from None
        # two files of one name in different folders are different scenes: the contents tell
        digest = hashlib.sha256(contents).hexdigest()
        options["file"] = f"{Path(name).stem}-{digest[:8]}"
        source = {"path": str(Path(name).resolve()), "sha256": digest}
    elif name in sim.scenes.BUILDERS:
        build = sim.scenes.BUILDERS[name]
        parameter = SIZE_PARAMETERS.get(name)
        if size is not None and parameter is None:
            raise ValueError(
                f"{name} has no size argument (--size sets the body count of "
                f"{', '.join(SIZE_PARAMETERS)})"
            )
        scene = build() if size is None else build(**{parameter: size})
        kind = "builder"
        if parameter is not None:  # the size run, given or the builder's default
            options["size"] = scene.params[parameter]
    elif name in scenarios.SCENARIOS:
        if size is not None:
            raise ValueError(f"{name}: a scenario has no size argument")
        scenario = scenarios.get(name)
        scene, kind = scenario.build(), "scenario"
        duration = scenario.duration(scene)
        steps = int(round(duration / dt))
        if steps < 1:  # was "steps must be an integer >= 1, got 0", of a --steps never given
            raise ValueError(f"{name}: dt {dt:g} s is longer than the scenario's {duration:g} s")
    else:
        raise ValueError(f"unknown scene or cell {name!r}; available:\n{available()}")
    label = Path(name).name if kind == "file" else name
    chosen = [scene_system(s) for s in systems]
    return Target(label, kind, scene, dt, steps, chosen, options, DEFAULT_SYSTEMS, source)


# ---- table cells -------------------------------------------------------------------------------
def _failure_cell(name):
    """table_failures/<scenario>: every system of the table at its dt, for the scenario's time."""
    parts = name.split("/")
    if len(parts) != 2 or parts[1] not in scenarios.SCENARIOS:
        raise ValueError(
            f"{name}: name a row of table_failures as table_failures/<scenario>; "
            f"scenarios: {', '.join(scenarios.SCENARIOS)}"
        )
    scenario = scenarios.get(parts[1])
    scene = scenario.build()
    steps = int(round(scenario.duration(scene) / DT))
    return Target(name, "table_failures", scene, DT, steps, [System(s, s) for s in common.SYSTEMS])


def match_value(axis, text):
    """The value of ``axis``'s rows (full table or quick) that ``text`` names: the nearest within
    VALUE_TOLERANCE (relative), so the paper's rounded 0.0333 names 1/30."""
    record = AXES[axis]
    values = list(dict.fromkeys(list(record.values) + list(record.quick)))
    try:
        x = float(text)
    except ValueError:
        x = math.nan
    # nan and inf compare false with every row: both once named the axis's first row silently
    if not math.isfinite(x):
        raise ValueError(
            f"table_extremes/{axis}/{text}: the value must be a finite number; the rows "
            f"are {', '.join(f'{v:g}' for v in values)}"
        )
    best = min(values, key=lambda v: abs(v - x))
    if abs(best - x) > VALUE_TOLERANCE * max(abs(best), abs(x)) and best != x:
        raise ValueError(
            f"table_extremes/{axis}/{text}: no row at {x:g} {record.unit}; the rows "
            f"are {', '.join(f'{v:g}' for v in values)}"
        )
    return best


def _extremes_cell(name):
    """table_extremes/<axis>/<value>: every system with a cell on that row, each as the table
    runs it (study.extremes.runs.run_task, the full table's duration)."""
    parts = name.split("/")
    if len(parts) != 3 or parts[1] not in AXES:
        raise ValueError(
            f"{name}: name a cell of table_extremes as table_extremes/<axis>/<value>;"
            f" axes: {', '.join(AXES)}"
        )
    axis, value = parts[1], match_value(parts[1], parts[2])
    record = AXES[axis]
    config = {
        "duration_s": {axis: record.duration_s},
        "samples": 1,
        "sample_budget": 1,
        "budget_s": math.inf,
    }
    v_star = {}
    if record.knob == "threshold":  # the threshold search the table itself runs
        v_star = {policy: threshold(policy) for policy in ("paper", "extended")}
    systems, task = [], None
    for system in ALL_SYSTEMS:
        if not applies(axis, system):
            continue
        star = v_star.get("extended" if system == "sim-extended" else "paper")
        if record.knob == "threshold" and not math.isfinite(star):
            systems.append(System(system, runner_system(system), not_run="no threshold found"))
            continue
        one = run_task(axis, value, system, config, star)
        task = task or one
        reason = ""
        if engine_of(one["runner"]) == "pybullet" and one["bodies"] > PYBULLET_MAX_BODIES:
            reason = f"the table does not run pybullet above {PYBULLET_MAX_BODIES} bodies"
        settings = dict(system_settings(system), **one["settings"])
        if one["iterations"] is not None:
            settings["iterations"] = one["iterations"]
        own = None if one["scene"] == task["scene"] else _scene_of(name, one["scene"])
        systems.append(System(system, one["runner"], settings, reason, own))
    scene = _scene_of(name, task["scene"])
    return Target(
        cell_label(axis, value), "table_extremes", scene, task["dt"], task["steps"], systems
    )


def cell_label(axis, value):
    """The name of an extremes cell, as the paper prints it: table_extremes/dt/0.03333."""
    return f"table_extremes/{axis}/{value:.4g}"


def threshold(policy):
    """v*, m/s: the hammer's speed at which sim-``policy``'s impulse test flips in the impact
    scene, found as table_extremes finds it (the same bisection, the full table's duration)."""
    axis = next(a for a in AXES.values() if a.knob == "threshold")
    return find_threshold(
        {
            "policy": policy,
            "steps": int(round(axis.duration_s / DT)),
            "bisection_steps": THRESHOLD_BISECTIONS,
        }
    )["v_star"]


def _scene_of(name, spec):
    """The scene of an extremes spec; a scene the table itself cannot build (it records the cell
    as rejected) cannot be traced either: say so."""
    try:
        return scene_of(spec)
    except ValueError as exc:
        raise ValueError(
            f"{name}: the table rejects this cell's scene ({exc}); there is no run to record"
        ) from None
