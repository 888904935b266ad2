"""``pack(scene)``: a Scene's bodies as the struct-of-arrays a World runs on.

Why a module of its own: the World's set-up used to loop over the bodies in Python, calling
``geometry.mass_properties`` once per body (16 s for 10^5 boxes). Here every per-polygon quantity
is computed for all polygons at once (``sim.polygons``); an array-backed scene
(``Scene.from_arrays``) is packed without any Python loop over its bodies, and a Body-list scene
only loops to read the fields.

The formulas are the World's: the centre of mass is the body position plus the rotated centroid,
vertices are stored about it, and results are bit-for-bit those of the one-body loop (sines and
cosines come from ``math``, as there, rather than numpy's vectorised ones, which may differ in
the last bit).
"""

import math
from typing import NamedTuple

import numpy as np

from .polygons import (
    drop_collinear,
    edge_normals_many,
    extent_many,
    mass_properties_many,
    thinnest_width_many,
)
from .scene import BodyArrays


class Packed(NamedTuple):
    """Per-body arrays of M bodies: the N dynamic ones first, then the static ones in scene
    order."""

    n_dynamic: int  # N
    vert_start: (
        np.ndarray
    )  # (M+1,) int64: body i's rows of local_verts are vert_start[i]:vert_start[i+1]
    local_verts: np.ndarray  # (V,2) m, body frame about the centre of mass
    local_normals: np.ndarray  # (V,2) outward unit edge normals, body frame
    position: np.ndarray  # (M,2) m, centre of mass in the world
    angle: np.ndarray  # (M,) rad
    velocity: np.ndarray  # (M,2) m/s of the centre of mass, zeros for static
    angular_velocity: np.ndarray  # (M,) rad/s, zeros for static
    inv_mass: np.ndarray  # (M,) 1/kg, 0 for static
    inv_inertia: np.ndarray  # (M,) 1/(kg m^2), 0 for static
    mass: np.ndarray  # (N,) kg
    inertia: np.ndarray  # (N,) kg m^2 about the centre of mass
    friction: np.ndarray  # (M,) Coulomb mu
    restitution: np.ndarray  # (M,) in [0, 1]
    extent: np.ndarray  # (M,) m, centre of mass to the farthest vertex
    size: np.ndarray  # (M,) m, thinnest width across an edge normal
    bullet: np.ndarray  # (M,) bool, False for static


def pack(scene, share=True):
    """The bodies of a validated ``sim.Scene`` (``World`` validates it first) as ``Packed``.

    ``share``: when every dynamic body has one polygon and one density (10^6 copies of a box),
    compute that polygon's properties once and give every body a copy (the same numbers, bit for
    bit: each polygon's are computed on its own rows alone). At 10^6 boxes that took 1.3-2.5 s of
    the pack's 1.7-3.6 s. False computes them body by body (tests compare the two)."""
    dynamic = scene.body_arrays
    if dynamic is None:
        dynamic = BodyArrays.from_bodies(scene.bodies)
    static = BodyArrays.from_bodies(scene.static_bodies)
    n = len(dynamic.position)
    m = n + len(static.position)
    # the polygons whose properties are computed: every body's, or the one shared polygon then
    # the static ones (shape_of: each body's row among them)
    k = _shared_polygon(dynamic) if share else 0
    head = dynamic if not k else _first(dynamic, k)
    shape_of = None if not k else np.concatenate([np.zeros(n, np.int64), 1 + np.arange(m - n)])
    vertices = np.concatenate([head.vertices, static.vertices])  # (V,2) m
    vert_start = np.concatenate([head.vert_start, static.vert_start[1:] + head.vert_start[-1]])
    # extreme but finite fields can overflow these: the World checks them and names the body
    # (validation.check_mass_properties), so numpy need not warn as well
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        mass, centroid, inertia = mass_properties_many(
            vertices, vert_start, np.concatenate([head.density, static.density])
        )
    # the solver's polygons without collinear vertices (the same shapes; see drop_collinear);
    # the mass properties are the given polygons', as Body.mass and Body.inertia report them
    vertices, vert_start = drop_collinear(vertices, vert_start)
    local = vertices - np.repeat(centroid, np.diff(vert_start), axis=0)
    normals = edge_normals_many(local, vert_start)
    extent = extent_many(local, vert_start)
    size = thinnest_width_many(local, vert_start, normals)
    if shape_of is not None:
        mass, centroid, inertia = mass[shape_of], centroid[shape_of], inertia[shape_of]
        extent, size = extent[shape_of], size[shape_of]
        rows, vert_start = _copies(vert_start, shape_of)
        local, normals = local[rows], normals[rows]
    angle = np.concatenate([dynamic.angle, static.angle])
    angles = angle.tolist()
    c = np.fromiter(map(math.cos, angles), np.float64, m)
    s = np.fromiter(map(math.sin, angles), np.float64, m)
    origin = np.concatenate([dynamic.position, static.position])  # (M,2) m
    position = np.empty((m, 2))
    position[:, 0] = origin[:, 0] + c * centroid[:, 0] - s * centroid[:, 1]
    position[:, 1] = origin[:, 1] + s * centroid[:, 0] + c * centroid[:, 1]
    velocity = np.zeros((m, 2))
    velocity[:n] = dynamic.velocity
    angular_velocity = np.zeros(m)
    angular_velocity[:n] = dynamic.angular_velocity
    inv_mass = np.zeros(m)
    inv_inertia = np.zeros(m)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        inv_mass[:n] = 1.0 / mass[:n]
        inv_inertia[:n] = 1.0 / inertia[:n]
    bullet = np.zeros(m, dtype=bool)
    bullet[:n] = dynamic.bullet
    return Packed(
        n_dynamic=n,
        vert_start=vert_start,
        local_verts=local,
        local_normals=normals,
        position=position,
        angle=angle,
        velocity=velocity,
        angular_velocity=angular_velocity,
        inv_mass=inv_mass,
        inv_inertia=inv_inertia,
        mass=mass[:n].copy(),
        inertia=inertia[:n].copy(),
        friction=np.concatenate([dynamic.friction, static.friction]),
        restitution=np.concatenate([dynamic.restitution, static.restitution]),
        extent=extent,
        size=size,
        bullet=bullet,
    )


def _shared_polygon(dynamic):
    """The vertex count k of the polygon every dynamic body shares, with one density; 0 if they
    do not (or there are fewer than two). Compared bit for bit, so that a -0.0 is not taken for
    a 0.0."""
    n = len(dynamic.position)
    counts = np.diff(dynamic.vert_start)
    if n < 2 or (counts != counts[0]).any():
        return 0
    k = int(counts[0])
    bits = dynamic.vertices.reshape(n, k * 2).view(np.int64)
    density = dynamic.density.view(np.int64)
    return k if (bits == bits[0]).all() and (density == density[0]).all() else 0


def _first(dynamic, k):
    """The first body's polygon and density, as the fields the pack reads from ``dynamic``."""
    return dynamic._replace(
        vertices=dynamic.vertices[:k],
        vert_start=np.array([0, k], np.int64),
        density=dynamic.density[:1],
    )


def _copies(vert_start, shape_of):
    """(rows (V',) int64 of the computed polygons' vertex rows, one run per body; the bodies'
    vert_start (M+1,)) for bodies whose polygons are rows ``shape_of`` of those computed."""
    counts = np.diff(vert_start)[shape_of]
    start = np.zeros(len(shape_of) + 1, np.int64)
    np.cumsum(counts, out=start[1:])
    rows = np.repeat(vert_start[:-1][shape_of] - start[:-1], counts) + np.arange(start[-1])
    return rows, start
