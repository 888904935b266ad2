"""A sim body as every peer builds it: the engines put a body's origin at its centre of mass, sim
at the origin its vertices are given about. One conversion for all runners, so that every peer
integrates identical bodies (sim's own mass and moment) from identical poses."""

import math

import numpy as np

from sim.geometry import mass_properties


def com_pose(body):
    """(centre of mass (x, y) in the world, m; the vertices about it (K,2) m, in the body's
    order; mass kg; moment about the centre of mass kg m^2) of a ``sim.Body``."""
    mass, centroid, inertia = mass_properties(body.vertices, body.density)
    c, s = math.cos(body.angle), math.sin(body.angle)
    com = (
        body.position[0] + c * centroid[0] - s * centroid[1],
        body.position[1] + s * centroid[0] + c * centroid[1],
    )
    return com, np.asarray(body.vertices, dtype=np.float64) - centroid, mass, inertia


def body_label(kind, i, name):
    """ "body 3 (name)" for messages; "body 3" for an unnamed body (sim names it "body 3")."""
    return f"{kind} {i}" + (f" ({name})" if name and name != f"{kind} {i}" else "")
