"""Figure "fig_edge_as_floor": the seed's figure 2 as a filmstrip.

Question: does a body landing on a frozen body's floor-parallel top edge treat that edge as a floor
(section 5.2), as the seed says? seed_fig2 (sim/scenes.py): box B rests on the floor, box A falls
from
2.5 m, tilted 10 degrees, onto B's top edge. Recorded under paper (the figure), extended and off,
120 steps at dt 1/60.

    python -m experiments.fig_edge_as_floor [--quick]     (quick = the same run: it is tiny)
"""

from study import filmstrip
from sim import scenes

NAME = "fig_edge_as_floor"
main = filmstrip.experiment(NAME, __doc__, scenes.seed_fig2, ("paper", "extended", "off"), 120)

if __name__ == "__main__":
    main()
