"""The failure catalogue's impacts and lost supports: a load whose support is knocked away
(``support_removed``), a projectile hitting a frozen column (``impact_on_stack``), a load landing
on a frozen plank's overhang (``load_on_overhang``), a row of frozen dominoes woken one by one
(``wake_cascade``); each builder with its classifier, measure and catalogue entry. Every
projectile is scheduled: it slides on something frictionless and arrives at ``arrive_s``."""

import numpy as np

import sim

from .record import ARRIVE_S, Scenario, bottom, index, world_vertices, wrap

SHELF_THICKNESS = 0.2  # m, static shelves a projectile slides along
SHELF_GAP = 0.05  # m, between a shelf's end and the body it leads to


def _shelf(x_from, x_to, top):
    """A static, frictionless shelf from x_from to x_to (m) whose top face is at ``top``."""
    return sim.Body.box(
        x_to - x_from,
        SHELF_THICKNESS,
        position=(0.5 * (x_from + x_to), top - 0.5 * SHELF_THICKNESS),
        friction=0.0,
        name="shelf",
    )


# ---- support removed ----------------------------------------------------------------------------
def support_removed(speed=4.0, arrive_s=ARRIVE_S, load_friction=0.05):
    """A load (0.8 x 0.4 m) rests on a support (1 x 1 m box, mu 0.6); a heavy low projectile
    (1.0 x 0.3 m, 3 kg, friction 0) slides along the floor at ``speed`` m/s and hits the support's
    foot at ``arrive_s``. The support and projectile leave together (inelastic: 3 m/s at the
    defaults, decelerated by the support's floor friction over ~3 m). The load is nearly
    frictionless (``load_friction`` 0.05: 0.17 with the support, geometric mean), so the support
    is pulled from under it as a tablecloth is (friction drags the load at most
    mu g t^2 / 2 = 8 cm in the 0.3 s the support takes to pass), and it must fall 1 m to the floor
    (the projectile, low and fast, has passed before the load comes down to its height).

    Why 0.05 and not 0 (it was 0 before solver v2): a load resting on a frictionless support keeps
    whatever horizontal velocity the solve leaves it, and solver v2 leaves round-off (1e-22 m/s);
    ``paper`` freezes a rotation-stable body only once Coulomb friction has stopped it, so with
    mu = 0 it slid at 1e-22 m/s for ever and was never frozen: the danger met no frozen load.
    Any friction stops it within a step. The question is the same: the support is still pulled
    from under the load, and the load must still fall.

    Danger: nothing touches the load; only its support moves (the seed's second limit: nothing
    wakes a body whose support is knocked away, it floats)."""
    gap = speed * arrive_s
    bodies = [
        sim.Body.box(1.0, 1.0, position=(0.0, 0.5), friction=0.6, name="support"),
        sim.Body.box(0.8, 0.4, position=(0.0, 1.2), friction=load_friction, name="load"),
        sim.Body.box(
            1.0,
            0.3,
            position=(-0.5 - gap - 0.5, 0.15),
            velocity=(speed, 0.0),
            friction=0.0,
            density=10.0,
            name="projectile",
        ),
    ]
    return sim.Scene(
        bodies=bodies,
        name="support_removed",
        params={"speed": speed, "arrive_s": arrive_s, "load_friction": load_friction},
    )


def _support_removed_outcome(scene, p, a):
    load, support = index(scene, "load"), index(scene, "support")
    low = bottom(scene, p, a, load)
    if low < 0.05:
        return "fell"
    s = world_vertices(scene, support, p[support], a[support])
    under = s[:, 0].min() <= p[load, 0] <= s[:, 0].max() and abs(s[:, 1].max() - low) < 0.05
    return "stayed" if under else "floating"


# ---- impact on a frozen stack -------------------------------------------------------------------
def impact_on_stack(height=4, speed=4.0, arrive_s=ARRIVE_S, projectile_density=12.0):
    """A column of ``height`` unit boxes (mu 0.6); a heavy projectile (0.5 x 0.5 m, 3 kg at the
    defaults) slides along a frictionless static shelf level with the top box's base and hits the
    top box's lower half at ``speed`` m/s at ``arrive_s``. Its momentum (12 N s), delivered 3.25 m
    up a 4 kg column, tips the whole column over about the bottom box's far corner: every box,
    the bottom one included, ends on the floor (checked at dt/8).

    Danger: a hit on one frozen body must wake it and pass its momentum down through bodies that
    are not hit (seed section 3: a rotation-stable body is special only until a collision; its
    second limit: nothing else wakes a body)."""
    top = float(height - 1)  # m, the top box's base
    gap = speed * arrive_s
    bodies = [
        sim.Body.box(1.0, 1.0, position=(0.0, 0.5 + k), friction=0.6, name=f"box {k}")
        for k in range(height)
    ]
    x_face = -0.5 - gap  # the projectile's front face at t = 0
    bodies.append(
        sim.Body.box(
            0.5,
            0.5,
            position=(x_face - 0.25, top + 0.25),
            velocity=(speed, 0.0),
            friction=0.6,
            density=projectile_density,
            name="projectile",
        )
    )
    shelf = _shelf(x_face - 1.0, -0.5 - SHELF_GAP, top)
    return sim.Scene(
        bodies=bodies,
        static_bodies=[shelf],
        name="impact_on_stack",
        params={
            "height": height,
            "speed": speed,
            "arrive_s": arrive_s,
            "projectile_density": projectile_density,
        },
    )


def _moved(scene, p, a, i):
    """How far body i's centre moved from its start, m."""
    return float(np.hypot(*(p[i] - np.asarray(scene.bodies[i].position))))


def _impact_measure(scene, p, a):
    """How far the column's bottom box moved, m."""
    return _moved(scene, p, a, 0)


def _impact_outcome(scene, p, a):
    """A box "moved" if its centre moved 0.1 m or it turned 0.1 rad. "toppled": the bottom box
    moved (the column went over as a whole); "stood": nothing moved; "top knocked off": only the
    top box moved; "base stayed": boxes above the bottom one moved, the bottom one did not (the
    column broke above a base that never woke)."""
    height = scene.params["height"]
    moved = [_moved(scene, p, a, k) > 0.1 or abs(wrap(a[k])) > 0.1 for k in range(height)]
    if moved[0]:
        return "toppled"
    if not any(moved):
        return "stood"
    return "top knocked off" if not any(moved[:-1]) else "base stayed"


# ---- load on an overhang ------------------------------------------------------------------------
def load_on_overhang(speed=2.0, arrive_s=ARRIVE_S, length=3.0, com_inside=0.2):
    """A plank (``length`` x 0.2 m, 0.6 kg) lies on a column of two unit boxes, overhanging to the
    right, its centre of mass ``com_inside`` m inside the column's edge (it rests). A 1 kg load
    (0.5 x 0.5 m, mu 0.6) slides in from the right along a frictionless static shelf 1 cm above
    the plank's top and onto the plank's overhanging end at ``arrive_s``, where friction stops it
    within 0.35 m: its weight ~1 m beyond the edge outweighs the plank's 0.2 m inside (moment
    ~10 N m against 1.2 N m), so the plank must tip over the edge.

    Danger: the seed treats a rotation-stable body's floor-parallel top edge "exactly like the
    floor" (section 5.2), so a body landing on it never loads it; and a load on an overhang is a
    three-body problem (plank, column, load)."""
    top = 2.2  # m, the plank's top face
    plank_x = 0.5 - com_inside  # the column's right edge is at x = 0.5
    x_end = plank_x + 0.5 * length  # the plank's overhanging end
    gap = speed * arrive_s
    shelf_from = x_end + SHELF_GAP
    bodies = [
        sim.Body.box(1.0, 1.0, position=(0.0, 0.5), friction=0.6, name="box 0"),
        sim.Body.box(1.0, 1.0, position=(0.0, 1.5), friction=0.6, name="box 1"),
        sim.Body.box(length, 0.2, position=(plank_x, top - 0.1), friction=0.6, name="plank"),
        sim.Body.box(
            0.5,
            0.5,
            position=(x_end + gap + 0.25, top + 0.01 + 0.25),
            velocity=(-speed, 0.0),
            friction=0.6,
            density=4.0,
            name="projectile load",
        ),
    ]
    shelf = _shelf(shelf_from, x_end + gap + 1.5, top + 0.01)
    return sim.Scene(
        bodies=bodies,
        static_bodies=[shelf],
        name="load_on_overhang",
        params={"speed": speed, "arrive_s": arrive_s, "length": length, "com_inside": com_inside},
    )


def _plank_tilt(scene, p, a):
    return float(abs(wrap(a[index(scene, "plank")])))


def _load_outcome(scene, p, a):
    """ "tipped": the plank's centre dropped 0.2 m or it turned 0.2 rad; else "held"."""
    plank = index(scene, "plank")
    dropped = scene.bodies[plank].position[1] - p[plank, 1]
    return "tipped" if dropped > 0.2 or _plank_tilt(scene, p, a) > 0.2 else "held"


# ---- wake cascade -------------------------------------------------------------------------------
def wake_cascade(
    n=8, pitch=0.6, width=0.15, height=1.0, speed=2.0, arrive_s=ARRIVE_S, projectile_density=12.0
):
    """A row of ``n`` dominoes (``width`` x ``height``, mu 0.6, ``pitch`` apart); a small, dense
    projectile (0.25 x 0.25 m, 0.75 kg at the defaults: 1.5 N s at 2 m/s, above both policies'
    impulse thresholds, so the first domino is woken by every policy) slides along a frictionless
    static shelf whose top is at 0.7 ``height`` and strikes the first domino high up at
    ``arrive_s``, tipping it onto the next: each falling domino tips the next, and all must fall
    (pitch < height).

    Danger: every domino must be woken by its neighbour's fall, a weak, slow impact (a falling
    domino carries ~0.1 N s, under both impulse thresholds), through the whole row."""
    gap = speed * arrive_s
    shelf_top = 0.7 * height
    bodies = [
        sim.Body.box(
            width, height, position=(k * pitch, 0.5 * height), friction=0.6, name=f"domino {k}"
        )
        for k in range(n)
    ]
    x_face = -0.5 * width - gap
    bodies.append(
        sim.Body.box(
            0.25,
            0.25,
            position=(x_face - 0.125, shelf_top + 0.125),
            velocity=(speed, 0.0),
            friction=0.6,
            density=projectile_density,
            name="projectile",
        )
    )
    shelf = _shelf(x_face - 1.0, -0.5 * width - SHELF_GAP, shelf_top)
    return sim.Scene(
        bodies=bodies,
        static_bodies=[shelf],
        name="wake_cascade",
        params={
            "n": n,
            "pitch": pitch,
            "width": width,
            "height": height,
            "speed": speed,
            "arrive_s": arrive_s,
            "projectile_density": projectile_density,
        },
    )


def _dominoes_fallen(scene, p, a):
    """How many dominoes lean more than 0.2 rad (11 degrees; one resting on the next leans
    asin((pitch - width) / height) = 27 degrees, a standing one 0)."""
    n = scene.params["n"]
    return int(np.count_nonzero(np.abs(wrap(a[:n])) > 0.2))


def _cascade_outcome(scene, p, a):
    n = scene.params["n"]
    k = _dominoes_fallen(scene, p, a)
    if k == n:
        return "all fell"
    return "none fell" if k == 0 else "some fell"


# ---- the catalogue's entries --------------------------------------------------------------------
SUPPORT_REMOVED = Scenario(
    "support_removed",
    "a support knocked away from under a frozen load (seed limit 2: no way back to motion)",
    support_removed,
    6.0,
    "fell",
    ("fell", "stayed", "floating"),
    _support_removed_outcome,
    lambda sc, p, a: bottom(sc, p, a, index(sc, "load")),
    "load_bottom_m",
    event_s=ARRIVE_S,
)


IMPACT_ON_STACK = Scenario(
    "impact_on_stack",
    "a projectile hits a frozen stack's top box (seed section 3)",
    impact_on_stack,
    6.0,
    "toppled",
    ("toppled", "stood", "top knocked off", "base stayed"),
    _impact_outcome,
    _impact_measure,
    "base_moved_m",
    event_s=ARRIVE_S,
)


LOAD_ON_OVERHANG = Scenario(
    "load_on_overhang",
    "a load lands on a frozen plank's overhanging end (seed "
    "5.2: an edge treated as the floor; three bodies)",
    load_on_overhang,
    6.0,
    "tipped",
    ("tipped", "held"),
    _load_outcome,
    _plank_tilt,
    "plank_tilt_rad",
    event_s=ARRIVE_S,
)


WAKE_CASCADE = Scenario(
    "wake_cascade",
    "a row of frozen dominoes, each woken by its neighbour's fall",
    wake_cascade,
    7.0,
    "all fell",
    ("all fell", "some fell", "none fell"),
    _cascade_outcome,
    _dominoes_fallen,
    "dominoes_fallen",
    event_s=ARRIVE_S,
)
