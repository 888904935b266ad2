"""Validation of convex polygons (one: ``validate_polygon``, the reference; many at once:
``validate_polygons``) and mass properties of many at once (numpy, vectorised).

Why this module exists: ``sim.geometry`` checks and measures one polygon per call, and on a
4-vertex box almost all of a call's ~90 us is numpy's per-call overhead. A scene of 10^6 bodies
paid that 10^6 times. Here the polygons of a whole scene are handled together: grouped by vertex
count, each group is one (n, K, 2) array, so the cost is a few array operations per distinct K.

Packed layout (the World's): ``vertices`` (V,2) float64, m, every polygon's vertices concatenated;
``vert_start`` (M+1,) int64 offsets, polygon i being rows vert_start[i]:vert_start[i+1].

Agreement with ``sim.geometry``, which stays the reference:
- ``mass_properties_many`` and ``edge_normals_many`` apply the same operations in the same order as
  ``geometry.mass_properties`` / ``geometry.edge_normals``, and their sums reduce in the order numpy
  reduces one polygon, so the results are equal bit for bit (tests/unit/test_packing.py checks
  this).
- ``validate_polygon`` lives here, beside its vectorised screen, so that one module owns what a
  valid polygon is (it moved from ``sim.geometry`` when the needle-tip check outgrew that module).
- ``validate_polygons`` does not re-implement the error messages: a vectorised screen marks every
  polygon that fails, or comes within a rounding margin of failing, one of ``validate_polygon``'s
  checks, and ``validate_polygon`` itself then judges the marked ones in index order. The verdicts
  and messages are therefore exactly the reference's.
"""

import math

import numpy as np

from .arguments import beyond_float, kind_of, numeric_array
from .geometry import MAX_COORDINATE, MAX_VERTICES, PolygonError, signed_area


def validate_polygon(vertices, name="polygon"):
    """Return ``vertices`` as a (K, 2) float64 array, or raise ``PolygonError`` naming ``name``.

    Rejects: fewer than 3 vertices, more than ``MAX_VERTICES``, NaN/inf, repeated vertices, zero
    area, clockwise order, any reflex vertex (non-convex) and needle tips. Collinear vertices are
    allowed only within a relative tolerance of 1e-9 (they add a zero-angle corner; the World
    solves the polygon without them, ``polygons.drop_collinear``).
    """
    # before the conversion, which takes text, switches and complex numbers (complex: a warning)
    numeric = numeric_array(vertices)
    try:
        v = np.asarray(vertices, dtype=np.float64) if numeric else None
    except (TypeError, ValueError) as exc:
        raise PolygonError(f"{name}: vertices are not an array of (x, y) numbers ({exc})") from None
    if v is None:
        if beyond_float(vertices):
            raise PolygonError(
                f"{name}: vertices contain NaN or inf (an integer beyond float's range)"
            )
        try:
            got = kind_of(vertices)
        except (TypeError, ValueError) as exc:  # ragged: no one array
            raise PolygonError(
                f"{name}: vertices are not an array of (x, y) numbers ({exc})"
            ) from None
        raise PolygonError(
            f"{name}: vertices must be numbers, not text, switches or complex numbers (got {got})"
        )
    if v.ndim != 2 or v.shape[1] != 2:
        raise PolygonError(f"{name}: vertices must have shape (K, 2), got {v.shape}")
    k = v.shape[0]
    if k < 3:
        raise PolygonError(f"{name}: a polygon needs at least 3 vertices, got {k}")
    if k > MAX_VERTICES:
        raise PolygonError(f"{name}: at most {MAX_VERTICES} vertices are supported, got {k}")
    if not np.all(np.isfinite(v)):
        raise PolygonError(f"{name}: vertices contain NaN or inf")
    if np.abs(v).max() > MAX_COORDINATE:
        raise PolygonError(
            f"{name}: a vertex lies {np.abs(v).max():.4g} m from the body's origin, "
            f"beyond {MAX_COORDINATE:g} m (the solver's range)"
        )
    scale = float(np.max(np.abs(v - v.mean(axis=0))))
    if scale <= 0.0:
        raise PolygonError(f"{name}: degenerate polygon (all vertices coincide)")
    edges = np.roll(v, -1, axis=0) - v
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    short = np.flatnonzero(lengths <= 1e-9 * scale)
    if short.size:
        i = int(short[0])
        raise PolygonError(f"{name}: degenerate polygon (vertices {i} and {(i + 1) % k} coincide)")
    area = signed_area(v)
    if abs(area) <= 1e-12 * scale * scale:
        raise PolygonError(f"{name}: degenerate polygon (zero area)")
    if area < 0.0:
        raise PolygonError(f"{name}: vertices are clockwise; give them counter-clockwise")
    nxt, norm = np.roll(edges, -1, axis=0), lengths * np.roll(lengths, -1)
    # cross and dot of consecutive unit edges: sine and cosine of the turn at the vertex between
    turn, cosine = (
        (edges[:, 0] * nxt[:, 1] - edges[:, 1] * nxt[:, 0]) / norm,
        (edges * nxt).sum(1) / norm,
    )
    reflex = np.flatnonzero(turn < -1e-9)
    if reflex.size:
        raise PolygonError(f"{name}: non-convex polygon (reflex vertex {(int(reflex[0]) + 1) % k})")
    # A tip turning back within 1e-9 of 180 degrees is a needle no collinearity test can tell
    # from a straight vertex by its sine alone (a 5e-11 m^2 triangle lost all its vertices)
    needle = np.flatnonzero((np.abs(turn) <= 1e-9) & (cosine < 0.0))
    if needle.size:
        raise PolygonError(
            f"{name}: degenerate polygon (needle tip at vertex {(int(needle[0]) + 1) % k})"
        )
    # A convex CCW polygon turns through exactly 2*pi; more means it winds around twice.
    angles = np.arctan2(turn, cosine)
    if abs(angles.sum() - 2.0 * math.pi) > 1e-6:
        raise PolygonError(f"{name}: non-convex polygon (self-intersecting outline)")
    return v


# The tolerances of validate_polygon, widened by margins far larger than the rounding
# differences between its one-polygon arithmetic and the vectorised arithmetic here (a shoelace
# sum of <= 1024 terms is off by < 1024 * 2.2e-16 * scale^2 = 2.3e-13 scale^2). A polygon inside a
# margin is only screened in: the reference then decides.
_SHORT_EDGE = 1e-9 * (1.0 + 1e-6)  # relative to the polygon's scale (reference: 1e-9)
_THIN_AREA = 2e-12  # relative to scale^2 (reference: 1e-12)
_REFLEX_TURN = -1e-9 * (1.0 - 1e-6)  # sine of the turn angle (reference: -1e-9)
_NEEDLE_TURN = 1e-9 * (1.0 + 1e-6)  # |sine| of a turn backwards (reference: 1e-9)
_WINDING = 1e-6 * (1.0 - 1e-3)  # rad off 2 pi (reference: 1e-6)


def check_packed(vertices, vert_start):
    """Return (vertices (V,2) float64, vert_start (M+1,) int64), or raise ValueError saying what
    is wrong with the packed layout."""
    vertices = np.asarray(vertices, dtype=np.float64)
    if vertices.ndim != 2 or vertices.shape[1] != 2:
        raise ValueError(f"vertices must have shape (V, 2), got {vertices.shape}")
    vert_start = np.asarray(vert_start)
    if (
        vert_start.ndim != 1
        or len(vert_start) < 1
        or not np.issubdtype(vert_start.dtype, np.integer)
    ):
        raise ValueError(
            f"vert_start must be a 1-D integer array of shape (M+1,), got "
            f"{vert_start.dtype} {vert_start.shape}"
        )
    vert_start = vert_start.astype(np.int64, copy=False)
    if vert_start[0] != 0 or vert_start[-1] != len(vertices) or np.any(np.diff(vert_start) < 0):
        raise ValueError(
            f"vert_start must rise from 0 to len(vertices) = {len(vertices)} without "
            f"decreasing, got {vert_start[0]} .. {vert_start[-1]}"
        )
    return vertices, vert_start


def vertex_counts(vert_start):
    """(M,) int64: the number of vertices of each polygon."""
    return np.diff(vert_start)


def by_vertex_count(vert_start):
    """The polygons grouped by vertex count: a list of (k, index (n,) int64 polygon numbers in
    increasing order, rows (n, k) int64 rows of the packed vertex array)."""
    counts = vertex_counts(vert_start)
    groups = []
    for k in np.unique(counts).tolist():
        index = np.flatnonzero(counts == k)
        groups.append((k, index, vert_start[index][:, None] + np.arange(k)))
    return groups


def next_rows(vert_start):
    """(V,) int64: for each packed vertex row, the row of the next vertex of the same polygon
    (wrapping to the polygon's first vertex), i.e. ``np.roll(v, -1, axis=0)`` for every polygon."""
    nxt = np.arange(1, int(vert_start[-1]) + 1, dtype=np.int64)
    counts = vertex_counts(vert_start)
    full = counts > 0
    nxt[vert_start[1:][full] - 1] = vert_start[:-1][full]
    return nxt


def polygon_suspects(vertices, vert_start):
    """(M,) bool: polygons that fail, or come within a rounding margin of failing, a check of
    ``validate_polygon``. Every polygon it leaves unmarked passes that function."""
    vertices, vert_start = check_packed(vertices, vert_start)
    suspect = np.zeros(len(vert_start) - 1, dtype=bool)
    for k, index, rows in by_vertex_count(vert_start):
        if k < 3 or k > MAX_VERTICES:
            suspect[index] = True
            continue
        g = vertices[rows]  # (n,k,2) m
        with np.errstate(all="ignore"):  # non-finite input is marked below
            centred = g - g.mean(axis=1, keepdims=True)
            scale = np.abs(centred).max(axis=(1, 2))  # (n,) m
            edges = np.roll(g, -1, axis=1) - g
            lengths = np.hypot(edges[..., 0], edges[..., 1])  # (n,k) m
            short = np.any(lengths <= _SHORT_EDGE * scale[:, None], axis=1)
            x, y = centred[..., 0], centred[..., 1]
            area = 0.5 * (
                (x * np.roll(y, -1, axis=1)).sum(axis=1) - (np.roll(x, -1, axis=1) * y).sum(axis=1)
            )  # (n,) m^2, CCW > 0
            thin = ~(area > _THIN_AREA * scale * scale)  # NaN counts as thin
            nxt = np.roll(edges, -1, axis=1)
            norm = lengths * np.roll(lengths, -1, axis=1)
            sine = (edges[..., 0] * nxt[..., 1] - edges[..., 1] * nxt[..., 0]) / norm
            cosine = (edges[..., 0] * nxt[..., 0] + edges[..., 1] * nxt[..., 1]) / norm
            reflex = np.any(sine < _REFLEX_TURN, axis=1)
            needle = np.any((np.abs(sine) <= _NEEDLE_TURN) & ~(cosine > 0.0), axis=1)
            winding = ~(np.abs(np.arctan2(sine, cosine).sum(axis=1) - 2.0 * math.pi) <= _WINDING)
        finite = np.isfinite(g).all(axis=(1, 2)) & (np.abs(g).max(axis=(1, 2)) <= MAX_COORDINATE)
        suspect[index] = ~finite | short | thin | reflex | needle | winding
    return suspect


def validate_polygons(vertices, vert_start, names):
    """Raise ``PolygonError`` for the first invalid polygon in index order, with exactly the message
    ``validate_polygon`` gives it; return None when all are valid.

    names: callable i -> the polygon's name for the message, called only for screened-in polygons.
    """
    vertices, vert_start = check_packed(vertices, vert_start)
    for i in np.flatnonzero(polygon_suspects(vertices, vert_start)).tolist():
        validate_polygon(vertices[vert_start[i] : vert_start[i + 1]], names(i))


def _require_polygons(vert_start):
    counts = vertex_counts(vert_start)
    if len(counts) and counts.min() < 3:
        i = int(np.argmax(counts < 3))
        raise PolygonError(f"polygon {i} has {counts[i]} vertices; validate polygons first")


def mass_properties_many(vertices, vert_start, density):
    """Mass (M,) kg, centroid (M,2) m in each polygon's own frame, and moment of inertia about the
    centroid (M,) kg m^2 of valid polygons; density kg/m^2, a number or (M,).

    The formulas of ``geometry.mass_properties`` (a triangle fan from vertex 0, for precision far
    from the origin), and the same results bit for bit."""
    vertices, vert_start = check_packed(vertices, vert_start)
    _require_polygons(vert_start)
    m = len(vert_start) - 1
    density = np.broadcast_to(np.asarray(density, dtype=np.float64), (m,))
    mass = np.empty(m)
    centroid = np.empty((m, 2))
    inertia = np.empty(m)
    for _, index, rows in by_vertex_count(vert_start):
        g = vertices[rows]  # (n,k,2) m
        origin = g[:, 0]
        p = g - origin[:, None]
        a = p[:, 1:-1]
        b = p[:, 2:]
        cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]  # (n,k-2) twice each triangle's area
        area = 0.5 * cross.sum(axis=1)
        c = ((a + b) * cross[..., None]).sum(axis=1) / (6.0 * area)[:, None]
        ax, ay, bx, by = a[..., 0], a[..., 1], b[..., 0], b[..., 1]
        i_origin = (cross * (ax**2 + ax * bx + bx**2 + ay**2 + ay * by + by**2)).sum(axis=1) / 12.0
        d = density[index]
        mk = d * area
        mass[index] = mk
        c2 = c[:, 0] * c[:, 0] + c[:, 1] * c[:, 1]  # as geometry.mass_properties: no BLAS
        inertia[index] = d * i_origin - mk * c2  # parallel axis theorem
        centroid[index] = c + origin
    return mass, centroid, inertia


#: |sine of the turn| at a vertex at or below which it is collinear with its neighbours (the
#: tolerance ``validate_polygon`` allows collinear vertices within)
COLLINEAR_TURN = 1e-9


def drop_collinear(vertices, vert_start):
    """The polygons without their collinear vertices: (vertices (V',2), vert_start (M+1,)), the
    inputs themselves when no polygon has one.

    Why: a collinear vertex splits a face into parts that the narrowphase sees as faces of their
    own, all equally facing a support, and it takes the first: a unit box whose bottom edge was
    given in four parts rested on the first quarter only, tipped over and sank 0.53 m into the
    floor; a box on a static box whose top was split fell off it. A collinear vertex adds no
    corner, so the polygon without it is the same shape."""
    vertices, vert_start = check_packed(vertices, vert_start)
    nxt = next_rows(vert_start)
    prev = np.empty_like(nxt)
    prev[nxt] = np.arange(len(nxt))
    e_in = vertices - vertices[prev]
    e_out = vertices[nxt] - vertices
    with np.errstate(all="ignore"):
        norm = np.hypot(e_in[:, 0], e_in[:, 1]) * np.hypot(e_out[:, 0], e_out[:, 1])
        sine = (e_in[:, 0] * e_out[:, 1] - e_in[:, 1] * e_out[:, 0]) / norm
        cosine = (e_in[:, 0] * e_out[:, 0] + e_in[:, 1] * e_out[:, 1]) / norm
    # collinear: a turn of ~0, never of ~180 degrees (a needle tip, which validate_polygon
    # refuses; by its sine alone a 1e7 m kite lost its far tip and a box fell through it)
    keep = ~((np.abs(sine) <= COLLINEAR_TURN) & (cosine > 0.0))
    if keep.all():
        return vertices, vert_start
    kept = np.add.reduceat(keep.astype(np.int64), vert_start[:-1]) if len(keep) else keep
    # "collinear" is judged vertex by vertex: a thin lens (two arcs of 500 vertices turning 9e-10
    # each) lost both arcs and was left a 2-gon. A polygon that would keep fewer than 3 keeps all
    few = np.flatnonzero(kept < 3)
    for i in few.tolist():  # rare: a loop
        keep[vert_start[i] : vert_start[i + 1]] = True
    if few.size:
        kept = np.add.reduceat(keep.astype(np.int64), vert_start[:-1])
    start = np.zeros(len(vert_start), np.int64)
    np.cumsum(kept, out=start[1:])
    return vertices[keep], start


def edge_normals_many(vertices, vert_start):
    """(V,2) outward unit normals of every polygon's edges, packed like ``vertices``
    (``geometry.edge_normals`` for each polygon, bit for bit)."""
    vertices, vert_start = check_packed(vertices, vert_start)
    e = vertices[next_rows(vert_start)] - vertices
    n = np.stack([e[:, 1], -e[:, 0]], axis=1)
    return n / np.hypot(n[:, 0], n[:, 1])[:, None]


def extent_many(local_vertices, vert_start):
    """(M,) m: distance from each polygon's centroid to its farthest vertex, given the vertices
    relative to the centroid (the World's body frame)."""
    local_vertices, vert_start = check_packed(local_vertices, vert_start)
    _require_polygons(vert_start)
    reach = np.hypot(local_vertices[:, 0], local_vertices[:, 1])
    return np.maximum.reduceat(reach, vert_start[:-1]) if len(vert_start) > 1 else np.empty(0)


def thinnest_width_many(local_vertices, vert_start, normals=None):
    """(M,) m: each convex polygon's width across its thinnest edge direction, min over edges e of
    max over vertices v of dot(v_e - v, n_e). The length scale of a body for tolerances (a plank's
    thickness, not its length). ``normals`` (V,2): the edge normals if already computed."""
    local_vertices, vert_start = check_packed(local_vertices, vert_start)
    _require_polygons(vert_start)
    if normals is None:
        normals = edge_normals_many(local_vertices, vert_start)
    width = np.empty(len(vert_start) - 1)
    for k, index, rows in by_vertex_count(vert_start):
        # (k, n) layout: row j holds vertex j of every polygon, so each step below is a
        # contiguous operation along n, however few vertices the polygons have
        x, y = local_vertices[rows.T, 0], local_vertices[rows.T, 1]  # (k,n) m
        nx, ny = normals[rows.T, 0], normals[rows.T, 1]
        best = np.full(len(index), np.inf)
        for e in range(k):
            depth = (x[e] - x) * nx[e] + (y[e] - y) * ny[e]  # (k,n) m
            np.minimum(best, depth.max(axis=0), out=best)
        width[index] = best
    return width
