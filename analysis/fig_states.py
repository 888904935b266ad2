"""Figure "fig_states": seed figure 1 from a real run — A rotation-stable, B vertical-stable, C
free.

Draws the first step of the paper run at which A, B and C are in exactly the seed's three states,
and the extended policy at the same step (it has no vertical-stable state: B is simply awake)."""

import matplotlib.pyplot as plt

from analysis import filmstrip as fs
from analysis import style

NAME = "fig_states"
SEED_STATES = (2, 1, 0)  # A rotation-stable, B vertical-stable, C free


def draw(table, meta):
    step = fs.first_step(table, "paper", lambda f: tuple(f["state"].astype(int)) == SEED_STATES)
    if step is None:
        raise RuntimeError("the paper run never shows the seed's three states at once")
    xlim, ylim = fs.extent(table[table["step"] <= step])
    fig, axes = plt.subplots(1, 2, figsize=(style.WIDTH, 1.9))
    for ax, policy in zip(axes, ("paper", "extended")):
        fs.draw_frame(ax, fs.bodies(table, policy, step), xlim=xlim, ylim=ylim)
        ax.set_title(f"{policy}, step {step} (t = {step * meta['parameters']['dt']:.2f} s)")
    fs.state_legend(fig, ncol=4, y=0.98)
    style.save_figure(fig, NAME)
    frame = fs.bodies(table, "paper", step).sort_values("body")
    return {
        "step": step,
        "time_s": step * meta["parameters"]["dt"],
        "states": dict(zip(frame["name"], (style.STATE_LABEL[s] for s in frame["state"]))),
        "frozen_at_step": {
            n: fs.nan_if_none(fs.frozen_step(table, "paper", n)) for n in frame["name"]
        },
        "extended_frozen_at_step": {
            n: fs.nan_if_none(fs.frozen_step(table, "extended", n)) for n in frame["name"]
        },
    }


main = style.entry(NAME, draw)

if __name__ == "__main__":
    main()
