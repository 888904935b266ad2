"""Figure "fig_edge_as_floor": seed figure 2 as a filmstrip — A lands on frozen B's top edge.

Top row paper, bottom row extended, at the same steps: the start, just before A touches B, each
step at which A's paper state changes, and the end; dashed outlines are the off run."""

import matplotlib.pyplot as plt

from analysis import filmstrip as fs
from analysis import style

NAME = "fig_edge_as_floor"
POLICIES = ("paper", "extended")


def draw(table, meta):
    dt = meta["parameters"]["dt"]
    a_events = fs.events(table, "paper", "A")
    last = int(table["step"].max())
    change_steps = sorted(set(int(s) for s in a_events["step"]))
    frozen_a = fs.frozen_step(table, "paper", "A")
    steps = sorted(
        set(
            [0, max(0, change_steps[0] - 8) if change_steps else 0]
            + change_steps
            + ([frozen_a] if frozen_a is not None else [])
            + [last]
        )
    )
    xlim, ylim = fs.extent(table)
    fig, axes = plt.subplots(len(POLICIES), len(steps), figsize=(style.WIDTH, 3.2), squeeze=False)
    for r, policy in enumerate(POLICIES):
        for c, step in enumerate(steps):
            ax = axes[r, c]
            fs.draw_frame(
                ax,
                fs.bodies(table, policy, step),
                ghost=fs.bodies(table, "off", step),
                xlim=xlim,
                ylim=ylim,
            )
            ax.set_title(f"step {step}" if r == 0 else "", fontsize=7)
            if c == 0:
                ax.set_ylabel(policy)
            if c > 0:
                ax.set_yticklabels([])
    fs.state_legend(fig, ghost=True, y=0.97)
    style.save_figure(fig, NAME)
    return {
        "frames": steps,
        "time_of_frame_s": [s * dt for s in steps],
        **fs.body_a_numbers(table, POLICIES),
    }


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
