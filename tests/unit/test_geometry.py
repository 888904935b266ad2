"""sim/geometry.py against the slow references in tests/naive.py, known answers and invariants.

Random polygons span four decades of size (1 cm .. 100 m) and sit away from the origin, because
both are where float round-off hides. Tolerances are relative to the coordinates in play.

Several kernel decisions are discontinuous (which face is the reference, which edge is incident,
whether a point is within the margin). Near such a boundary the kernel and the reference may
legitimately round to different sides, so those tests ``assume`` the configuration is clear of every
boundary by a stated gap instead of loosening the comparison.
"""

import math
import re

import numpy as np
import pytest
from hypothesis import assume, event, given, settings
from hypothesis import strategies as st

import naive  # tests/ is on sys.path under pytest's default rootdir-relative import mode
from sim import geometry
from sim.geometry import PolygonError
from sim.polygons import drop_collinear, validate_polygon

SETTINGS = settings(max_examples=150, deadline=None)


# ------------------------------------------------------------------------------------------------
# Strategies


def _place(local, angle, centre):
    """Rotate body-frame vertices by ``angle`` and move them to ``centre`` (keeps CCW order)."""
    return np.ascontiguousarray(local @ naive.rotation(angle).T + np.asarray(centre))


@st.composite
def ellipse_polygons(draw, min_vertices=3, max_vertices=64):
    """Convex CCW polygon: points on an ellipse at random, strictly increasing angles.

    Angular gaps come from weights in [1, 10], so no gap is less than a tenth of the mean: the
    polygon is strictly convex and has no near-duplicate vertices for validation to reject.
    """
    n = draw(st.integers(min_vertices, max_vertices))
    weights = np.array(draw(st.lists(st.floats(1.0, 10.0), min_size=n, max_size=n)))
    phase = draw(st.floats(0.0, 2.0 * math.pi))
    t = phase + 2.0 * math.pi * (np.cumsum(weights) - weights[0]) / weights.sum()
    size = 10.0 ** draw(st.floats(-2.0, 2.0))  # semi-major axis, 1 cm .. 100 m
    aspect = draw(st.floats(0.2, 1.0))
    local = np.stack([size * np.cos(t), aspect * size * np.sin(t)], axis=1)
    return _place(local, draw(st.floats(-math.pi, math.pi)), draw(_centres))


@st.composite
def boxes(draw):
    """Rectangles: parallel edges make exact SAT ties between opposite faces possible."""
    w = 10.0 ** draw(st.floats(-2.0, 2.0))
    h = w * draw(st.floats(0.1, 10.0))
    local = np.array([[-w, -h], [w, -h], [w, h], [-w, h]]) / 2.0
    return _place(local, draw(st.floats(-math.pi, math.pi)), draw(_centres))


_centres = st.tuples(st.floats(-50.0, 50.0), st.floats(-50.0, 50.0))
polygons = st.one_of(ellipse_polygons(), ellipse_polygons(max_vertices=6), boxes())


def size_of(v):
    return float(np.max(np.ptp(v, axis=0)))


def coord_scale(*polys):
    """Magnitude of the numbers the kernels work with: sets the round-off floor of a comparison."""
    return max(float(np.max(np.abs(p))) + size_of(p) for p in polys)


def inradius_about(v, point):
    """Distance from an interior point to the nearest edge line."""
    return float(np.min(np.einsum("ij,ij->i", naive.normals(v), v - point)))


def place_at_separation(a, b, direction, target):
    """Translate ``b`` along ``direction`` from a's vertex mean until the SAT separation is target.

    SAT separation along a ray is convex in the travel distance and negative at distance 0 (the two
    vertex means coincide inside both shapes), so {separation <= target} is an interval starting at
    0 and bisection finds its end.
    """
    u = np.array([math.cos(direction), math.sin(direction)])
    local = b - b.mean(axis=0)
    start = a.mean(axis=0)

    def sep(dist):
        return naive.sat_separation(a, local + start + dist * u)

    hi = size_of(a) + size_of(b) + abs(target) + 1e-12
    while sep(hi) <= target:
        hi *= 2.0
    lo = 0.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if sep(mid) <= target:
            lo = mid
        else:
            hi = mid
    return np.ascontiguousarray(local + start + lo * u)


@st.composite
def pairs(draw, min_frac=-0.5, max_frac=0.5, shapes=polygons):
    """Two polygons whose SAT separation is a random fraction of the pair's inner size.

    Negative fractions push b into a (depth up to half the smaller inradius about the vertex means,
    which is always reachable); positive ones leave a gap.
    """
    a = draw(shapes)
    b = draw(shapes)
    inner = min(inradius_about(a, a.mean(axis=0)), inradius_about(b, b.mean(axis=0)))
    # keep clear of exact touching, where "overlap" and "apart" are decided by round-off
    sides = [st.floats(lo, hi) for lo, hi in ((min_frac, -1e-3), (1e-3, max_frac)) if lo < hi]
    frac = draw(st.one_of(sides))
    b = place_at_separation(a, b, draw(st.floats(-math.pi, math.pi)), frac * inner)
    return a, b, inner


# ------------------------------------------------------------------------------------------------
# Kernel wrappers


def kernel_collide(a, b, margin):
    pts = np.full((2, 2), np.nan)
    seps = np.full(2, np.nan)
    ids = np.full(2, -1, dtype=np.int64)
    normal = np.full(2, np.nan)
    count, flip, edge, _ = geometry.collide_polygons(
        a,
        geometry.edge_normals(a),
        b,
        geometry.edge_normals(b),
        float(margin),
        pts,
        seps,
        ids,
        normal,
    )
    return {
        "count": int(count),
        "flip": int(flip),
        "edge": int(edge),
        "points": pts[:count],
        "separations": seps[:count],
        "ids": ids[:count].tolist(),
        "normal": normal,
    }


def kernel_floor(v, floor_y, margin):
    pts = np.full((2, 2), np.nan)
    seps = np.full(2, np.nan)
    ids = np.full(2, -1, dtype=np.int64)
    count, _ = geometry.collide_floor(
        v, geometry.edge_normals(v), float(floor_y), float(margin), pts, seps, ids
    )
    return int(count), pts[:count], seps[:count], ids[:count].tolist()


def box(cx, cy, w, h, angle=0.0):
    return _place(np.array([[-w, -h], [w, -h], [w, h], [-w, h]]) / 2.0, angle, (cx, cy))


def assume_clear_of_decisions(a, b, margin, gap, dot_gap):
    """Skip configurations within ``gap`` (m) / ``dot_gap`` (cosine) of a kernel decision boundary.

    Returns the reference manifold for the configuration.
    """
    ref = naive.collide_polygons(a, b, margin)
    c = ref["choice"]
    assume(abs(c["sep_a"] - margin) > gap and abs(c["sep_b"] - margin) > gap)
    bias = naive.REFERENCE_ABS_BIAS + naive.REFERENCE_REL_BIAS * abs(c["sep_a"])
    assume(abs(c["sep_b"] - (c["sep_a"] + bias)) > gap)
    if c["sep_a"] > margin or c["sep_b"] > margin:
        return ref
    ref_v, inc_v = (b, a) if c["flip"] else (a, b)
    # the best face of the reference polygon must win by more than the gap
    s = np.sort(naive.axis_separations(ref_v, inc_v))
    assume(s[-1] - s[-2] > gap)
    n = naive.normals(ref_v)[c["edge"]]
    inc, dots = naive.incident_edge(n, inc_v)
    d = np.sort(dots)
    assume(d[1] - d[0] > dot_gap)
    # the incident edge must overlap the face's extent by more than the gap, or miss it by more
    r0, r1 = naive.edges(ref_v)[c["edge"]]
    p0, p1 = naive.edges(inc_v)[inc]
    tangent = (r1 - r0) / np.hypot(*(r1 - r0))
    s0, s1 = sorted((tangent @ (p0 - r0), tangent @ (p1 - r0)))
    overlap = min(s1, tangent @ (r1 - r0)) - max(s0, 0.0)
    assume(abs(overlap) > gap)
    # every clipped point must be clearly inside or outside the margin
    for p, _ in naive.clip_incident_edge(ref_v, c["edge"], inc_v, inc):
        assume(abs(n @ (p - r0) - margin) > gap)
    return ref


def _bias_band(sep_a, sep_b):
    """Width of the documented reference-face hysteresis around sep_a == sep_b."""
    return naive.REFERENCE_ABS_BIAS + naive.REFERENCE_REL_BIAS * max(abs(sep_a), abs(sep_b))


# ------------------------------------------------------------------------------------------------
# Mass properties


@pytest.mark.parametrize(
    "impl", [geometry.mass_properties, naive.mass_properties], ids=["geometry", "naive"]
)
class TestMassKnownAnswers:
    """Closed forms; run on the reference too, so that the reference is itself checked."""

    def test_box(self, impl):
        w, h, rho = 3.0, 0.5, 7.0
        m, c, inertia = impl(box(10.0, -4.0, w, h), rho)
        assert m == pytest.approx(rho * w * h, rel=1e-12)
        assert c == pytest.approx([10.0, -4.0], abs=1e-12)
        assert inertia == pytest.approx(m * (w * w + h * h) / 12.0, rel=1e-12)

    def test_unit_box(self, impl):
        m, c, inertia = impl(box(0.0, 0.0, 1.0, 1.0), 1.0)
        assert (m, inertia) == pytest.approx((1.0, 1.0 / 6.0), rel=1e-12)
        assert c == pytest.approx([0.0, 0.0], abs=1e-15)

    def test_right_triangle(self, impl):
        # legs a along x and b along y: centroid at (a/3, b/3), J_c = m (a^2 + b^2) / 18
        a, b, rho = 4.0, 3.0, 2.5
        off = np.array([-7.0, 12.0])
        m, c, inertia = impl(np.array([[0.0, 0.0], [a, 0.0], [0.0, b]]) + off, rho)
        assert m == pytest.approx(rho * a * b / 2.0, rel=1e-12)
        assert c == pytest.approx(off + [a / 3.0, b / 3.0], abs=1e-12)
        assert inertia == pytest.approx(m * (a * a + b * b) / 18.0, rel=1e-12)

    @pytest.mark.parametrize("n", [3, 4, 5, 6, 7, 12, 64, 1024])
    def test_regular_polygon(self, impl, n):
        radius, rho, centre = 0.37, 1200.0, (3.0, -2.0)
        m, c, inertia = impl(naive.regular_polygon(n, radius, centre, phase=0.3), rho)
        m_ref, j_ref = naive.regular_polygon_mass_properties(n, radius, rho)
        assert m == pytest.approx(m_ref, rel=1e-11)
        assert c == pytest.approx(centre, abs=1e-12)
        assert inertia == pytest.approx(j_ref, rel=1e-11)


@SETTINGS
@given(polygons, st.floats(0.1, 1e4))
def test_mass_properties_match_reference(v, density):
    m, c, inertia = geometry.mass_properties(v, density)
    m_ref, c_ref, j_ref = naive.mass_properties(v, density)
    assert m == pytest.approx(m_ref, rel=1e-9)
    assert np.allclose(c, c_ref, rtol=0.0, atol=1e-10 * coord_scale(v))
    assert inertia == pytest.approx(j_ref, rel=1e-9)
    assert m > 0.0 and inertia > 0.0


@SETTINGS
@given(polygons, st.floats(-math.pi, math.pi), _centres, st.integers(0, 63))
def test_mass_properties_rigid_motion_and_relabelling(v, angle, shift, roll):
    """Mass and inertia about the centroid are intrinsic; the centroid moves with the body."""
    m, c, inertia = geometry.mass_properties(v, 3.0)
    moved = np.roll(v @ naive.rotation(angle).T + shift, roll % len(v), axis=0)
    m2, c2, inertia2 = geometry.mass_properties(moved, 3.0)
    assert m2 == pytest.approx(m, rel=1e-9)
    assert inertia2 == pytest.approx(inertia, rel=1e-9)
    expected = naive.rotation(angle) @ c + shift
    assert np.allclose(c2, expected, rtol=0.0, atol=1e-10 * coord_scale(v, moved))


@SETTINGS
@given(polygons)
def test_signed_area_and_normals(v):
    m, _, _ = naive.mass_properties(v, 1.0)
    assert geometry.signed_area(v) == pytest.approx(m, rel=1e-6)
    assert geometry.signed_area(v[::-1]) == pytest.approx(-m, rel=1e-6)
    n = geometry.edge_normals(v)
    assert np.allclose(n, naive.normals(v), rtol=0.0, atol=1e-12)
    assert np.allclose(np.hypot(n[:, 0], n[:, 1]), 1.0, atol=1e-14)
    # outward: every vertex of the polygon lies behind (or on) every edge's line
    heights = np.einsum("ijk,ik->ij", v[None, :, :] - v[:, None, :], n)  # (edge, vertex)
    assert np.all(heights <= 1e-10 * coord_scale(v))


# ------------------------------------------------------------------------------------------------
# validate_polygon

_SQUARE = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
_PENTAGON = naive.regular_polygon(5, 1.0)

BAD_POLYGONS = {
    "clockwise": _SQUARE[::-1],
    "reflex vertex": [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [1.0, 0.5], [0.0, 2.0]],
    "repeated consecutive vertex": [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
    "closing vertex repeated": _SQUARE + [[0.0, 0.0]],
    "all vertices coincide": [[2.0, 3.0]] * 4,
    "collinear three": [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]],
    "collinear four": [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]],
    "collinear back and forth": [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0]],
    "pentagram": _PENTAGON[[0, 2, 4, 1, 3]].tolist(),
    "winds twice": np.concatenate([_PENTAGON, _PENTAGON]).tolist(),
    "nan": [[0.0, 0.0], [1.0, 0.0], [float("nan"), 1.0]],
    "inf": [[0.0, 0.0], [float("inf"), 0.0], [1.0, 1.0]],
    "-inf": [[0.0, 0.0], [1.0, 0.0], [1.0, -float("inf")]],
    "two vertices": [[0.0, 0.0], [1.0, 0.0]],
    "no vertices": [],
    "three columns": [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    "flat list": [0.0, 0.0, 1.0, 0.0, 0.0, 1.0],
    "3-d array": [_SQUARE],
    "ragged": [[0.0, 0.0], [1.0], [0.0, 1.0]],
    "not numbers": [["a", "b"], ["c", "d"], ["e", "f"]],
    "none": None,
    "too many vertices": naive.regular_polygon(geometry.MAX_VERTICES + 1, 1.0),
    # area 5e-11 m^2, above the zero-area limit: its two tips turn back by 180 degrees within 1e-9
    "needle": [[0.0, 0.0], [1.0, 0.0], [2.0, 1e-10]],
    "long needle kite": [[0.0, 0.0], [1e7, -1e-3], [1e7 + 1.0, 0.0], [1e7, 1e-3]],
}


def test_a_needle_tip_is_refused_as_a_needle_and_a_sharp_tip_is_not():
    """A tip turning back within 1e-9 of 180 degrees passed (its |sine| is that of a straight
    vertex) and the World dropped its vertices as collinear: a thin triangle lost all three
    ("polygon 1 has 0 vertices"), a 1e7 m kite its far tip, and a box on it fell through. A tip
    sharper than any real corner but resolvable (1e-6 rad) is a valid polygon and keeps it."""
    with pytest.raises(PolygonError, match="needle tip at vertex 0"):
        validate_polygon(BAD_POLYGONS["long needle kite"], name="ledge")
    sharp = np.array([[0.0, 0.0], [1.0, -1e-6], [2.0, 0.0], [1.0, 1e-6]])
    assert validate_polygon(sharp).shape == (4, 2)
    vertices, start = drop_collinear(sharp, np.array([0, 4]))
    assert vertices.tolist() == sharp.tolist() and start.tolist() == [0, 4]
    # drop_collinear, given one unvalidated, keeps a needle's tip and drops only the straight vertex
    kite = np.array(BAD_POLYGONS["long needle kite"])
    assert drop_collinear(kite, np.array([0, 4]))[0].tolist() == kite.tolist()
    needle = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1e-10]])
    assert drop_collinear(needle, np.array([0, 4]))[0].tolist() == needle[[0, 2, 3]].tolist()


@pytest.mark.parametrize("label", list(BAD_POLYGONS))
def test_validate_rejects(label):
    with pytest.raises(PolygonError, match=re.escape("crate #7")):
        validate_polygon(BAD_POLYGONS[label], name="crate #7")


def test_validate_says_clockwise_for_a_clockwise_polygon():
    # A clockwise convex polygon also has only "reflex" corners; the user should be told the fix
    # (reverse the order), not that the shape is non-convex.
    with pytest.raises(PolygonError, match="(?i)clockwise"):
        validate_polygon(naive.regular_polygon(6, 1.0)[::-1])


def test_polygon_error_is_value_error():
    # callers that predate PolygonError catch ValueError
    with pytest.raises(ValueError):
        validate_polygon(_SQUARE[::-1])


@pytest.mark.parametrize(
    "v",
    [_SQUARE, naive.regular_polygon(geometry.MAX_VERTICES, 1.0), [[0, 0], [1, 0], [0, 1]]],
    ids=["square", "max vertices", "ints"],
)
def test_validate_accepts(v):
    out = validate_polygon(v)
    assert out.dtype == np.float64 and out.shape == (len(v), 2)
    assert np.array_equal(out, np.asarray(v, dtype=np.float64))


@SETTINGS
@given(polygons)
def test_validate_accepts_random_convex_and_rejects_its_mirror(v):
    out = validate_polygon(v, name="p")
    assert out.shape == v.shape and out.dtype == np.float64 and np.array_equal(out, v)
    with pytest.raises(PolygonError, match="p"):
        validate_polygon(v[::-1], name="p")


@SETTINGS
@given(ellipse_polygons(min_vertices=4), st.integers(0, 63), st.floats(0.01, 0.5))
def test_validate_rejects_dented_polygon(v, i, depth):
    """Pull one vertex past the chord of its neighbours, to the inside: that vertex becomes reflex.

    (Onto the chord would only make it collinear, which is allowed.)
    """
    k = len(v)
    i %= k
    chord = v[(i + 1) % k] - v[i - 1]
    inward = np.array([-chord[1], chord[0]])  # left of the chord = inside, for CCW
    dented = v.copy()
    dented[i] = 0.5 * (v[i - 1] + v[(i + 1) % k]) + depth * inward
    with pytest.raises(PolygonError, match="dented"):
        validate_polygon(dented, name="dented")


@pytest.mark.parametrize(
    "v",
    [
        # exactly collinear (steps of exactly (1, 1)) but the shoelace products round to a positive
        # "area" above the 1e-12 * scale^2 threshold: accepted, and mass_properties then gives NaN
        [[50.8, 52.1], [51.8, 53.1], [52.8, 54.1]],
    ],
    ids=["collinear accepted"],
)
def test_validate_rejects_collinear_far_from_origin(v):
    with pytest.raises(PolygonError):
        validate_polygon(v)


def test_validate_accepts_thin_triangle_far_from_origin():
    # A CCW triangle 1 m wide and 1 um tall (area/scale^2 ~ 1e-6, far above the 1e-12 threshold):
    # accepted at the origin, but at 1e5 m the shoelace round-off (~1e-6 m^2) swamps its area and
    # it is rejected as zero-area (or as clockwise, for other offsets). Validation should not
    # depend on where the polygon sits.
    thin = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, 1e-6]])
    validate_polygon(thin)
    validate_polygon(thin + [100000.3, 100000.4])


# ------------------------------------------------------------------------------------------------
# Separating axes


@SETTINGS
@given(pairs())
def test_max_separation_matches_reference(pair):
    a, b, _ = pair
    tol = 1e-10 * coord_scale(a, b)
    for p, q in ((a, b), (b, a)):
        edge, sep = geometry.max_separation(p, geometry.edge_normals(p), q)
        per_edge = naive.axis_separations(p, q)
        assert sep == pytest.approx(per_edge.max(), abs=tol)
        assert per_edge[edge] == pytest.approx(per_edge.max(), abs=tol)  # ties may pick either


@SETTINGS
@given(pairs())
def test_sat_sign_matches_overlap(pair):
    """SAT says 'apart' exactly when a test that uses no axes finds no shared point."""
    a, b, _ = pair
    sep = max(
        geometry.max_separation(a, geometry.edge_normals(a), b)[1],
        geometry.max_separation(b, geometry.edge_normals(b), a)[1],
    )
    assume(abs(sep) > 1e-9 * coord_scale(a, b))
    assert (sep < 0.0) == naive.polygons_intersect(a, b)


@SETTINGS
@given(pairs(min_frac=0.0, max_frac=2.0))
def test_sat_separation_versus_true_distance(pair):
    """Projection onto any unit axis cannot exceed the distance; the best edge axis attains it
    whenever the closest features are a vertex facing the inside of an edge."""
    a, b, _ = pair
    tol = 1e-9 * coord_scale(a, b)
    sep = max(
        geometry.max_separation(a, geometry.edge_normals(a), b)[1],
        geometry.max_separation(b, geometry.edge_normals(b), a)[1],
    )
    dist, t = naive.polygon_distance(a, b)
    assert sep <= dist + tol
    if 1e-6 < t < 1.0 - 1e-6:
        assert sep == pytest.approx(dist, abs=tol)


@SETTINGS
@given(pairs(min_frac=-0.5, max_frac=0.3), st.floats(0.0, 0.2))
def test_collide_symmetric_in_a_and_b(pair, margin_frac):
    """Swapping A and B describes the same contact: same points, opposite normal, flip toggled."""
    a, b, inner = pair
    margin = margin_frac * inner
    sep_a = naive.max_separation(a, b)[1]
    sep_b = naive.max_separation(b, a)[1]
    # Inside this band the documented bias keeps each call on its own first polygon's face, so
    # the two calls legitimately use different faces.
    assume(abs(sep_a - sep_b) > 2.0 * _bias_band(sep_a, sep_b))
    ab = kernel_collide(a, b, margin)
    ba = kernel_collide(b, a, margin)
    assert (ab["count"] > 0) == (ba["count"] > 0)
    assert ab["count"] == ba["count"]
    if ab["count"]:
        tol = 1e-10 * coord_scale(a, b)
        assert np.allclose(ab["normal"], -ba["normal"], atol=1e-12)
        assert np.allclose(ab["separations"], ba["separations"], rtol=0.0, atol=tol)
        if ab["edge"] < 0:  # corners: each call's point is on its second polygon
            assert ba["edge"] < 0
            other = ab["points"] - ab["separations"][:, None] * ab["normal"]
            assert np.allclose(other, ba["points"], rtol=0.0, atol=tol)
            return
        assert ab["flip"] != ba["flip"]
        assert np.allclose(ab["points"], ba["points"], rtol=0.0, atol=tol)


# ------------------------------------------------------------------------------------------------
# Contact manifolds between polygons


@SETTINGS
@given(pairs(min_frac=-0.5, max_frac=0.3), st.floats(0.0, 0.2))
def test_collide_matches_reference_clipping(pair, margin_frac):
    a, b, inner = pair
    margin = margin_frac * inner
    gap = 1e-9 * coord_scale(a, b)
    ref = assume_clear_of_decisions(a, b, margin, gap, 1e-9)
    got = kernel_collide(a, b, margin)
    inc_v = a if ref["flip"] else b
    cut = sum(not np.any(np.all(p == inc_v, axis=1)) for p in ref["points"])
    event(f"count={ref['count']} flip={ref['flip']} cut={cut}")
    assert got["count"] == ref["count"]
    if not ref["count"]:
        return
    assert (got["flip"], got["edge"]) == (ref["flip"], ref["edge"])
    if ref["edge"] >= 0:  # corners (edge -1): a vertex met at two edges ties; see the test below
        assert got["ids"] == ref["ids"]
    assert np.allclose(got["normal"], ref["normal"], rtol=0.0, atol=1e-12)
    assert np.allclose(got["points"], ref["points"], rtol=0.0, atol=gap)
    assert np.allclose(got["separations"], ref["separations"], rtol=0.0, atol=gap)


@SETTINGS
@given(pairs(min_frac=-0.5, max_frac=0.3), st.floats(0.0, 0.2))
def test_contact_points_lie_on_incident_boundary(pair, margin_frac):
    """Properties that hold whatever face was chosen, checked against that face directly."""
    a, b, inner = pair
    margin = margin_frac * inner
    tol = 1e-9 * coord_scale(a, b)
    got = kernel_collide(a, b, margin)
    if not got["count"] or got["edge"] < 0:  # corners: no face (test_polygons_apart_within_...)
        return
    ref_v, inc_v = (b, a) if got["flip"] else (a, b)
    r0, r1 = naive.edges(ref_v)[got["edge"]]
    n = naive.outward_normal(r0, r1)
    # the normal is the reference face's outward normal, oriented from A to B
    assert np.allclose(got["normal"], -n if got["flip"] else n, atol=1e-12)
    assert len(set(got["ids"])) == got["count"]
    for p, s, fid in zip(got["points"], got["separations"], got["ids"]):
        assert s == pytest.approx(float(n @ (p - r0)), abs=tol)
        assert s <= margin
        assert naive.boundary_distance(p, inc_v) <= tol
        # ...and within the reference face's extent (the side planes)
        along = float((r1 - r0) @ (p - r0)) / float((r1 - r0) @ (r1 - r0))
        assert -1e-9 <= along <= 1.0 + 1e-9
        assert (fid >> 1) // (naive.ID_BASE**2) == got["flip"]
        assert (fid >> 1) // naive.ID_BASE % naive.ID_BASE == got["edge"]


@SETTINGS
@given(pairs(min_frac=0.0, max_frac=2.0), st.floats(0.0, 0.2))
def test_collide_beyond_margin_is_empty(pair, margin_frac):
    a, b, inner = pair
    margin = margin_frac * inner
    sep = naive.sat_separation(a, b)
    assume(sep > margin + 1e-9 * coord_scale(a, b))
    assert kernel_collide(a, b, margin)["count"] == 0
    assert kernel_collide(b, a, margin)["count"] == 0


@SETTINGS
@given(pairs(min_frac=-0.5, max_frac=-1e-3))
def test_overlapping_polygons_get_a_penetrating_contact(pair):
    """Shapes that overlap must produce a contact, or the solver lets them sink into each other.
    Checked where the face choice is unambiguous; inside the bias band see
    test_overlap_inside_bias_band_gets_a_contact."""
    a, b, _ = pair
    sep_a = naive.max_separation(a, b)[1]
    sep_b = naive.max_separation(b, a)[1]
    assume(abs(sep_a - sep_b) > 2.0 * _bias_band(sep_a, sep_b))
    for p, q in ((a, b), (b, a)):
        got = kernel_collide(p, q, 0.0)
        assert got["count"] >= 1 and got["separations"].min() < 0.0


def test_overlap_inside_bias_band_gets_a_contact():
    # Overlap 11.9 mm (B's face) / 12.0 mm (A's face): within the 1e-4 + 1e-3*|sep| bias, so A's
    # face (edge 0, only 1.8 mm long) is kept; B's incident edge lies wholly beyond that face's
    # end, so clipping against it removes it; the kernel must then fall back to B's face (it once
    # returned 0 points for (A, B) while (B, A) gave 2).
    a = np.array([[0.0042, 0.007], [0.0043, 0.0052], [0.0649, 0.0721]])
    b = np.array([[0.0162, -0.0054], [0.0163, 0.0056], [0.014, 0.02], [-0.0249, 0.0601]])
    assert naive.polygons_intersect(a, b) and naive.sat_separation(a, b) < -0.01
    assert kernel_collide(b, a, 0.0)["count"] == 2
    assert kernel_collide(a, b, 0.0)["count"] >= 1


def test_corners_apart_get_one_point_at_their_closest_points():
    """Two unit boxes corner to corner, g = 10 mm apart along each axis: each box's incident
    edge lies wholly past the other's face end, so clipping keeps nothing. The manifold is then
    one point at the closest points (the corners, g sqrt 2 apart), A the reference (edge -1), the
    normal along the diagonal; none beyond the margin. Before, no point at all: a corner met in
    a step went into the other body by up to the step's travel."""
    g = 0.01
    a = box(0.0, 0.0, 1.0, 1.0)
    b = box(1.0 + g, 1.0 + g, 1.0, 1.0)
    got = kernel_collide(a, b, 0.02)
    assert (got["count"], got["flip"], got["edge"]) == (1, 0, -1)
    assert got["separations"][0] == pytest.approx(g * math.sqrt(2.0), rel=1e-12)
    np.testing.assert_allclose(got["points"][0], [0.5 + g, 0.5 + g], atol=1e-12)
    np.testing.assert_allclose(got["normal"], [math.sqrt(0.5), math.sqrt(0.5)], atol=1e-12)
    assert (got["ids"][0] >> 1) // naive.ID_BASE**2 == 2  # apart from every face-clipping id
    ref = naive.collide_polygons(a, b, 0.02)
    assert (ref["count"], ref["edge"], ref["ids"]) == (1, -1, got["ids"])
    back = kernel_collide(b, a, 0.02)  # B first: the point on A, the normal reversed
    np.testing.assert_allclose(back["points"][0], [0.5, 0.5], atol=1e-12)
    np.testing.assert_allclose(back["normal"], -got["normal"], atol=1e-12)
    assert kernel_collide(a, b, 0.014)["count"] == 0  # g sqrt 2 = 14.1 mm: beyond the margin


def _vertex_cone(v, i):
    """The outward normals of the two edges that meet at vertex i of CCW polygon v: directions
    from the vertex that point away from the polygon lie between them."""
    n = naive.normals(v)
    return n[i - 1], n[i]


def _angle(u):
    return math.atan2(u[1], u[0])


@st.composite
def corner_pairs(draw):
    """Two polygons corner to corner: a vertex of b placed a random fraction of the pair's inner
    size from a vertex of a, along a direction inside a's cone there, b turned so that the
    opposite direction lies inside its own vertex's cone. Their closest points are then those two
    vertices, and often neither face's clip keeps a point."""
    a = draw(polygons)
    b = draw(polygons)
    inner = min(inradius_about(a, a.mean(axis=0)), inradius_about(b, b.mean(axis=0)))
    i = draw(st.integers(0, len(a) - 1))
    j = draw(st.integers(0, len(b) - 1))
    lo, hi = (_angle(n) for n in _vertex_cone(a, i))
    sweep = (hi - lo) % (2.0 * math.pi)
    u_angle = lo + sweep * draw(st.floats(0.1, 0.9))
    u = np.array([math.cos(u_angle), math.sin(u_angle)])
    blo, bhi = (_angle(n) for n in _vertex_cone(b, j))
    bsweep = (bhi - blo) % (2.0 * math.pi)
    inward = blo + bsweep * draw(st.floats(0.1, 0.9))  # a direction out of b at vertex j
    turn = (u_angle + math.pi) - inward  # ... turned to point back at a
    local = (b - b[j]) @ naive.rotation(turn).T
    gap = draw(st.floats(1e-3, 0.3)) * inner
    return a, np.ascontiguousarray(local + a[i] + gap * u), inner


@SETTINGS
@given(st.one_of(pairs(min_frac=1e-3, max_frac=0.3), corner_pairs()), st.floats(0.0, 0.4))
def test_polygons_apart_within_the_margin_always_get_a_point(pair, margin_frac):
    """No speculative contact is missed: two polygons closer than the margin (their true
    distance, naive.polygon_distance) get at least one point whichever comes first, every point
    at or within the margin; where no face keeps a point, the one point is the closest points'
    (the reference's answer, the distance itself)."""
    a, b, inner = pair
    margin = margin_frac * inner
    tol = 1e-9 * coord_scale(a, b)
    distance, _ = naive.polygon_distance(a, b)
    assume(distance < margin - tol)
    for p, q in ((a, b), (b, a)):
        got = kernel_collide(p, q, margin)
        event(f"edge={'corner' if got['edge'] < 0 else 'face'}")
        assert got["count"] >= 1
        assert got["separations"].max() <= margin
        if got["edge"] < 0:
            ref = naive.collide_polygons(p, q, margin)
            assert ref["edge"] == -1
            assert got["separations"][0] == pytest.approx(distance, abs=tol)
            np.testing.assert_allclose(got["points"], ref["points"], rtol=0.0, atol=tol)
            np.testing.assert_allclose(got["normal"], ref["normal"], rtol=0.0, atol=1e-9)


def test_box_resting_on_wider_box():
    a = box(0.0, 0.0, 4.0, 1.0)
    b = box(0.3, 0.999, 1.0, 1.0)  # bottom at 0.499: 1 mm into a's top at 0.5
    got = kernel_collide(a, b, 0.01)
    assert got["count"] == 2 and got["flip"] == 0 and got["edge"] == 2
    assert got["normal"] == pytest.approx([0.0, 1.0])
    assert got["separations"] == pytest.approx([-0.001, -0.001], abs=1e-12)
    assert np.allclose(sorted(map(tuple, got["points"])), [(-0.2, 0.499), (0.8, 0.499)])


def test_box_overhanging_edge_is_clipped_to_side_plane():
    a = box(0.0, 0.0, 4.0, 1.0)
    b = box(1.9, 0.999, 1.0, 1.0)  # spans x 1.4 .. 2.4, a ends at 2
    got = kernel_collide(a, b, 0.01)
    assert got["count"] == 2
    assert sorted(got["points"][:, 0]) == pytest.approx([1.4, 2.0])
    assert got["points"][:, 1] == pytest.approx([0.499, 0.499])


def test_box_hovering_within_and_beyond_margin():
    a = box(0.0, 0.0, 4.0, 1.0)
    assert kernel_collide(a, box(0.0, 1.005, 1.0, 1.0), 0.01)["count"] == 2  # 5 mm gap
    assert kernel_collide(a, box(0.0, 1.02, 1.0, 1.0), 0.01)["count"] == 0  # 20 mm gap


# ------------------------------------------------------------------------------------------------
# Feature ids: warm starting carries impulses by id, so a configuration that barely moves must keep
# its ids.


@SETTINGS
@given(
    pairs(min_frac=-0.5, max_frac=0.1),
    st.floats(0.0, 0.2),
    st.floats(-math.pi, math.pi),
    st.floats(-1.0, 1.0),
)
def test_feature_ids_stable_under_nudge(pair, margin_frac, direction, spin):
    a, b, inner = pair
    margin = margin_frac * inner
    nudge = 1e-7
    # stay 100 nudges away from every decision the nudge could tip
    assume_clear_of_decisions(a, b, margin, 100 * nudge, 100 * nudge / size_of(b))
    centre = b.mean(axis=0)
    turn = spin * nudge / size_of(b)  # moves no vertex by more than the nudge
    moved = _place(
        b - centre, turn, centre + nudge * np.array([math.cos(direction), math.sin(direction)])
    )
    before = kernel_collide(a, b, margin)
    after = kernel_collide(a, moved, margin)
    event(f"count={before['count']}")
    assert after["count"] == before["count"]
    assert after["ids"] == before["ids"]
    assert np.allclose(after["points"], before["points"], rtol=0.0, atol=10 * nudge)


@pytest.mark.parametrize("dx", [1e-7, -1e-7, 3e-9, 0.0])
def test_feature_ids_stable_for_flush_stack(dx):
    """Equal boxes stacked flush put the top box's corners exactly on the side planes: round-off
    nudges must not change which ids the two corners get."""
    a = box(0.0, 0.0, 1.0, 1.0)
    reference = kernel_collide(a, box(0.0, 0.999, 1.0, 1.0), 0.01)
    got = kernel_collide(a, box(dx, 0.999, 1.0, 1.0), 0.01)
    assert reference["count"] == got["count"] == 2
    assert got["ids"] == reference["ids"]


@SETTINGS
@given(pairs(min_frac=-0.5, max_frac=0.3), polygons, st.floats(0.0, 0.2), st.booleans())
def test_packed_row_kernels_match_per_polygon_wrappers(pair, other, margin_frac, b_first):
    """The solver calls the row-range kernels on packed arrays; the per-polygon wrappers (used by
    the tests above) start A at row 0. Put other polygons around A and B so every row offset is
    non-zero, in either order, and demand identical answers."""
    a, b, inner = pair
    margin = margin_frac * inner
    blocks = [other, b, other, a] if b_first else [other, a, other, b]
    verts = np.ascontiguousarray(np.concatenate(blocks))
    normals = np.ascontiguousarray(np.concatenate([geometry.edge_normals(p) for p in blocks]))
    starts = np.cumsum([0] + [len(p) for p in blocks])
    ia, ib = (3, 1) if b_first else (1, 3)
    pts = np.full((2, 2), np.nan)
    seps = np.full(2, np.nan)
    ids = np.full(2, -1, dtype=np.int64)
    normal = np.full(2, np.nan)
    count, flip, edge, _ = geometry.collide_polygon_rows(
        verts,
        normals,
        starts[ia],
        starts[ia + 1],
        starts[ib],
        starts[ib + 1],
        float(margin),
        1e-4,
        pts,
        seps,
        ids,
        normal,
    )
    want = kernel_collide(a, b, margin)
    assert (count, flip, edge) == (want["count"], want["flip"], want["edge"])
    assert ids[:count].tolist() == want["ids"]
    assert np.array_equal(pts[:count], want["points"])
    assert np.array_equal(seps[:count], want["separations"])
    if count:
        assert np.array_equal(normal, want["normal"])
    floor_y = float(b[:, 1].min()) + 0.1 * margin_frac * inner
    count, _ = geometry.collide_floor_rows(
        verts, normals, starts[ib], starts[ib + 1], floor_y, float(margin), pts, seps, ids
    )
    want_count, want_pts, want_seps, want_ids = kernel_floor(b, floor_y, margin)
    assert count == want_count and ids[:count].tolist() == want_ids
    assert np.array_equal(pts[:count], want_pts) and np.array_equal(seps[:count], want_seps)


# ------------------------------------------------------------------------------------------------
# Floor


def test_floor_box_resting_flat():
    v = box(3.0, 0.5, 2.0, 1.0)
    count, pts, seps, ids = kernel_floor(v, 0.0, 0.01)
    assert count == 2
    assert seps.tolist() == [0.0, 0.0]
    assert sorted(map(tuple, pts)) == [(2.0, 0.0), (4.0, 0.0)]
    assert sorted(ids) == [0, 1]


def test_floor_tilted_box_touches_at_lowest_corner():
    v = box(0.0, 0.0, 2.0, 1.0, angle=0.3)
    lowest = int(np.argmin(v[:, 1]))
    floor_y = v[lowest, 1] + 0.001  # 1 mm of penetration at the corner only
    count, pts, seps, ids = kernel_floor(v, floor_y, 0.01)
    assert count == 1 and ids == [lowest]
    assert pts[0].tolist() == v[lowest].tolist()
    assert seps[0] == pytest.approx(-0.001, abs=1e-12)


def test_floor_box_above_margin():
    v = box(0.0, 0.52, 1.0, 1.0)  # 2 cm above the floor
    assert kernel_floor(v, 0.0, 0.01)[0] == 0
    assert kernel_floor(v, 0.0, 0.03)[0] == 2


@SETTINGS
@given(polygons, st.floats(-0.3, 0.3), st.floats(0.0, 0.1))
def test_floor_matches_reference(v, gap_frac, margin_frac):
    size = size_of(v)
    floor_y = float(v[:, 1].min()) - gap_frac * size  # gap_frac < 0: lowest vertex sunk
    margin = margin_frac * size
    count, pts, seps, ids = kernel_floor(v, floor_y, margin)
    # the lowest vertex is always a contact once it is within the margin (ties: any lowest one)
    low = float(v[:, 1].min())
    if low - floor_y <= margin:
        assert count >= 1 and min(pts[:, 1]) == low
    # every contact is a vertex, reported with its exact height above the floor
    for p, s, j in zip(pts, seps, ids):
        assert p.tolist() == v[j].tolist() and s == v[j, 1] - floor_y and s <= margin
    ref, _, scores = naive.floor_contacts(v, floor_y, margin)
    top = np.sort(scores)
    gap = 1e-9 * coord_scale(v)
    assume(top[-1] - top[-2] > 1e-9)  # one clear bottom edge
    assume(all(abs(v[j, 1] - floor_y - margin) > gap for j in range(len(v))))
    assert ids == [j for j, _, _ in ref]
    assert seps.tolist() == [s for _, _, s in ref]


# ------------------------------------------------------------------------------------------------
# Frame changes


@SETTINGS
@given(polygons, st.floats(-math.pi, math.pi), _centres)
def test_transform_and_rotate(v, angle, shift):
    c, s = math.cos(angle), math.sin(angle)
    out = np.empty_like(v)
    geometry.transform(v, shift[0], shift[1], c, s, out)
    assert np.allclose(
        out, v @ naive.rotation(angle).T + shift, rtol=0.0, atol=1e-12 * coord_scale(v, out)
    )
    # numpy's place (World.vertices, the study's overlaps) is the kernel's pose, bit for bit
    np.testing.assert_array_equal(geometry.place(v, shift, angle), out)
    geometry.rotate(v, c, s, out)
    assert np.allclose(out, v @ naive.rotation(angle).T, rtol=0.0, atol=1e-12 * coord_scale(v))


def test_a_valid_polygon_whose_every_turn_is_tiny_keeps_at_least_three_vertices():
    """ "Collinear" is judged vertex by vertex: a thin lens, two arcs of 500 vertices each turning
    9e-10 rad (each under the 1e-9 tolerance), lost both arcs and was left a 2-gon that packing
    refused ("polygon 0 has 2 vertices") though validate_polygon had accepted it (a reviewer,
    2026-12-07). Such a polygon keeps all its vertices."""
    n, a = 500, 5e-10 * 500 * 0.9
    phi = np.linspace(a, -a, n + 1)
    x = np.sin(phi) / np.sin(a)
    y = 2 * np.sin((a - phi) / 2) * np.sin((a + phi) / 2) / np.sin(a)
    lens = np.r_[np.c_[x, y], np.c_[-x, -y][1:-1]]
    assert validate_polygon(lens).shape == (2 * n, 2)
    box = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]])
    vertices, start = drop_collinear(np.r_[lens, box], np.array([0, 2 * n, 2 * n + 5]))
    assert start.tolist() == [0, 2 * n, 2 * n + 4]  # the lens whole; the box without (1, 0)
    assert vertices[: 2 * n].tolist() == lens.tolist()
