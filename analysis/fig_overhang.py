"""Figure "fig_overhang": seed figure 3 — filmstrip of A sliding off B under paper (dashed: off),
and the state and position timelines of A under paper and extended against off."""

import matplotlib.pyplot as plt
import numpy as np

from analysis import filmstrip as fs
from analysis import style

NAME = "fig_overhang"
POLICIES = ("paper", "extended")


def draw(table, meta):
    dt = meta["parameters"]["dt"]
    a_events = fs.events(table, "paper", "A")
    last = int(table["step"].max())
    frozen_a = fs.frozen_step(table, "paper", "A")
    change_steps = sorted(set(int(s) for s in a_events["step"]))
    steps = sorted(set([0] + change_steps + ([frozen_a] if frozen_a is not None else []) + [last]))
    if len(steps) > 7:  # keep the filmstrip readable: first, last and evenly spaced changes
        inner = steps[1:-1]
        steps = (
            [steps[0]]
            + [inner[i] for i in np.linspace(0, len(inner) - 1, 5).astype(int)]
            + [steps[-1]]
        )
        steps = sorted(set(steps))
    xlim, ylim = fs.extent(table)
    fig = plt.figure(figsize=(style.WIDTH, 4.2))
    grid = fig.add_gridspec(2, 2, height_ratios=(1.0, 1.0), hspace=0.35, wspace=0.35)
    # a stroboscopic filmstrip: B once, A at every frame (coloured by its paper state), the off run
    # dashed at the same steps
    ax = fig.add_subplot(grid[0, :])
    # B once (its final, frozen pose), then A at frames spread along its path: a frame is kept
    # when A has moved 0.3 m or turned 0.3 rad since the last kept one, so outlines do not pile up
    fs.draw_frame(ax, fs.bodies(table, "paper", last).query("name == 'B'"), xlim=xlim, ylim=ylim)
    track = fs.bodies(table, "paper").query("name == 'A'").set_index("step")
    strobe = [0]
    for step in sorted(set(range(0, last + 1, 3)) | set(steps)):
        p, q = track.loc[step], track.loc[strobe[-1]]
        if np.hypot(p.x - q.x, p.y - q.y) > 0.3 or abs(p.angle - q.angle) > 0.3:
            strobe.append(step)
    steps = strobe if strobe[-1] == last else strobe + [last]
    for step in steps:
        frame = fs.bodies(table, "paper", step).query("name == 'A'")
        ghost = fs.bodies(table, "off", step).query("name == 'A'")
        fs.draw_frame(ax, frame, ghost=ghost, xlim=xlim, ylim=ylim, names=False)
        a = frame.iloc[0]
        ax.annotate(
            f"{step}",
            (a["x"], a["y"]),
            ha="center",
            va="center",
            fontsize=6,
            color="white" if a["frozen"] else "black",
        )
    ax.set_title(
        "paper: A at steps "
        + ", ".join(str(s) for s in steps)
        + " (dashed: off at the same steps)",
        fontsize=8,
    )
    ax.set_xlabel("x (m)")
    ax_state = fig.add_subplot(grid[1, 0])
    ax_x = fig.add_subplot(grid[1, 1])
    for k, policy in enumerate(POLICIES):
        a = fs.bodies(table, policy)
        a = a[a["name"] == "A"].sort_values("step")
        t = a["step"].to_numpy() * dt
        st = style.system_style(f"sim-{policy}")
        # offset the two policies slightly so both step lines stay visible
        ax_state.step(
            t,
            a["state"].to_numpy() + 0.06 * (k - 0.5),
            where="post",
            color=st["color"],
            label=policy,
        )
        frozen = a["frozen"].to_numpy(bool)
        ax_state.plot(
            t[frozen],
            a["state"].to_numpy()[frozen] + 0.06 * (k - 0.5),
            "|",
            color=st["color"],
            markersize=3,
        )
        ax_x.plot(t, a["x"], color=st["color"], label=policy)
    ref = fs.bodies(table, "off")
    ref = ref[ref["name"] == "A"].sort_values("step")
    ax_x.plot(ref["step"] * dt, ref["x"], color="black", linestyle="--", label="off")
    ax_state.set_yticks(range(3), [style.STATE_LABEL[s].split(" ")[0] for s in range(3)])
    ax_state.set_xlabel("t (s)")
    ax_state.set_title("state of A (ticks: frozen)", fontsize=8)
    ax_state.legend(loc="lower right")
    ax_x.set_xlabel("t (s)")
    ax_x.set_ylabel("x of A (m)")
    ax_x.legend(loc="lower right")
    fs.state_legend(fig, ghost=True, y=0.92)
    style.save_figure(fig, NAME)
    left = a_events[a_events["cause"] == "com_outside_support"]
    return {
        "frames": steps,
        "com_outside_support_step": int(left["step"].iloc[0]) if len(left) else float("nan"),
        **fs.body_a_numbers(table, POLICIES),
        **_paper_against_off(table, a_events),
    }


def _paper_against_off(table, a_events):
    """What the paper's prose says of A under ``paper`` against ``off``, read from the run: how
    far A ends along its slide beyond where off's A ends (m, < 0: short of it), and, over A's
    first stay on one vertex (VS: the steps from entering it to the next event), how far A
    turned under each (rad). Written from a reading of the figure until 2026-12-07, the text
    said "turning more slowly ... ends short"; the run had it turn faster and end 0.078 m
    beyond."""
    a = {p: fs.bodies(table, p).query("name == 'A'").set_index("step") for p in ("paper", "off")}
    last = int(table["step"].max())
    along = np.sign(a["off"].loc[last, "x"] - a["off"].loc[0, "x"])
    out = {
        "paper_end_beyond_off_m": float(
            along * (a["paper"].loc[last, "x"] - a["off"].loc[last, "x"])
        )
    }
    steps = [int(s) for s in a_events["step"]]
    vs = [k for k, c in enumerate(a_events["cause"]) if c == "one_vertex_on_floor"]
    if vs and vs[0] + 1 < len(steps):
        start, end = steps[vs[0]], steps[vs[0] + 1]
        out["vs_steps"] = [start, end]
        out["vs_turn_rad"] = {
            p: float(abs(a[p].loc[end, "angle"] - a[p].loc[start, "angle"])) for p in a
        }
    return out


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
