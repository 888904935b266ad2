"""The failure catalogue's slow slides: a box sliding slower than every sleep threshold
(``slow_sliding``), a hexagon gliding on ice (``slow_glide``), a box and a plank creeping down
slopes just steeper than their friction angle (``slope_creep``, ``slope_creep_plank``); each
builder with its classifier, measure and catalogue entry. All four are judged on the distance slid
as a fraction of what Coulomb friction gives, with the same four labels."""

import math

import numpy as np

import sim

from .record import G, Scenario


# ---- slow sliding -------------------------------------------------------------------------------
def slow_sliding(speed=0.04, friction=0.001):
    """``sim.scenes.sliding_box``: a unit box slides on the floor at ``speed`` m/s (below every
    system's sleep speed: sim-sleep 0.05 m/s, Chipmunk's idle speed g dt = 0.16 m/s, Bullet's
    sqrt(0.05) = 0.22 m/s, extended's rest speed 0.02 m/s is crossed halfway) with Coulomb
    friction ``friction`` (floor and box alike): it must travel v^2 / (2 mu g) = 8.2 cm at the
    defaults, stopping after v / (mu g) = 4.1 s.

    Danger: a slow body is not a resting one (engines' known limit, seed limit 1)."""
    scene = sim.scenes.sliding_box(speed=speed, friction=friction)
    scene.name = "slow_sliding"
    scene.bodies[0].name = "box"
    return scene


def slow_glide(speed=0.05, friction=0.002, radius=0.4):
    """``slow_sliding`` with other geometry: a hexagon (circumradius ``radius``, resting on a
    flat edge) glides on the floor at ``speed`` m/s with Coulomb friction ``friction`` (floor and
    body alike): v^2 / (2 mu g) = 6.4 cm at the defaults, stopping after v / (mu g) = 2.5 s; it
    is under extended's rest speed for its last 1.0 s.

    Danger: as slow_sliding's, for a body with more than one contact point and rotational
    inertia of its own."""
    body = sim.Body.regular(6, radius, velocity=(speed, 0.0), friction=friction, name="box")
    body.position = (0.0, radius * math.cos(math.pi / 6))
    return sim.Scene(
        bodies=[body],
        floor_friction=friction,
        name="slow_glide",
        params={"speed": speed, "friction": friction, "radius": radius},
    )


def _slide_expected(scene):
    v, mu = scene.params["speed"], scene.params["friction"]
    return v * v / (2.0 * mu * G)


def _slide_measure(scene, p, a):
    """Distance slid as a fraction of v^2 / (2 mu g)."""
    return float((p[0, 0] - scene.bodies[0].position[0]) / _slide_expected(scene))


def _fraction_outcome(fraction):
    if fraction < 0.1:
        return "stuck"
    if fraction < 0.9:
        return "stopped short"
    return "slid" if fraction <= 1.1 else "slid too far"


# ---- slope creep --------------------------------------------------------------------------------
def slope_creep(acceleration=0.05, friction=0.3, size=0.5, seconds=6.0):
    """A ``size`` box on a static ramp whose slope is just steeper than its friction angle, so it
    slides down from rest at a = g (sin(theta) - mu cos(theta)) = ``acceleration`` m/s^2 (theta =
    16.98 degrees at the defaults, friction atan(0.3) = 16.70 degrees): 0.9 m in 6 s, at 0.3 m/s at
    the end but only 0.025 m/s after 0.5 s.

    Danger: it accelerates slower than extended's rest_acceleration (0.1 m/s^2) and stays under
    every sleep speed for seconds (engines' known limit: sleeping on a slope)."""
    return _on_ramp(
        "slope_creep",
        acceleration,
        friction,
        size,
        size,
        {"acceleration": acceleration, "friction": friction, "size": size, "seconds": seconds},
    )


def _on_ramp(name, acceleration, friction, width, height, params):
    """A ``width`` x ``height`` box at rest on a static ramp steep enough that it slides down at
    ``acceleration`` m/s^2 with Coulomb friction ``friction``; ``params`` plus the slope
    (theta_rad) are the scene's parameters."""
    # solve sin(t) - mu cos(t) = a / g for t by Newton's method (a few steps from atan(mu))
    theta = math.atan(friction)
    for _ in range(20):
        theta -= (math.sin(theta) - friction * math.cos(theta) - acceleration / G) / (
            math.cos(theta) + friction * math.sin(theta)
        )
    length = 10.0
    top = length * math.tan(theta)
    ramp = sim.Body(
        vertices=[(0.0, 0.0), (length, 0.0), (0.0, top)], friction=friction, name="ramp"
    )
    along = 2.0  # m from the ramp's top corner, down the slope
    surface = np.array([along * math.cos(theta), top - along * math.sin(theta)])
    normal = np.array([math.sin(theta), math.cos(theta)])
    centre = surface + 0.5 * height * normal
    box = sim.Body.box(
        width, height, position=tuple(centre), angle=-theta, friction=friction, name="box"
    )
    return sim.Scene(
        bodies=[box], static_bodies=[ramp], name=name, params={**params, "theta_rad": theta}
    )


def slope_creep_plank(acceleration=0.03, friction=0.5, width=1.2, height=0.25, seconds=6.0):
    """``slope_creep`` with other geometry: a long low plank (``width`` x ``height``) on a ramp
    whose slope is just steeper than a higher friction's angle (atan(0.5) = 26.57 degrees), so it
    slides from rest at a = ``acceleration`` m/s^2: 0.54 m in 6 s, under 0.02 m/s for 0.7 s.

    Danger: as slope_creep's, for a body whose supports are far apart (a wide contact holds no
    better against sliding)."""
    return _on_ramp(
        "slope_creep_plank",
        acceleration,
        friction,
        width,
        height,
        {
            "acceleration": acceleration,
            "friction": friction,
            "width": width,
            "height": height,
            "seconds": seconds,
        },
    )


def _slope_measure(scene, p, a):
    """Distance slid down the slope as a fraction of a t^2 / 2."""
    theta = scene.params["theta_rad"]
    dx, dy = p[0] - np.asarray(scene.bodies[0].position)
    travelled = float(dx * math.cos(theta) - dy * math.sin(theta))  # along the slope, down
    t = scene.params["seconds"]
    return travelled / (0.5 * scene.params["acceleration"] * t * t)


# ---- the catalogue's entries --------------------------------------------------------------------
SLOW_SLIDING = Scenario(
    "slow_sliding",
    "a body sliding slower than the sleep thresholds (engines' sleep; seed limit 1)",
    slow_sliding,
    6.0,
    "slid",
    ("stuck", "stopped short", "slid", "slid too far"),
    lambda sc, p, a: _fraction_outcome(_slide_measure(sc, p, a)),
    _slide_measure,
    "slide_fraction",
)


SLOPE_CREEP = Scenario(
    "slope_creep",
    "a body creeping down a slope just past its friction angle (engines' sleep)",
    slope_creep,
    6.0,
    "slid",
    ("stuck", "stopped short", "slid", "slid too far"),
    lambda sc, p, a: _fraction_outcome(_slope_measure(sc, p, a)),
    _slope_measure,
    "slide_fraction",
)


SLOW_GLIDE = Scenario(
    "slow_glide",
    "slow_sliding with a hexagon on near-frictionless ice",
    slow_glide,
    4.0,
    "slid",
    ("stuck", "stopped short", "slid", "slid too far"),
    lambda sc, p, a: _fraction_outcome(_slide_measure(sc, p, a)),
    _slide_measure,
    "slide_fraction",
)


SLOPE_CREEP_PLANK = Scenario(
    "slope_creep_plank",
    "slope_creep with a wide plank and a higher friction",
    slope_creep_plank,
    6.0,
    "slid",
    ("stuck", "stopped short", "slid", "slid too far"),
    lambda sc, p, a: _fraction_outcome(_slope_measure(sc, p, a)),
    _slope_measure,
    "slide_fraction",
)
