"""``sim.Body``: one convex polygon with its material and initial motion (validated on creation)."""
from dataclasses import dataclass, field
import math
import numbers

import numpy as np

from .geometry import PolygonError, mass_properties, validate_polygon

#: m; bodies beyond this are treated as diverged by the step loop (sim.kernel.MAX_COORDINATE)
MAX_COORDINATE = 1e12


def _finite_pair(value, what, name):
    try:
        x, y = (float(c) for c in value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: {what} must be a pair of numbers, got {value!r}") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"{name}: {what} is not finite: ({x}, {y})")
    return (x, y)


def _finite(value, what, name):
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: {what} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name}: {what} is not finite: {x}")
    return x


@dataclass
class Body:
    """A rigid convex polygon.

    vertices  (K,2) m, counter-clockwise, in the body frame. The body frame's origin is placed at
              ``position`` and rotated by ``angle``. The solver tracks the centre of mass: a World
              reports ``positions`` of centres of mass (equal to ``position`` when the vertices are
              centred on their centroid, as every builder in ``sim.scenes`` does).
    position  (2,) m; angle rad (CCW); velocity (2,) m/s of the centre of mass; angular_velocity rad/s.
    density   kg/m^2 (> 0). friction >= 0 (Coulomb mu, pairs mix by geometric mean);
              restitution in [0, 1] (pairs mix by max).
    name      used in error messages; defaults to "body <index>" once placed in a Scene.
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
    _centroid: np.ndarray = field(init=False, repr=False, compare=False)
    _validated: tuple = field(init=False, repr=False, compare=False, default=None)

    def __post_init__(self):
        self.validate(self.name or "body")

    def validate(self, name):
        """Check every field; raise ValueError naming ``name`` and the problem.

        A body is checked in full only when a field differs from the last time it passed (a
        cheap fingerprint of every field): scenes and Worlds re-validate their bodies, and the
        full check (~0.2 ms) made building a 10^4-body World cost seconds."""
        if self._validated is not None and self._validated == self._fingerprint():
            return
        self.vertices = validate_polygon(self.vertices, name)
        self.position = _finite_pair(self.position, "position", name)
        if max(abs(self.position[0]), abs(self.position[1])) > MAX_COORDINATE:
            raise ValueError(f"{name}: position {self.position} is beyond {MAX_COORDINATE:g} m, "
                             f"where the solver stops as diverged")
        self.velocity = _finite_pair(self.velocity, "velocity", name)
        self.angle = _finite(self.angle, "angle", name)
        self.angular_velocity = _finite(self.angular_velocity, "angular_velocity", name)
        self.density = _finite(self.density, "density", name)
        if self.density <= 0.0:
            raise ValueError(f"{name}: density must be > 0, got {self.density}")
        self.friction = _finite(self.friction, "friction", name)
        if self.friction < 0.0:
            raise ValueError(f"{name}: friction must be >= 0, got {self.friction}")
        self.restitution = _finite(self.restitution, "restitution", name)
        if not 0.0 <= self.restitution <= 1.0:
            raise ValueError(f"{name}: restitution must be in [0, 1], got {self.restitution}")
        _, self._centroid, _ = mass_properties(self.vertices, self.density)
        self._validated = self._fingerprint()

    def _fingerprint(self):
        """Every field as it stands, so that any change (in-place edits of the vertex array
        included) forces a full check."""
        v = self.vertices
        return (v.tobytes() if isinstance(v, np.ndarray) else repr(v), getattr(v, "shape", None),
                self.position, self.angle, self.velocity, self.angular_velocity, self.density,
                self.friction, self.restitution)

    @classmethod
    def box(cls, width, height, **kwargs):
        """A width x height rectangle centred on its centre of mass."""
        w, h = 0.5 * float(width), 0.5 * float(height)
        if not (w > 0 and h > 0):
            raise PolygonError(f"{kwargs.get('name') or 'box'}: width and height must be > 0, got {width} x {height}")
        return cls(vertices=[(-w, -h), (w, -h), (w, h), (-w, h)], **kwargs)

    @classmethod
    def regular(cls, n, radius, **kwargs):
        """A regular n-gon of circumradius ``radius``, centred, with a flat bottom edge."""
        name = kwargs.get("name") or "regular polygon"
        if isinstance(n, bool) or not isinstance(n, numbers.Integral):
            raise PolygonError(f"{name}: the vertex count must be an integer, got {n!r}")
        if not (isinstance(radius, numbers.Real) and math.isfinite(radius) and radius > 0):
            raise PolygonError(f"{name}: radius must be > 0 and finite, got {radius!r}")
        phase = -math.pi / 2 - math.pi / n
        verts = [(radius * math.cos(phase + 2 * math.pi * i / n), radius * math.sin(phase + 2 * math.pi * i / n))
                 for i in range(n)]
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
        """Centre of mass in the body frame, m."""
        return self._centroid.copy()

    def to_dict(self):
        return {"vertices": self.vertices.tolist(), "position": list(self.position), "angle": self.angle,
                "velocity": list(self.velocity), "angular_velocity": self.angular_velocity,
                "density": self.density, "friction": self.friction, "restitution": self.restitution,
                **({"name": self.name} if self.name else {})}
