"""The failure catalogue's scenarios: small scenes where freezing resting bodies can go wrong, each
with the outcome physics expects and a classifier that reads the outcome off a final pose.

Every scenario is built from ``sim.Body`` / ``sim.Scene`` with only what its question needs, and is
a ``Scenario``: ``build(**overrides)`` (the scene; keyword overrides change its parameters, for the
later study of numerical extremes), ``seconds`` it runs (``duration(scene)``), ``event_s`` when
the danger arrives, ``classify(scene, positions, angles)`` -> an outcome label (one of
``labels``), ``measure(scene, positions, angles)`` -> the one continuous quantity the label is
judged on (``measure_name``, unit in the name) and ``expected``, the label physics says. Every body
is named; ``key_bodies(scene)`` are all but those named "projectile..." (the bodies the question
is about: pose errors are taken over them).

The dangers come from the seed paper's own admitted limits (``docs/seed/translation.md`` section
6: no general rest test, no way back to motion, two bodies only; and section 5.2: a
rotation-stable body's edge parallel to the floor, struck by a vertical-unstable body, is treated
as the floor is) and from the engines' known ones (a body
is put to sleep when it is merely slow: slow sliding, creeping down a slope, tipping slowly out of
an unstable equilibrium).

Anything that must happen *after everything froze* is scheduled by time, since runners cannot be
edited mid-run: a projectile starts far away and slides towards its target on a frictionless
surface (the floor, for a projectile of friction 0, since pairs mix friction by geometric mean; or
a static shelf of friction 0), so it arrives at ``arrive_s`` (default 3.5 s: after Bullet's fixed
2 s of deactivation time, the slowest sleeper of the study, plus time to settle). A projectile
sliding at constant speed arrives at the same time in every engine (Chipmunk's integration order
moves it v dt further, 0.07 m at 4 m/s: 17 ms earlier), which a falling or thrown one would not.

Scenarios (each builder's docstring has its geometry and the physics of its expected outcome):

    support_removed       a load resting on a support that a projectile knocks away  -> fell
    overhang              seed figure 3: A slides off B's edge                       -> fell off
    tipping               a tall box at rest on its corner, centre of mass outside   -> toppled
    unstable_equilibrium  a plank whose centre of mass is 2 mm past its support edge -> tipped off
    slow_sliding          a box sliding slower than every sleep threshold            -> slid
    slope_creep           a box creeping down a slope just steeper than friction     -> slid
    impact_on_stack       a projectile hits the top box of a frozen 4-box column     -> toppled
    load_on_overhang      a load slides onto the overhanging end of a frozen plank   -> tipped
    wake_cascade          a projectile tips the first of a row of frozen dominoes    -> all fell
    three_bodies          three boxes, each over the one below, the top two together
                          past the bottom's edge (the seed's two-body rule passes)    -> toppled
    unstable_ledge        unstable_equilibrium's danger on a static ledge: a block   -> tipped off
    slow_glide            slow_sliding's danger with a hexagon on ice                -> slid
    slope_creep_plank     slope_creep's danger with a wide plank, higher friction    -> slid

The last three repeat a danger with other geometry: they were added when ``extended``'s rest test
became a certificate of equilibrium (it fixed the first of each kind), to check the fix is not
tied to one scene.

Units: metres, seconds, kilograms (per square metre for densities), radians.

The package: ``record`` (the ``Scenario`` record, the shared constants, the geometry of a final
pose), the builders with their classifiers and catalogue entries grouped by danger (``impacts``:
supports knocked away and projectiles; ``slides``: slow sliding and creep; ``balance``: tipping and
equilibria), and here the catalogue in its order (``SCENARIOS``, ``get``). Every name listed in
``__all__`` is importable from ``study.scenarios``.
"""

from . import balance, impacts, slides
from .balance import overhang, three_bodies, tipping, unstable_equilibrium, unstable_ledge
from .impacts import (
    SHELF_GAP,
    SHELF_THICKNESS,
    impact_on_stack,
    load_on_overhang,
    support_removed,
    wake_cascade,
)
from .record import (
    ARRIVE_S,
    G,
    Scenario,
    bottom,
    index,
    key_bodies,
    world_vertices,
    wrap,
)
from .slides import slope_creep, slope_creep_plank, slow_glide, slow_sliding

__all__ = [
    "ARRIVE_S",
    "G",
    "SCENARIOS",
    "SHELF_GAP",
    "SHELF_THICKNESS",
    "Scenario",
    "bottom",
    "get",
    "impact_on_stack",
    "index",
    "key_bodies",
    "load_on_overhang",
    "overhang",
    "slope_creep",
    "slope_creep_plank",
    "slow_glide",
    "slow_sliding",
    "support_removed",
    "three_bodies",
    "tipping",
    "unstable_equilibrium",
    "unstable_ledge",
    "wake_cascade",
    "world_vertices",
    "wrap",
]

#: name -> Scenario, in the catalogue's order (the order of the table's rows)
SCENARIOS = {
    s.name: s
    for s in (
        impacts.SUPPORT_REMOVED,
        balance.OVERHANG,
        balance.TIPPING,
        balance.UNSTABLE_EQUILIBRIUM,
        slides.SLOW_SLIDING,
        slides.SLOPE_CREEP,
        balance.UNSTABLE_LEDGE,
        slides.SLOW_GLIDE,
        slides.SLOPE_CREEP_PLANK,
        impacts.IMPACT_ON_STACK,
        impacts.LOAD_ON_OVERHANG,
        impacts.WAKE_CASCADE,
        balance.THREE_BODIES,
    )
}


def get(name):
    """The scenario called ``name``; a clear error for an unknown one."""
    try:
        return SCENARIOS[name]
    except KeyError:
        raise ValueError(
            f"unknown scenario {name!r}; choose one of {', '.join(SCENARIOS)}"
        ) from None
