"""Figure "fig_states": the seed's figure 1 rendered from a real run.

Question: do the paper's three states look as the seed draws them? seed_fig1 (sim/scenes.py): box A
flat on the floor (rotation-stable), box B standing on one corner tilted 30 degrees (vertical-stable
until it settles onto its face), box C in the air (free, the seed's "vertical-unstable"). Recorded
under paper (the figure) and extended and off (for comparison), 120 steps at dt 1/60.

    python -m experiments.fig_states [--quick]     (quick = the same run: it is tiny)
"""

from study import filmstrip
from sim import scenes

NAME = "fig_states"
main = filmstrip.experiment(NAME, __doc__, scenes.seed_fig1, ("paper", "extended", "off"), 120)

if __name__ == "__main__":
    main()
