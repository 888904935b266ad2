"""Figure "fig_overhang": the seed's figure 3, filmstrip plus state timeline.

Question: when the upper body slides until no support point lies under its centre of mass, does it
leave the rotation-stable state, as the seed's figure 3 says (it becomes vertical-unstable), and
fall off the edge? seed_fig3
(sim/scenes.py): A (0.8 x 0.4 m) rests on B (2 x 1 m) and slides right at 2.5 m/s with friction
0.2, so it passes B's edge and tips off. Recorded under paper (the figure), extended and off (the
reference the frozen runs should match), 240 steps at dt 1/60.

    python -m experiments.fig_overhang [--quick]     (quick = the same run: it is tiny)
"""

from study import filmstrip
from sim import scenes

NAME = "fig_overhang"
main = filmstrip.experiment(NAME, __doc__, scenes.seed_fig3, ("paper", "extended", "off"), 240)

if __name__ == "__main__":
    main()
