"""Canonical scene builders, shared by tests, experiments and recordings.

Every builder returns a ``sim.Scene`` whose ``name`` and ``params`` record how it was built, and
places bodies exactly touching (never overlapping) so runs start without a correction kick.
Units: metres, kilograms per square metre, seconds.
"""

import math

import numpy as np

from .arguments import count, positive
from .body import Body
from .scene import Scene


def _scene(name, bodies, params, **kwargs):
    return Scene(bodies=bodies, name=name, params=params, **kwargs)


def _counts(builder, minimum=1, **values):
    """Check the builder's counts (integers >= ``minimum``), naming the builder: a float count
    (pyramid(2.5)) or text met Python's TypeError deep inside, and drop(-1) a math domain error."""
    for name, value in values.items():
        count(value, f"{builder}: {name}", minimum)


def _lengths(builder, allow_zero=False, **values):
    """Check the builder's lengths (finite numbers > 0, or >= 0 with ``allow_zero``)."""
    for name, value in values.items():
        positive(value, f"{builder}: {name}", allow_zero)


def single_box(size=1.0, friction=0.6, density=1.0):
    """One square box resting on the floor."""
    _lengths("single_box", size=size)
    return _scene(
        "single_box",
        [Body.box(size, size, position=(0.0, size / 2), friction=friction, density=density)],
        {"size": size, "friction": friction},
    )


def rest_row(n=10, size=1.0, gap=0.5, friction=0.6):
    """``n`` square boxes resting on the floor in a row, ``gap`` apart (no box touches another)."""
    _counts("rest_row", n=n)
    _lengths("rest_row", size=size)
    _lengths("rest_row", allow_zero=True, gap=gap)
    pitch = size + gap
    bodies = [
        Body.box(size, size, position=(i * pitch, size / 2), friction=friction) for i in range(n)
    ]
    return _scene("rest_row", bodies, {"n": n, "size": size, "gap": gap, "friction": friction})


def stack(height=5, size=1.0, friction=0.6):
    """A column of ``height`` square boxes on the floor."""
    _counts("stack", height=height)
    _lengths("stack", size=size)
    bodies = [
        Body.box(size, size, position=(0.0, size / 2 + i * size), friction=friction)
        for i in range(height)
    ]
    return _scene("stack", bodies, {"height": height, "size": size, "friction": friction})


def pyramid(base=10, size=1.0, gap=0.125, friction=0.6):
    """A pyramid of square boxes: ``base`` on the floor, one fewer in each row above, each box
    centred over the gap between the two below; ``gap`` (m) separates neighbours in a row, as in
    Box2D's pyramid benchmark, so every box is carried only by the two below it.
    base*(base+1)/2 bodies."""
    _counts("pyramid", base=base)
    _lengths("pyramid", size=size)
    _lengths("pyramid", allow_zero=True, gap=gap)
    bodies = []
    pitch = size + gap
    for row in range(base):
        for k in range(base - row):
            x = (k - (base - row - 1) / 2) * pitch
            bodies.append(
                Body.box(size, size, position=(x, size / 2 + row * size), friction=friction)
            )
    return _scene("pyramid", bodies, {"base": base, "size": size, "gap": gap, "friction": friction})


def random_convex(rng, radius, n_min=3, n_max=8):
    """A random convex polygon (vertices CCW, centred on its centroid) of circumradius ~radius:
    sorted random angles on an ellipse, so it is convex by construction."""
    while True:
        k = int(rng.integers(n_min, n_max + 1))
        angles = np.sort(rng.uniform(0.0, 2 * math.pi, k))
        if np.min(np.diff(np.append(angles, angles[0] + 2 * math.pi))) < 0.3:
            continue  # avoid slivers: they make a needlessly stiff test
        aspect = rng.uniform(0.6, 1.0)
        v = np.stack([radius * np.cos(angles), radius * aspect * np.sin(angles)], axis=1)
        body = Body(vertices=v)
        return v - body.centroid


def drop(n=30, seed=0, radius=0.4, width=None, friction=0.6):
    """``n`` random convex polygons (3-8 vertices) dropped from a grid into a walled bin.

    Walls are static polygons. Bodies start 1.2*2*radius apart in a grid ``width`` wide (default
    about sqrt(n) columns), with small random angles and no velocity."""
    _counts("drop", n=n)
    _counts("drop", minimum=0, seed=seed)
    _lengths("drop", radius=radius)
    if width is not None:
        _lengths("drop", width=width)
    rng = np.random.default_rng(seed)
    cols = (
        max(1, int(math.ceil(math.sqrt(n))))
        if width is None
        else max(1, int(width / (2.4 * radius)))
    )
    pitch = 2.4 * radius
    bodies = []
    for i in range(n):
        row, col = divmod(i, cols)
        v = random_convex(rng, radius)
        x = (col - (cols - 1) / 2) * pitch + rng.uniform(-0.1, 0.1) * radius
        y = 0.5 + radius + row * pitch
        bodies.append(
            Body(
                vertices=v,
                position=(x, y),
                angle=float(rng.uniform(-math.pi, math.pi)),
                friction=friction,
            )
        )
    half = cols * pitch / 2 + radius
    wall_h = 1.0 + (n // cols + 1) * pitch
    walls = [
        Body.box(0.5, wall_h, position=(-half - 0.25, wall_h / 2), name="left wall"),
        Body.box(0.5, wall_h, position=(half + 0.25, wall_h / 2), name="right wall"),
    ]
    return _scene(
        "drop",
        bodies,
        {"n": n, "seed": seed, "radius": radius, "friction": friction},
        static_bodies=walls,
    )


def arch(n_blocks=9, radius=2.0, thickness=0.6, friction=0.8):
    """A semicircular arch of ``n_blocks`` trapezoidal voussoirs standing on the floor.

    With thickness/radius well above the ~0.11 minimum of a semicircular arch (Heyman), and
    friction above the thrust/weight ratio at the springings, it stands. The springings need
    mu ~0.6 against the floor (mixed sqrt(0.8 * 0.6) = 0.69 with the default floor): at 0.6 the arch
    stands right at its friction limit. Contact faces are radial,
    so most contacts are neither horizontal nor vertical."""
    _counts("arch", minimum=2, n_blocks=n_blocks)  # one block would span a straight angle
    _lengths("arch", radius=radius, thickness=thickness)
    if not thickness < 2.0 * radius:
        raise ValueError(
            f"arch: thickness must be below twice the radius (the inner radius is radius - "
            f"thickness/2), got thickness {thickness} and radius {radius}"
        )
    r_in = radius - thickness / 2
    r_out = radius + thickness / 2
    bodies = []
    for k in range(n_blocks):
        a0 = math.pi * k / n_blocks
        a1 = math.pi * (k + 1) / n_blocks
        # CCW: inner a0 -> outer a0 -> outer a1 -> inner a1 is clockwise for increasing angle,
        # so go the other way round
        pts = [
            (r_out * math.cos(a0), r_out * math.sin(a0)),
            (r_out * math.cos(a1), r_out * math.sin(a1)),
            (r_in * math.cos(a1), r_in * math.sin(a1)),
            (r_in * math.cos(a0), r_in * math.sin(a0)),
        ]
        v = np.array(pts)
        if (v[1, 0] - v[0, 0]) * (v[2, 1] - v[0, 1]) - (v[1, 1] - v[0, 1]) * (
            v[2, 0] - v[0, 0]
        ) < 0:
            v = v[::-1]
        c = Body(vertices=v).centroid
        bodies.append(Body(vertices=v - c, position=tuple(c), friction=friction))
    return _scene(
        "arch",
        bodies,
        {"n_blocks": n_blocks, "radius": radius, "thickness": thickness, "friction": friction},
    )


# ---- the seed paper's figures -----------------------------------------------------------------
def seed_fig1():
    """Seed figure 1: A rests flat on the floor on two vertices (rotation-stable), B is a box
    standing on one corner, tilted 30 degrees (vertical-stable: short of a square's 45 degree
    tipping angle, it turns back onto its face, touching with one vertex for the first ~30 steps,
    the moment drawn), C is in the air (vertical-unstable)."""
    a = Body.box(1.0, 1.0, position=(-2.0, 0.5), name="A")
    tilt = math.radians(30.0)
    # the corner (-0.5, -0.5) rotated by the tilt is the lowest: put it on the floor
    lowest = -0.5 * math.sin(tilt) - 0.5 * math.cos(tilt)
    b = Body.box(1.0, 1.0, position=(0.0, -lowest), angle=tilt, name="B")
    c = Body.box(1.0, 1.0, position=(2.0, 2.5), angle=math.radians(15.0), name="C")
    return _scene("seed_fig1", [a, b, c], {"tilt_deg": 30.0})


def seed_fig2(drop_height=1.8):
    """Seed figure 2: body A falls onto the floor-parallel top edge of B, which rests on the floor.

    A (centre at ``drop_height`` m, tilted 10 degrees) lands on one corner at ~2.5 m/s: under the
    seed's impulse threshold (1 N s), so under ``paper`` it stays on that vertex (VS) and then
    settles on its face (RS) (the seed's figure shows the landing only). (From 2.5 m it lands at
    4.4 m/s, above the threshold: it bounces off its corner instead, and comes down on its face a
    step later.)"""
    b = Body.box(2.0, 1.0, position=(0.0, 0.5), name="B")
    a = Body.box(0.8, 0.8, position=(0.2, drop_height), angle=math.radians(10.0), name="A")
    return _scene("seed_fig2", [a, b], {"drop_height": drop_height})


def seed_fig3(speed=2.5, friction=0.2):
    """Seed figure 3: A rests on B and slides right (initial speed ``speed``) until no support point
    lies under its centre of mass a0, then tips off B's edge and falls to the floor.

    With friction mu between A and B (sqrt(mu*mu) = mu), A would slide speed^2/(2 mu g) on an
    endless surface: 1.6 m at the defaults, enough to carry a0 past B's edge 0.9 m away."""
    b = Body.box(2.0, 1.0, position=(0.0, 0.5), friction=friction, name="B")
    a = Body.box(0.8, 0.4, position=(0.1, 1.2), velocity=(speed, 0.0), friction=friction, name="A")
    return _scene("seed_fig3", [a, b], {"speed": speed, "friction": friction})


def sliding_box(speed=3.0, friction=0.4, size=1.0):
    """A box sliding on the floor at ``speed``; friction mixes with the floor's to ``friction``
    (the floor is given the same mu, and sqrt(mu*mu) = mu). Stops after v^2 / (2 mu g)."""
    return _scene(
        "sliding_box",
        [Body.box(size, size, position=(0.0, size / 2), velocity=(speed, 0.0), friction=friction)],
        {"speed": speed, "friction": friction},
        floor_friction=friction,
    )


#: name -> builder, for command lines (`make trace SCENE=...`) and experiments
BUILDERS = {
    f.__name__: f
    for f in (
        single_box,
        rest_row,
        stack,
        pyramid,
        drop,
        arch,
        seed_fig1,
        seed_fig2,
        seed_fig3,
        sliding_box,
    )
}
