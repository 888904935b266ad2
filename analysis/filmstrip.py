"""Drawing the filmstrip figures (fig_states, fig_edge_as_floor, fig_overhang) from the
``study.filmstrip`` tables: bodies as filled polygons coloured by state (frozen ones darker
and hatched), the floor, optional dashed "ghost" outlines of the reference (off) run, and the state
legend."""

import math

import numpy as np
from matplotlib.patches import Patch, Polygon

from analysis import style
from study.filmstrip import outline_xy


def bodies(table, policy, step=None):
    """The "body" rows of one policy (and one step)."""
    t = table[(table["kind"] == "body") & (table["policy"] == policy)]
    return t if step is None else t[t["step"] == step]


def events(table, policy, name=None):
    t = table[(table["kind"] == "event") & (table["policy"] == policy)]
    return t if name is None else t[t["name"] == name]


def draw_frame(ax, frame, ghost=None, xlim=None, ylim=None, names=True):
    """Draw one step's bodies (``frame``: body rows of one step) on ``ax``; ``ghost``: body rows
    drawn as dashed outlines (the reference run at the same step)."""
    for _, row in frame.iterrows():
        frozen = bool(row["frozen"])
        ax.add_patch(
            Polygon(
                outline_xy(row["outline"]),
                closed=True,
                facecolor=style.state_color(row["state"], frozen),
                edgecolor="black",
                linewidth=0.8,
                hatch="///" if frozen else None,
            )
        )
        if names:
            ax.text(
                row["x"],
                row["y"],
                row["name"],
                ha="center",
                va="center",
                fontsize=7,
                color="white" if frozen else "black",
                fontweight="bold",
            )
    if ghost is not None:
        for _, row in ghost.iterrows():
            ax.add_patch(
                Polygon(
                    outline_xy(row["outline"]),
                    closed=True,
                    fill=False,
                    edgecolor="black",
                    linestyle="--",
                    linewidth=0.6,
                    alpha=0.6,
                )
            )
    ax.axhline(0.0, color="black", linewidth=1.0)
    ax.set_aspect("equal")
    ax.grid(False)
    if xlim is not None:
        ax.set_xlim(*xlim)
    if ylim is not None:
        ax.set_ylim(*ylim)
    ax.tick_params(labelsize=6)


def extent(table, margin=0.3):
    """(xlim, ylim) covering every outline in ``table`` (floor included)."""
    xy = np.vstack([outline_xy(o) for o in table.loc[table["kind"] == "body", "outline"]])
    lo, hi = xy.min(axis=0) - margin, xy.max(axis=0) + margin
    return (lo[0], hi[0]), (min(lo[1], -0.15), hi[1])


def state_legend(fig, frozen=True, ghost=False, ncol=5, y=1.02):
    handles = [
        Patch(facecolor=style.state_color(s), edgecolor="black", label=style.STATE_LABEL[s])
        for s in range(3)
    ]
    if frozen:
        handles.append(
            Patch(
                facecolor=style.state_color(2, True),
                edgecolor="black",
                hatch="///",
                label="frozen (not solved)",
            )
        )
    if ghost:
        handles.append(
            Patch(fill=False, edgecolor="black", linestyle="--", label="off (reference)")
        )
    fig.legend(
        handles=handles, loc="lower center", ncol=ncol, bbox_to_anchor=(0.5, y), frameon=False
    )


def final_error(table, policy, reference="off"):
    """Largest centre distance (m) and angle difference (rad) between ``policy`` and
    ``reference`` at the last step."""
    last = int(table.loc[table["kind"] == "body", "step"].max())
    a = bodies(table, policy, last).sort_values("body")
    b = bodies(table, reference, last).sort_values("body")
    d = np.hypot(a["x"].to_numpy() - b["x"].to_numpy(), a["y"].to_numpy() - b["y"].to_numpy())
    da = np.abs(np.angle(np.exp(1j * (a["angle"].to_numpy() - b["angle"].to_numpy()))))
    return float(d.max()), float(da.max())


def first_step(table, policy, predicate):
    """First step at which ``predicate(frame)`` holds for the policy's bodies, or None."""
    for step, frame in bodies(table, policy).groupby("step"):
        if predicate(frame.sort_values("body")):
            return int(step)
    return None


def frozen_step(table, policy, name):
    """First step from which ``name`` stays frozen to the end, or None."""
    rows = bodies(table, policy)
    rows = rows[rows["name"] == name].sort_values("step")
    frozen = rows["frozen"].to_numpy(bool)
    if not frozen[-1]:
        return None
    k = len(frozen) - 1
    while k > 0 and frozen[k - 1]:
        k -= 1
    return int(rows["step"].iloc[k])


def nan_if_none(x):
    return math.nan if x is None else x


def body_a_numbers(table, policies):
    """What the paper quotes of body A in a two-body seed figure: its paper events, the step it
    froze under each policy, and its final pose error against off."""
    from analysis import style

    err = {p: final_error(table, p) for p in policies}
    return {
        "a_paper_events": [
            {
                "step": int(e.step),
                "from": style.STATE_LABEL[int(e.from_state)],
                "to": style.STATE_LABEL[int(e.state)],
                "cause": e.cause,
            }
            for e in events(table, "paper", "A").itertuples()
        ],
        "a_frozen_step": {p: nan_if_none(frozen_step(table, p, "A")) for p in policies},
        "final_position_error_m": {p: err[p][0] for p in policies},
        "final_angle_error_rad": {p: err[p][1] for p in policies},
    }
