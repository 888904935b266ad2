"""``sim.Body``: one convex polygon with its material and initial motion (validated on creation).

The rules for a body's fields live here once, in two forms that agree: ``check_fields`` for one
body (it raises the message) and ``failing_fields`` for arrays of many bodies (it finds which fail,
so that ``Scene.from_arrays`` can ask ``check_fields`` for the first one's message)."""

from collections.abc import Sequence
from dataclasses import dataclass, field
import math
import numbers

import numpy as np

from .arguments import numeric_array
from .polygons import thinnest_width_many, validate_polygon
from .geometry import (
    MAX_COORDINATE,
    MAX_SPEED,
    MAX_VERTICES,
    PolygonError,
    mass_properties,
)

#: Polygons (shape, bytes of the float64 vertex array) that passed ``validate_polygon``: a scene of
#: 10^5 equal boxes checks its one polygon once instead of 10^5 times (~70 us each). The check is
#: a pure function of the vertex values, so remembering a pass changes no verdict; failures are
#: never remembered (each gets its own message). Only small polygons are remembered, and the set
#: is emptied when full, so that it stays under a megabyte.
_PASSED_POLYGONS = set()
_PASSED_POLYGONS_MAX = 4096
_REMEMBERED_VERTICES = 32


def _validated_polygon(vertices, name):
    """``validate_polygon(vertices, name)``, skipping the check for a polygon seen to pass."""
    try:
        given = np.asarray(vertices)
    except (TypeError, ValueError):
        given = None
    if given is None or not numeric_array(vertices):
        return validate_polygon(vertices, name)  # raises the reference's message
    v = np.asarray(given, dtype=np.float64)
    if v.size > 2 * _REMEMBERED_VERTICES:
        return validate_polygon(v, name)
    key = (v.shape, v.tobytes())
    if key in _PASSED_POLYGONS:
        return v
    v = validate_polygon(v, name)
    if len(_PASSED_POLYGONS) >= _PASSED_POLYGONS_MAX:
        _PASSED_POLYGONS.clear()
    _PASSED_POLYGONS.add(key)
    return v


def _canonical(value):
    """A field as a value that compares whole: arrays as (dtype, shape, bytes), sequences of
    numbers as tuples of floats, everything else as it is."""
    if isinstance(value, np.ndarray):
        a = np.ascontiguousarray(value, dtype=np.float64) if value.dtype.kind in "iuf" else value
        return (a.dtype.str, a.shape, a.tobytes())
    if isinstance(value, (list, tuple)):
        return _canonical(np.asarray(value, dtype=np.float64)) if _numeric(value) else value
    return value


def _numeric(seq):
    try:
        np.asarray(seq, dtype=np.float64)
        return True
    except (TypeError, ValueError):
        return False


#: rad: no body may start turned further. An angle is a float64 to which each substep adds its
#: turn, and at 1e15 rad (a spacing between floats of 0.125 rad) a body spinning at 1 rad/s kept
#: its angle for good while its angular velocity stayed 1; at 1e6 rad the spacing is 1.2e-10 rad,
#: a 30th of the turn of a substep at 1e-6 rad/s. Angles reached while running are not limited.
MAX_ANGLE = 1e6

#: what float() takes but is not a number here: text ("2" is a mistake, and "12" would unpack to
#: the pair (1.0, 2.0)), switches (True is not 1 m) and complex numbers (float() of a numpy
#: complex drops the imaginary part with only a warning)
NOT_NUMBERS = (str, bytes, bool, np.bool_, complex, np.complexfloating)


def real(value):
    """``float(value)`` of a real number; TypeError for anything in NOT_NUMBERS. An integer beyond
    float's range (10**400) is +-inf, so that the caller's finiteness check names it (float()
    raises a bare OverflowError, which named neither the field nor the body)."""
    if isinstance(value, NOT_NUMBERS):
        raise TypeError(f"not a number: {value!r}")
    try:
        return float(value)
    except OverflowError:
        return math.inf if value > 0 else -math.inf


def finite_pair(value, what, name):
    """(x, y) as a tuple of finite floats, or ValueError naming ``name`` and ``what``. A pair is
    a sequence or an array of two numbers (a dict or a set has no order to read it in)."""
    if not isinstance(value, (Sequence, np.ndarray)) or isinstance(value, (str, bytes)):
        raise ValueError(f"{name}: {what} must be a pair of numbers, got {value!r}")
    try:
        x, y = (real(c) for c in value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: {what} must be a pair of numbers, got {value!r}") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"{name}: {what} is not finite: ({x}, {y})")
    return (x, y)


def finite_number(value, what, name):
    """``value`` as a finite float, or ValueError naming ``name`` and ``what``."""
    try:
        x = real(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: {what} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name}: {what} is not finite: {x}")
    return x


def check_fields(
    name, position, velocity, angle, angular_velocity, density, friction, restitution, bullet
):
    """Every field of a body but its vertices, checked in a fixed order; returns them normalised
    (position and velocity as (x, y) tuples of floats, floats, a bool) or raises ValueError naming
    ``name`` and the first problem."""
    position = finite_pair(position, "position", name)
    if max(abs(position[0]), abs(position[1])) > MAX_COORDINATE:
        raise ValueError(
            f"{name}: position {position} is beyond {MAX_COORDINATE:g} m, "
            f"where the solver stops as diverged"
        )
    velocity = finite_pair(velocity, "velocity", name)
    if max(abs(velocity[0]), abs(velocity[1])) > MAX_SPEED:
        raise ValueError(
            f"{name}: velocity {velocity} is beyond {MAX_SPEED:g} m/s, faster than "
            f"the solver can follow (sim.geometry.MAX_SPEED)"
        )
    angle = finite_number(angle, "angle", name)
    if abs(angle) > MAX_ANGLE:
        raise ValueError(
            f"{name}: angle {angle:.10g} rad is beyond {MAX_ANGLE:g} rad, where float64 rounds "
            f"away a step's turn (sim.body.MAX_ANGLE); give it modulo 2 pi"
        )
    angular_velocity = finite_number(angular_velocity, "angular_velocity", name)
    if abs(angular_velocity) > MAX_SPEED:
        raise ValueError(
            f"{name}: angular_velocity {angular_velocity} is beyond {MAX_SPEED:g} "
            f"rad/s, faster than the solver can follow (sim.geometry.MAX_SPEED)"
        )
    density = finite_number(density, "density", name)
    if density <= 0.0:
        raise ValueError(f"{name}: density must be > 0, got {density}")
    friction = finite_number(friction, "friction", name)
    if friction < 0.0:
        raise ValueError(f"{name}: friction must be >= 0, got {friction}")
    restitution = finite_number(restitution, "restitution", name)
    if not 0.0 <= restitution <= 1.0:
        raise ValueError(f"{name}: restitution must be in [0, 1], got {restitution}")
    if not isinstance(bullet, (bool, np.bool_)):
        raise ValueError(f"{name}: bullet must be True or False, got {bullet!r}")
    return (
        position,
        velocity,
        angle,
        angular_velocity,
        density,
        friction,
        restitution,
        bool(bullet),
    )


def failing_fields(position, velocity, angle, angular_velocity, density, friction, restitution):
    """(N,) bool: the bodies whose fields ``check_fields`` rejects, given float64 arrays of N bodies
    (position, velocity (N,2); the others (N,)). Bullet flags are checked by their dtype instead."""
    with np.errstate(invalid="ignore"):
        fine = (
            np.isfinite(position).all(axis=1)
            & (np.abs(position).max(axis=1) <= MAX_COORDINATE)
            & (np.abs(velocity).max(axis=1) <= MAX_SPEED)
            & (np.abs(angular_velocity) <= MAX_SPEED)
            & np.isfinite(velocity).all(axis=1)
            & np.isfinite(angle)
            & (np.abs(angle) <= MAX_ANGLE)
            & np.isfinite(angular_velocity)
            & np.isfinite(density)
            & (density > 0.0)
            & np.isfinite(friction)
            & (friction >= 0.0)
            & (restitution >= 0.0)
            & (restitution <= 1.0)
        )
    return ~fine


@dataclass
class Body:
    """A rigid convex polygon.

    vertices  (K,2) m, counter-clockwise, in the body frame. The body frame's origin is placed at
              ``position`` and rotated by ``angle``. The solver tracks the centre of mass: a World
              reports ``positions`` of centres of mass (equal to ``position`` when the vertices are
              centred on their centroid, as every builder in ``sim.scenes`` does).
    position  (2,) m; angle rad (CCW); velocity (2,) m/s of the centre of mass; angular_velocity
    rad/s.
    density   kg/m^2 (> 0). friction >= 0 (Coulomb mu, pairs mix by geometric mean);
              restitution in [0, 1] (pairs mix by max).
    name      used in error messages; defaults to "body <index>" once placed in a Scene.
    bullet    True for a fast body that the solver sweeps (continuous collision) against dynamic
              bodies too, not only against static ones and the floor.
    """

    vertices: object
    position: tuple = (0.0, 0.0)
    angle: float = 0.0
    velocity: tuple = (0.0, 0.0)
    angular_velocity: float = 0.0
    density: float = 1.0
    friction: float = 0.5
    restitution: float = 0.0
    name: str = ""
    bullet: bool = False
    _validated: tuple = field(init=False, repr=False, compare=False, default=None)

    def __post_init__(self):
        self.validate(self.name if isinstance(self.name, str) and self.name else "body")

    def validate(self, name):
        """Check every field; raise ValueError naming ``name`` and the problem.

        A body is checked in full only when a field differs from the last time it passed (a
        cheap fingerprint of every field): scenes and Worlds re-validate their bodies, and the
        full check (~0.2 ms) made building a 10^4-body World cost seconds."""
        if self.name is None:
            self.name = ""
        if not isinstance(self.name, str):  # messages and results files print it
            raise ValueError(
                f"{name if isinstance(name, str) else 'body'}: name must be a "
                f"string, got {self.name!r}"
            )
        if self._validated is not None and self._validated == self._fingerprint():
            return
        self.vertices = _validated_polygon(self.vertices, name)
        (
            self.position,
            self.velocity,
            self.angle,
            self.angular_velocity,
            self.density,
            self.friction,
            self.restitution,
            self.bullet,
        ) = check_fields(
            name,
            self.position,
            self.velocity,
            self.angle,
            self.angular_velocity,
            self.density,
            self.friction,
            self.restitution,
            self.bullet,
        )
        self._validated = self._fingerprint()

    @classmethod
    def prevalidated(
        cls,
        vertices,
        position,
        angle,
        velocity,
        angular_velocity,
        density,
        friction,
        restitution,
        name="",
        bullet=False,
    ):
        """A Body from fields that already passed every check, without checking them again.

        For ``Scene.from_arrays``, whose bodies are validated as arrays: materialising 10^6 of
        them through the full check would cost minutes. The caller guarantees normalised, valid
        fields: vertices a (K,2) float64 array that passes ``validate_polygon``, position and
        velocity tuples of two floats, floats, a str and a bool. Later changes are still caught:
        the fingerprint is taken here, so the next ``validate`` checks a changed body in full."""
        body = object.__new__(cls)
        body.vertices, body.position, body.angle, body.velocity = (
            vertices,
            position,
            angle,
            velocity,
        )
        body.angular_velocity, body.density, body.friction = angular_velocity, density, friction
        body.restitution, body.name, body.bullet = restitution, name, bullet
        body._validated = body._fingerprint()
        return body

    def _fingerprint(self):
        """Every field as it stands, so that any change (in-place edits of the vertex array
        included) forces a full check. Arrays by dtype, shape and bytes: ``==`` on an array is
        elementwise (``body.position = world.positions[i]`` made the comparison raise)."""
        v = self.vertices
        return (
            _canonical(v) if isinstance(v, np.ndarray) else repr(v),
            *map(
                _canonical,
                (
                    self.position,
                    self.angle,
                    self.velocity,
                    self.angular_velocity,
                    self.density,
                    self.friction,
                    self.restitution,
                    self.bullet,
                ),
            ),
        )

    def __eq__(self, other):
        """Same fields (arrays compared whole, not elementwise), name included."""
        if not isinstance(other, Body):
            return NotImplemented
        return all(
            _canonical(getattr(self, f)) == _canonical(getattr(other, f))
            for f in (
                "vertices",
                "position",
                "angle",
                "velocity",
                "angular_velocity",
                "density",
                "friction",
                "restitution",
                "name",
                "bullet",
            )
        )

    @classmethod
    def box(cls, width, height, **kwargs):
        """A width x height rectangle centred on its centre of mass."""
        name = kwargs.get("name") or "box"
        w = 0.5 * finite_number(width, "width", name)
        h = 0.5 * finite_number(height, "height", name)
        if not (w > 0 and h > 0):
            raise PolygonError(f"{name}: width and height must be > 0, got {width} x {height}")
        return cls(vertices=[(-w, -h), (w, -h), (w, h), (-w, h)], **kwargs)

    @classmethod
    def regular(cls, n, radius, **kwargs):
        """A regular n-gon of circumradius ``radius``, centred, with a flat bottom edge."""
        name = kwargs.get("name") or "regular polygon"
        if isinstance(n, bool) or not isinstance(n, numbers.Integral) or not 3 <= n <= MAX_VERTICES:
            # checked before the vertices are made: n = 10**30 filled the memory
            raise PolygonError(
                f"{name}: the vertex count must be an integer from 3 to {MAX_VERTICES}, got {n!r}"
            )
        try:  # real(): no switches (True is not 1 m), no text; 10**400 is inf
            r = real(radius) if isinstance(radius, numbers.Real) else math.nan
        except TypeError:
            r = math.nan
        if not (math.isfinite(r) and r > 0):
            huge = isinstance(radius, numbers.Integral) and math.isinf(r)
            got = "an integer beyond float's range" if huge else repr(radius)
            raise PolygonError(f"{name}: radius must be > 0 and finite, got {got}")
        radius = r
        phase = -math.pi / 2 - math.pi / n
        verts = [
            (
                radius * math.cos(phase + 2 * math.pi * i / n),
                radius * math.sin(phase + 2 * math.pi * i / n),
            )
            for i in range(n)
        ]
        return cls(vertices=verts, **kwargs)

    @property
    def mass(self):
        return mass_properties(self.vertices, self.density)[0]

    @property
    def inertia(self):
        """Moment of inertia about the centre of mass, kg m^2."""
        return mass_properties(self.vertices, self.density)[2]

    @property
    def centroid(self):
        """Centre of mass in the body frame, m (2,)."""
        return mass_properties(self.vertices, self.density)[1]

    @property
    def size(self):
        """Its thinnest width, m: the length its contact tolerances scale with
        (``sim.tolerances``; a plank's thickness, not its length)."""
        vertices = np.asarray(self.vertices, dtype=np.float64)
        return float(thinnest_width_many(vertices, np.array([0, len(vertices)]))[0])

    def to_dict(self):
        return {
            "vertices": self.vertices.tolist(),
            "position": list(self.position),
            "angle": self.angle,
            "velocity": list(self.velocity),
            "angular_velocity": self.angular_velocity,
            "density": self.density,
            "friction": self.friction,
            "restitution": self.restitution,
            **({"name": self.name} if self.name else {}),
            **({"bullet": True} if self.bullet else {}),
        }  # absent = False: older files stay valid
