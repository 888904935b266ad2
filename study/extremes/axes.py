"""The axes of the extremes table (experiments/table_extremes.py), one ``Axis`` record each, and the
systems that have a cell on them.

Adding an axis is one entry in AXES: its values, unit and label, the scene it runs (a builder of
study.extremes.scenes), what its value varies (the scene's argument, or a ``knob`` of the
run), how long it runs, and the reference's settings; the sweep, the reference, the metadata and
the figure read everything from the record."""

from dataclasses import dataclass

from study.common import SYSTEMS
from study.peers import engine_of
from study.systems import NO_PRESOLVE_SYSTEMS, runner_system

#: every system, and the sim systems again with the presolve off (study.systems, NO_PRESOLVE;
#: table_extremes' docstring, "Systems")
ALL_SYSTEMS = SYSTEMS + NO_PRESOLVE_SYSTEMS

#: what an axis's value can vary besides the scene's argument (``Axis.knob``)
KNOBS = ("dt", "iterations", "substeps", "steps", "threshold")


@dataclass(frozen=True)
class Axis:
    """One axis of the table: a row per value, benign to extreme."""

    name: str
    unit: str  # of the values
    label: str  # the figure's words for the axis
    values: tuple  # the full table's values, benign to extreme
    quick: tuple  # --quick's values (the extreme ones)
    builder: str  # the scene: a builder of study.extremes.scenes.BUILDERS
    #: the builder's argument when the value varies the run rather than the scene (``knob``);
    #: None: the value itself is the argument
    scene_arg: float | None = None
    #: what else the value sets: "dt" (s), "iterations" (the engine's own), "substeps" (sim),
    #: "steps" (the run's length), "threshold" (the value is v0/v* - 1 of the impact test); ""
    knob: str = ""
    duration_s: float = 3.0  # s simulated in the full table (knob "steps": the value instead)
    quick_duration_s: float = 1.0  # s simulated under --quick
    #: the scene starts with bodies resting on one another, where sim's presolve puts them in
    #: equilibrium: the sim systems are run again without it
    placed: bool = False
    #: a knob only sim has: no peer cell, no "breaks first"
    sim_only: bool = False
    #: the config key of the reference's refinement of dt ("fine", or "fine_projectile")
    fine: str = "fine"
    #: the reference's scene, when one smaller scene stands for the row's: (builder, argument)
    reference_scene: tuple | None = None
    #: the config key of the most simulated time the reference runs (s), or ""
    reference_cap: str = ""

    def scene_spec(self, value, v_star=None):
        """The scene of the row at ``value``, as a spec (``v_star``: the threshold, m/s, for
        knob "threshold")."""
        if self.knob == "threshold":
            return {"builder": self.builder, "args": [v_star * (1.0 + value)]}
        return {
            "builder": self.builder,
            "args": [value if self.scene_arg is None else self.scene_arg],
        }


_PROJECTILE = dict(quick_duration_s=3.0, fine="fine_projectile")

AXES = {
    axis.name: axis
    for axis in (
        Axis(
            "mass_heavy_on_light",
            "m_top/m_below",
            "mass, heavy on light",
            # 1e4: where sim's stack no longer stands (the heavy box sank 0.84 m into the light
            # one, 2026-12-07; it stood at 1000 and sank 7.5 cm at 3000): the table shows it
            (1, 10, 100, 1000, 10000),
            (1000,),
            "mass_stack",
            placed=True,
        ),
        Axis(
            "mass_light_on_heavy",
            "m_top/m_below",
            "mass, light on heavy",
            (1, 0.1, 0.01, 0.001),
            (0.001,),
            "mass_stack",
            placed=True,
        ),
        Axis(
            "mass_dropped",
            "m_top/m_below",
            "mass, heavy dropped on light",
            (1, 10, 100, 1000, 10000),
            (1000,),
            "dropped_mass_stack",
        ),
        Axis(
            "size_small",
            "m",
            "box size, small",
            (1.0, 0.1, 0.01, 1e-3, 1e-4),
            (1.0, 0.01),
            "size_stack",
            placed=True,
        ),
        Axis(
            "size_large",
            "m",
            "box size, large",
            (1.0, 10.0, 100.0),
            (100.0,),
            "size_stack",
            placed=True,
        ),
        Axis(
            "plank_flat",
            "aspect",
            "plank across a box",
            (1, 3, 10, 30, 100),
            (1, 100),
            "plank_flat",
            placed=True,
        ),
        Axis(
            "plank_upright",
            "aspect",
            "plank on its end",
            (1, 3, 10, 30, 100),
            (100,),
            "plank_upright",
            placed=True,
        ),
        Axis(
            "polygon_vertices",
            "vertices",
            "n-gon on a box",
            (3, 4, 8, 16, 32, 64),
            (3, 64),
            "polygon_on_box",
            placed=True,
        ),
        Axis(
            "collinear",
            "m",
            "near-collinear vertex",
            (1e-2, 1e-4, 1e-6, 1e-9),
            (1e-9,),
            "collinear_box",
            placed=True,
        ),
        Axis(
            "projectile_stack",
            "m/s",
            "projectile into stack",
            (10, 30, 100, 200),
            (200,),
            "projectile_stack",
            placed=True,
            **_PROJECTILE,
        ),
        Axis(
            "projectile_wall",
            "m/s",
            "projectile into wall",
            (10, 30, 100, 200),
            (200,),
            "projectile_wall",
            **_PROJECTILE,
        ),
        Axis(
            "dt",
            "s",
            "time step (10-box stack)",
            (1 / 480, 1 / 240, 1 / 120, 1 / 60, 1 / 30, 1 / 15),
            (1 / 15,),
            "dropped_column",
            scene_arg=10,
            knob="dt",
            duration_s=5.0,
        ),
        Axis(
            "iterations",
            "iterations",
            "iterations (10-box stack; sim: /substep)",
            (50, 20, 10, 5, 2, 1),
            (1,),
            "dropped_column",
            scene_arg=10,
            knob="iterations",
            duration_s=5.0,
        ),
        Axis(
            "substeps",
            "substeps",
            "sim substeps (10-box stack)",
            (16, 8, 4, 2, 1),
            (1,),
            "dropped_column",
            scene_arg=10,
            knob="substeps",
            duration_s=5.0,
            sim_only=True,
        ),
        Axis(
            "stack_height",
            "boxes",
            "stack height",
            (10, 20, 50),
            (20,),
            "column",
            duration_s=5.0,
            placed=True,
        ),
        Axis(
            "pyramid_base",
            "boxes",
            "pyramid base",
            (10, 20, 40, 60),
            (5,),
            "pyramid",
            duration_s=5.0,
            placed=True,
        ),
        # the reference: one five-box column (the columns never touch: identical, independent)
        Axis(
            "bodies",
            "bodies",
            "many bodies",
            (10000,),
            (100,),
            "columns",
            duration_s=2.0,
            placed=True,
            reference_scene=("column", 5),
        ),
        # the reference runs at most long_run_reference_s: a placed column stands or falls within
        # seconds; the drift and energy over 10^5 steps are measured in the run itself
        Axis(
            "long_run",
            "steps",
            "long resting run",
            (100000,),
            (3000,),
            "column",
            scene_arg=3,
            knob="steps",
            placed=True,
            reference_cap="long_run_reference_s",
        ),
        Axis(
            "impact_threshold",
            "v0/v* - 1",
            "impact at threshold",
            (-1e-3, -1e-6, 1e-6, 1e-3),
            (-1e-6, 1e-6),
            "impact",
            knob="threshold",
            duration_s=2.0,
        ),
        Axis(
            "knife_edge",
            "rad",
            "knife edge",
            (1e-3, 1e-6, 1e-9, 0.0),
            (1e-6, 0.0),
            "knife_edge",
            duration_s=10.0,
            quick_duration_s=4.0,
        ),
    )
}

#: the axes whose scenes start placed at rest: also run without sim's presolve
PLACED_AXES = tuple(name for name, axis in AXES.items() if axis.placed)
#: the axes of a knob only sim has: no peer row, no "breaks first"
SIM_ONLY_AXES = tuple(name for name, axis in AXES.items() if axis.sim_only)


def applies(axis, system):
    """Whether ``system`` (one of ALL_SYSTEMS) has a cell on ``axis`` (a name): the no-presolve
    systems only on PLACED_AXES, the sim-only axes only for sim. Elsewhere the cell is not
    applicable, which is not "not run": there is nothing to run."""
    base = runner_system(system)
    if axis in SIM_ONLY_AXES and engine_of(base) != "sim":
        return False
    return system == base or axis in PLACED_AXES
