"""The records of the extremes table: what one run measured (``Measurement``, the executor's
result, one per run or reference) and one row of the table (``Row``: its fields are the CSV's
columns, in order). Named fields, so that a column is spelled in one place.

The columns are described in experiments/table_extremes.py's docstring ("Measured in every run",
"Columns")."""

import dataclasses
import math
from dataclasses import dataclass, fields

from study.extremes.axes import AXES
from study.extremes.rules import ref_valid
from study.peers import DEFAULT_ITERATIONS, engine_of


@dataclass
class Measurement:
    """One run (or reference run) as measured by study.extremes.runs.simulate; NaN where a
    quantity was not measured (the run was refused, or the scene has no body that should rest)."""

    role: str = "run"  # "run" or "ref"
    status_hint: str = ""  # "", or "rejected" / "not run" decided while running
    error: str = ""  # the exception raised, as text
    steps_done: int = 0
    finite: bool = True
    exploded: bool = False
    tunnelled: str = ""  # what passed through what, or ""
    outcome: str = ""  # "stands", "collapsed", "stopped", "passed", "stays", ...
    energy_growth: float = math.nan  # largest E(t) - E(0), / E_avail
    ke_max_rel: float = math.nan  # largest kinetic energy, / E_avail
    penetration_max_m: float = math.nan  # m
    penetration_rel: float = math.nan  # / the thinner body's width
    drift_max_m: float = math.nan  # m, of a body that should rest
    drift_rel: float = math.nan  # / its width
    wakes_max: float = math.nan  # most asleep -> awake of one body (count; NaN: no sample)
    state_changes_max: float = math.nan  # most state changes of one sim body (NaN: a peer)
    asleep_before_event: float = math.nan  # fraction asleep just before the projectile arrives
    ms_per_step: float = math.nan  # ms, wall time per step (indicative: runs share a pool)
    wall_s: float = math.nan  # s, the whole run
    bodies: int = 0
    decision: str = ""  # the impulse test's verdict (impact axis), or ""
    iterations: int | None = None  # as the runner reports them (sim: per substep)
    substeps: int | None = None  # sim's substeps per step; None for the peers
    chattering: str = ""  # the chattering rule's verdict, set when the table is made

    def stored(self):
        """A plain dict (the executor's incremental store keeps JSON)."""
        return dataclasses.asdict(self)


@dataclass
class Row:
    """One row of table_extremes.csv: one (axis, value, system) cell. A cell that was not run
    has only its key, status and reason (the rest None: empty in the CSV)."""

    axis: str
    value: float
    unit: str
    system: str
    scene: str | None = None  # the scene spec as text, builder(args)
    bodies: int | None = None
    dt_s: float | None = None  # s
    iterations: int | None = None  # the run's solver iterations (sim: per substep)
    substeps: int | None = None  # sim's substeps per step; None for the peers
    steps: int | None = None
    status: str | None = None  # one of study.extremes.rules.STATUSES
    reason: str | None = None
    outcome: str | None = None
    ref_outcome: str | None = None
    ref_valid: bool | None = None
    error: str | None = None
    finite: bool | None = None
    exploded: bool | None = None
    tunnelled: str | None = None
    chattering: str | None = None
    energy_growth: float | None = None
    ke_max_rel: float | None = None
    penetration_max_m: float | None = None  # m
    penetration_rel: float | None = None
    drift_max_m: float | None = None  # m
    drift_rel: float | None = None
    wakes_max: float | None = None
    state_changes_max: float | None = None
    asleep_before_event: float | None = None
    decision: str | None = None
    ms_per_step: float | None = None  # ms
    steps_done: int | None = None
    wall_s: float | None = None  # s

    @classmethod
    def of_run(cls, task, res, status, reason, ref):
        """The row of a run task (a dict of study.extremes.runs.run_task), its Measurement
        ``res``, its mark and the reference's Measurement ``ref``."""
        spec = task["scene"]
        if res.iterations is not None:
            iterations = res.iterations
        elif task["iterations"] is not None:
            iterations = task["iterations"]
        else:
            iterations = DEFAULT_ITERATIONS[engine_of(task["runner"])]
        return cls(
            axis=task["axis"],
            value=task["value"],
            unit=AXES[task["axis"]].unit,
            system=task["system"],
            scene=f"{spec['builder']}({', '.join(f'{a:.6g}' for a in spec['args'])})",
            bodies=res.bodies,
            dt_s=task["dt"],
            iterations=iterations,
            substeps=res.substeps,
            steps=task["steps"],
            status=status,
            reason=reason,
            outcome=res.outcome,
            ref_outcome=ref.outcome,
            ref_valid=ref_valid(ref),
            error=res.error,
            finite=res.finite,
            exploded=res.exploded,
            tunnelled=res.tunnelled,
            chattering=res.chattering,
            energy_growth=res.energy_growth,
            ke_max_rel=res.ke_max_rel,
            penetration_max_m=res.penetration_max_m,
            penetration_rel=res.penetration_rel,
            drift_max_m=res.drift_max_m,
            drift_rel=res.drift_rel,
            wakes_max=res.wakes_max,
            state_changes_max=res.state_changes_max,
            asleep_before_event=res.asleep_before_event,
            decision=res.decision,
            ms_per_step=res.ms_per_step,
            steps_done=res.steps_done,
            wall_s=res.wall_s,
        )


#: the CSV's columns, in order
COLUMNS = tuple(f.name for f in fields(Row))
