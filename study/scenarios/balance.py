"""The failure catalogue's tipping and lost equilibrium: a body sliding off its support's edge
(``overhang``, seed figure 3), a box on its corner with its centre of mass outside (``tipping``), a
plank or block just past its support's edge (``unstable_equilibrium``, ``unstable_ledge``) and
three boxes whose top two are past the bottom's edge (``three_bodies``); each builder with its
classifier, measure and catalogue entry."""

import math

import sim

from .record import Scenario, bottom, index, wrap


# ---- overhang (seed figure 3) -------------------------------------------------------------------
def overhang(speed=2.5, friction=0.2):
    """Seed figure 3 (``sim.scenes.seed_fig3``): A (0.8 x 0.4) rests on B (2 x 1) and slides right
    at ``speed`` m/s with friction ``friction``; it would slide v^2 / (2 mu g) = 1.6 m on an
    endless surface, so its centre of mass passes B's edge (0.9 m away) and it falls to the floor.

    Danger: the seed's rule for it (section 5.2) exists; sleeping sees a body slow near the edge."""
    scene = sim.scenes.seed_fig3(speed=speed, friction=friction)
    scene.name = "overhang"
    return scene


def _overhang_measure(scene, p, a):
    return float(p[index(scene, "A"), 1])


def _overhang_outcome(scene, p, a):
    return "fell off" if _overhang_measure(scene, p, a) < 1.0 else "stayed on"  # B's top: 1 m


# ---- tipping ------------------------------------------------------------------------------------
def tipping(width=0.5, height=2.0, past_deg=5.0, friction=0.6):
    """A ``width`` x ``height`` box starts at rest standing on one corner, tilted ``past_deg``
    beyond its tipping angle atan(width / height) (14.0 degrees), so its centre of mass is outside
    its support (the corner): it must topple onto its long side (|angle| -> 90 degrees).

    Danger: it starts at rest, slow at first (seed limit 1, no general rest test)."""
    angle = math.atan(width / height) + math.radians(past_deg)
    lowest = -0.5 * width * math.sin(angle) - 0.5 * height * math.cos(angle)
    body = sim.Body.box(
        width, height, position=(0.0, -lowest), angle=angle, friction=friction, name="box"
    )
    return sim.Scene(
        bodies=[body],
        name="tipping",
        params={"width": width, "height": height, "past_deg": past_deg, "friction": friction},
    )


def _tipping_measure(scene, p, a):
    return float(abs(wrap(a[0])))


def _tipping_outcome(scene, p, a):
    tilt = _tipping_measure(scene, p, a)
    if tilt > math.radians(75.0):
        return "toppled"
    return "upright" if tilt < math.radians(5.0) else "stuck leaning"


# ---- unstable equilibrium -----------------------------------------------------------------------
def unstable_equilibrium(past=0.002, length=2.0, thickness=0.2, friction=0.6):
    """A plank (``length`` x ``thickness``) lies on a 1 x 1 m box with its centre of mass ``past``
    m beyond the box's right edge. No support point is under its centre of mass, so it must tip
    about the edge: slowly at first (tilt ~ (past / (thickness / 2)) (cosh(k t) - 1), k = 1.7/s:
    0.5 rad after ~2.3 s for 2 mm), then it slides off and falls.

    Danger: for the first second it moves less than every sleep threshold (engines' known limit,
    seed limit 1)."""
    support = sim.Body.box(1.0, 1.0, position=(0.0, 0.5), friction=friction, name="support")
    plank = sim.Body.box(
        length,
        thickness,
        position=(0.5 + past, 1.0 + 0.5 * thickness),
        friction=friction,
        name="plank",
    )
    return sim.Scene(
        bodies=[support, plank],
        name="unstable_equilibrium",
        params={"past": past, "length": length, "thickness": thickness, "friction": friction},
    )


def unstable_ledge(past=0.001, length=1.5, thickness=0.3, friction=0.6):
    """``unstable_equilibrium`` with other geometry: a thicker block (``length`` x ``thickness``)
    lies on a static ledge (a 1 x 1 m static box) with its centre of mass ``past`` m beyond the
    ledge's edge. Its support cannot move, so only the block's own rest test decides: it must tip
    about the edge, slowly at first (as the plank does), and fall.

    Danger: as unstable_equilibrium's, on an immovable support: the block is slow for a second
    or more, and rests on two points (a whole face), not one."""
    ledge = sim.Body.box(1.0, 1.0, position=(0.0, 0.5), friction=friction, name="ledge")
    block = sim.Body.box(
        length,
        thickness,
        position=(0.5 + past, 1.0 + 0.5 * thickness),
        friction=friction,
        name="plank",
    )
    return sim.Scene(
        bodies=[block],
        static_bodies=[ledge],
        name="unstable_ledge",
        params={"past": past, "length": length, "thickness": thickness, "friction": friction},
    )


def _unstable_measure(scene, p, a):
    """How far the plank's centre dropped, m."""
    plank = index(scene, "plank")
    return float(scene.bodies[plank].position[1] - p[plank, 1])


def _unstable_outcome(scene, p, a):
    """ "tipped off": the plank came down to the floor (one end, or all of it, on it); "balanced":
    still flat on the box; "stuck tilted": tilted yet touching nothing but the box's corner,
    which cannot be a resting pose (it was frozen mid-tip)."""
    plank = index(scene, "plank")
    if bottom(scene, p, a, plank) < 0.02:
        return "tipped off"
    return "balanced" if abs(wrap(a[plank])) < 0.05 else "stuck tilted"


# ---- three bodies -------------------------------------------------------------------------------
def three_bodies(offset=0.4, width=1.0, thickness=0.5):
    """Three ``width`` x ``thickness`` boxes stacked like a staircase, each ``offset`` m right of
    the one below: each centre of mass is over the box directly below it (the seed's two-body
    test passes for every pair), but the top two together have their centre of mass at 1.5
    ``offset`` = 0.6 m, beyond the bottom box's edge at 0.5 m, so the top two must topple off.

    Danger: the seed's third limit, collisions among three or more bodies are not handled."""
    bodies = [
        sim.Body.box(
            width,
            thickness,
            position=(k * offset, (k + 0.5) * thickness),
            friction=0.6,
            name=f"box {k}",
        )
        for k in range(3)
    ]
    return sim.Scene(
        bodies=bodies,
        name="three_bodies",
        params={"offset": offset, "width": width, "thickness": thickness},
    )


def _three_measure(scene, p, a):
    """How far the top box's centre dropped, m."""
    return float(scene.bodies[2].position[1] - p[2, 1])


def _three_outcome(scene, p, a):
    return "toppled" if _three_measure(scene, p, a) > 0.5 * scene.params["thickness"] else "stood"


# ---- the catalogue's entries --------------------------------------------------------------------
OVERHANG = Scenario(
    "overhang",
    "seed figure 3: a body sliding off its support's edge",
    overhang,
    4.0,
    "fell off",
    ("fell off", "stayed on"),
    _overhang_outcome,
    _overhang_measure,
    "A_height_m",
)


TIPPING = Scenario(
    "tipping",
    "a body at rest on a corner, centre of mass outside (seed limit 1)",
    tipping,
    4.0,
    "toppled",
    ("toppled", "upright", "stuck leaning"),
    _tipping_outcome,
    _tipping_measure,
    "tilt_rad",
)


UNSTABLE_EQUILIBRIUM = Scenario(
    "unstable_equilibrium",
    "a plank 2 mm past its support's edge tips slowly at first (engines' sleep; seed limit 1)",
    unstable_equilibrium,
    6.0,
    "tipped off",
    ("tipped off", "balanced", "stuck tilted"),
    _unstable_outcome,
    _unstable_measure,
    "plank_drop_m",
)


UNSTABLE_LEDGE = Scenario(
    "unstable_ledge",
    "unstable_equilibrium on an immovable ledge: a block 1 mm past its edge",
    unstable_ledge,
    6.0,
    "tipped off",
    ("tipped off", "balanced", "stuck tilted"),
    _unstable_outcome,
    _unstable_measure,
    "plank_drop_m",
)


THREE_BODIES = Scenario(
    "three_bodies",
    "three bodies: the top two together past the bottom's edge (seed limit 3)",
    three_bodies,
    3.0,
    "toppled",
    ("toppled", "stood"),
    _three_outcome,
    _three_measure,
    "top_drop_m",
)
