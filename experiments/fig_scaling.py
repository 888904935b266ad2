"""Figure "fig_scaling" (figure 5): how step time grows with the awake and the frozen body count.

Question: what does one more awake body cost per step (a), and one more frozen body (b)? The model
is ms/step = a * N_awake + b * N_frozen + c; freezing is ideal when b = 0 (a frozen body costs
nothing), and the measured b/a says how far from that each system is.

Scenes: the mixes of bench_freeze part 2 (``study.protocols.mix_scene``): rest_row(N_frozen)
(unit boxes on the floor, frozen once the system freezes them) plus N_awake unit boxes in a block
(pitch 2 m, never touching) that start 3000 m up, thrown upwards so that they peak half way
through the timing (``study.protocols.mix_launch``), so they stay awake, slow and never touch
anything (checked: the awake count equals the design before and after the timing, and the lowest
flyer stays above 5 m; each mix's fastest flyer speed at the end is a row). Grid: N_frozen in
{0, 5000, 10000, 20000} x N_awake in {100, 200, 400, 800} (16 mixes), wide enough to draw a line per
fixed count. The frozen counts reach 20000 because a frozen body costs sim so little that with
{0, 1000, 2000, 4000} the fit's b was set by differences of a few microseconds between worlds
that do not grow with N_frozen (sim-extended: 17.9 us a step with no row and 21-22 us with any of
them, 100 flyers): b/a came out 0.010-0.012 +- 0.003, where 20000 frozen bodies against none,
timed side by side, add 0.03 ns a body a step (b/a 0.0003). The price: sim-off's a is not
resolved (800 flyers add ~0.08 ms to a step of ~10 ms with 20000 resting bodies solved); its b,
the cost of a solved resting body, is.

Systems: sim-extended (the row frozen within 2 steps), sim-off (nothing frozen: the row is
*solved*, so its "b" is the cost of a resting body that is solved, the cost freezing removes),
and pymunk-sleep (Chipmunk's sleeping, for comparison: the row put to sleep by its 0.5 s timer;
after the 10 warm-up steps it is stepped until only the flyers are solved, at most 2 s), and
box2d-sleep (Box2D 2.3's sleeping, the same way: its b2_timeToSleep is 0.5 s too).
sim-sleep is left out to keep within the time budget (building the worlds dominates the run): its
asleep bodies leave sim's awake list exactly as extended's frozen ones do, so its b is the same
mechanism measured twice. pybullet is left out: its deactivation takes 2 s and it costs ~30 ms
per step per 1000 awake boxes (fig_speedup).

Method (study.protocols.per_body_cost, bench_freeze's part 2): every world of the sweep is
built and settled first, then timed in 7 repeats of 50 steps, round-robin over all 48 worlds (order
reversed on every other repeat), the garbage collector paused, Numba kernels compiled before;
ms/step is the median over repeats. The fit is least squares over the 16 mixes of each system, with
standard errors of a, b, c and of b/a (delta method, with the a-b covariance), the RMS and largest
residual and R^2, and b/b_off, a/a_off against sim-off. The same fit is also made on each mix's
fastest repeat (scene "fit_min"): on a machine shared with other work, load spikes hit a few
repeats of some mixes, and the minimum is the estimate least touched by them; the figure shows the
median fit, the table both, so a disagreement between them is visible rather than hidden. The awake
bodies are the cheapest kind: no contacts, and slow (at most g dt (7 x 50 / 2) = 28.6 m/s, 0.48 m a
step, under the half-size step past which sim's continuous stage sweeps a body). Dropped from rest,
as they were until the study found it, they reached 57 m/s, sim swept each against its
neighbours in the block every step, and that sweep was most of sim's a (1.1-1.8 us a flyer
against ~0.1 us slow), so b/a came out several times too small for sim. dt
1/60 s; each engine at its own default solver settings (study.peers.DEFAULT_ITERATIONS: sim
its soft step with 4 substeps per step and 1 biased + 1 relax sweep per substep, pymunk 10
iterations per step); slop (sim) and collision_slop (pymunk) 0.005 m; every system's full settings
(``runner.settings``) are in the metadata's ``system_settings``.

Columns (long form, bench_freeze's): part ("per_body_cost"), scene (mix label, "fit" or
"fit_min"), system, bodies, n_awake, n_frozen (the mix's design), metric, value, unit, flag (""
when the awake-count and flight checks held). Fit rows: scene "fit" (medians) or "fit_min"
(fastest repeats), metric "fit_<key>".

    python -m experiments.fig_scaling [--quick]
writes results/data/fig_scaling.csv and fig_scaling.json (which also holds the fits). --quick:
N_frozen {0, 200, 400} x N_awake {20, 50}, 3 repeats of 10 steps.
"""

import pandas as pd
from tqdm import tqdm

import sim
from study.common import DT, SLOP, build, compile_kernels, entry
from study.cost_fit import fit_cost, relative_to_off
from study.protocols import (
    FALL_HEIGHT,
    FLY_PITCH,
    WARMUP_STEPS,
    flight_budget,
    mix_launch,
    per_body_cost,
)

NAME = "fig_scaling"
SYSTEMS = ("sim-extended", "sim-off", "pymunk-sleep", "box2d-sleep")

FULL = {
    "mix_frozen": (0, 5000, 10000, 20000),
    "mix_awake": (100, 200, 400, 800),
    "mix_steps": 50,
    "mix_settle_s": 2.0,
    "repeats": 7,
}
#: --quick: small enough for the test suite; each mix is timed over 40 steps (10 gave a frozen body
#: 0.21 of a solved one's cost in a fit on a loaded machine, CI on 8227c8e, against 0.012 in the
#: full run: the fit's slope over 400 frozen bodies is a few microseconds a step)
QUICK = {
    "mix_frozen": (0, 200, 400),
    "mix_awake": (20, 50),
    "mix_steps": 40,
    "mix_settle_s": 1.0,
    "repeats": 3,
}


def fit_fastest(rows):
    """system -> fit_cost over each mix's fastest repeat (ms_per_step_min), with
    b/b_off and a/a_off against sim-off as for the median fit."""
    t = pd.DataFrame(rows)
    t = t[
        (t["part"] == "per_body_cost") & (t["scene"] != "fit") & (t["metric"] == "ms_per_step_min")
    ]
    fits = {
        system: fit_cost(g["n_awake"], g["n_frozen"], g["value"])
        for system, g in t.groupby("system", sort=False)
    }
    return relative_to_off(fits)


def fit_min_rows(rows, fits_min):
    """The median fit's rows again, scene "fit_min", with the fastest-repeat fit's values."""
    out = []
    for row in rows:
        key = row["metric"][len("fit_") :]
        if row["scene"] == "fit" and key in fits_min[row["system"]]:
            out.append({**row, "scene": "fit_min", "value": fits_min[row["system"]][key]})
    return out


def run(config, args):
    compile_kernels()
    repeats = config["repeats"]
    n_worlds = len(config["mix_frozen"]) * len(config["mix_awake"]) * len(SYSTEMS)
    scenes = []
    with tqdm(total=n_worlds * repeats, desc=f"{NAME} timing", unit="repeat") as bar:
        rows, fits = per_body_cost(
            config,
            repeats,
            bar,
            systems=SYSTEMS,
            extra_units={"b_over_a_stderr": "ratio"},
            scenes_out=scenes,
        )
    fits_min = fit_fastest(rows)
    rows += fit_min_rows(rows, fits_min)
    probe = sim.scenes.single_box()
    settings = {}
    for system in SYSTEMS:
        with build(system, probe) as r:
            settings[system] = r.settings
    parameters = {
        "dt": DT,
        "slop": SLOP,
        "warmup_steps": WARMUP_STEPS,
        "fall_height_m": FALL_HEIGHT,
        "mix_launch_m_per_s": mix_launch(config, repeats),
        "fly_pitch_m": FLY_PITCH,
        "flight_budget_steps": flight_budget(),
        "systems": SYSTEMS,
        "model": "ms/step = a N_awake + b N_frozen + c",
        "fits": fits,
        "fits_min": fits_min,
        "system_settings": settings,
    }
    return pd.DataFrame(rows), scenes, parameters


main = entry(NAME, __doc__, FULL, QUICK, run)

if __name__ == "__main__":
    main()
