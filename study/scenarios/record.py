"""The failure catalogue's record and the geometry its classifiers read: ``Scenario`` (one entry:
builder, duration, expected outcome, classifier and measure, with the final pose validated before
either reads it), the constants every scene shares (gravity, when a scheduled projectile arrives)
and the geometry of a final pose (``wrap``, ``world_vertices``, ``bottom``, ``index``,
``key_bodies``). See the package docstring (``study/scenarios/__init__.py``) for the catalogue."""

from dataclasses import dataclass
import inspect
from typing import Callable

import numpy as np

from sim import geometry

G = 9.81  # m/s^2, every scene's gravity (sim.Scene's default)
ARRIVE_S = 3.5  # s, when a scheduled projectile reaches its target (see the package docstring)


@dataclass(frozen=True)
class Scenario:
    """One entry of the catalogue (see the package docstring)."""

    name: str
    question: str  # what can go wrong, and whose limit it is
    builder: Callable  # builder(**params) -> sim.Scene
    seconds: float  # s simulated
    expected: str  # the outcome physics says
    labels: tuple  # every label classify can return
    classifier: Callable  # classifier(scene, positions, angles) -> label
    measurer: Callable  # measurer(scene, positions, angles) -> float
    measure_name: str  # what measure() returns, with its unit in the name
    event_s: float | None = None  # s, when the danger arrives (None: from the start)

    @property
    def params(self):
        """The builder's parameters and their defaults (the catalogue's scene)."""
        return {k: p.default for k, p in inspect.signature(self.builder).parameters.items()}

    def build(self, **overrides):
        """The scene, with parameters overridden by keyword (unknown names are an error)."""
        unknown = sorted(set(overrides) - set(self.params))
        if unknown:
            raise ValueError(
                f"scenario {self.name}: unknown parameter(s) {', '.join(unknown)}; "
                f"it takes {', '.join(sorted(self.params)) or 'none'}"
            )
        return self.builder(**{**self.params, **overrides})

    def classify(self, scene, positions, angles):
        """The outcome label of a final pose: positions (N,2) m, angles (N,) rad."""
        positions, angles = _pose(scene, positions, angles)
        label = self.classifier(scene, positions, angles)
        if label not in self.labels:
            raise RuntimeError(
                f"scenario {self.name}: classifier returned {label!r}, not one of {self.labels}"
            )
        return label

    def measure(self, scene, positions, angles):
        """The continuous quantity behind the label (``measure_name``), of a final pose."""
        positions, angles = _pose(scene, positions, angles)
        return float(self.measurer(scene, positions, angles))

    def event_time(self, scene):
        """When the danger arrives in ``scene``, s (its ``arrive_s`` if it was built with
        another), or None when it is there from the start."""
        if self.event_s is None:
            return None
        return float(scene.params.get("arrive_s", self.event_s))

    def duration(self, scene):
        """Seconds to run ``scene`` (a scene may carry its own, as slope_creep does: its
        expected distance depends on it)."""
        return float(scene.params.get("seconds", self.seconds))


def _pose(scene, positions, angles):
    """Validated (N,2) m and (N,) rad arrays for ``scene``'s bodies."""
    positions = np.asarray(positions, dtype=float)
    angles = np.asarray(angles, dtype=float)
    n = len(scene.bodies)
    if positions.shape != (n, 2) or angles.shape != (n,):
        raise ValueError(
            f"scene {scene.name}: expected positions ({n}, 2) and angles ({n},), "
            f"got {positions.shape} and {angles.shape}"
        )
    if not (np.isfinite(positions).all() and np.isfinite(angles).all()):
        raise ValueError(f"scene {scene.name}: the pose is not finite")
    return positions, angles


# ---- geometry of a final pose ------------------------------------------------------------------
def wrap(angle):
    """Angle(s) mapped to (-pi, pi], rad (engines report unwrapped angles)."""
    return np.angle(np.exp(1j * np.asarray(angle, dtype=float)))


def world_vertices(scene, i, position, angle):
    """(K,2) m: world vertices of dynamic body ``i`` with its centre of mass at ``position``."""
    body = scene.bodies[i]
    return geometry.place(body.vertices - body.centroid, position, angle)


def bottom(scene, positions, angles, i):
    """Lowest point of body ``i``, m."""
    return float(world_vertices(scene, i, positions[i], angles[i])[:, 1].min())


def index(scene, name):
    """Index of the dynamic body called ``name`` (builders name every body they place)."""
    for i, b in enumerate(scene.bodies):
        if b.name == name:
            return i
    raise ValueError(f"scene {scene.name}: no body named {name!r}")


def key_bodies(scene):
    """Indices of every body that is not a projectile: the structure the question is about.
    (A projectile's own end pose says nothing about freezing and can lie anywhere.)"""
    return [i for i, b in enumerate(scene.bodies) if not b.name.startswith("projectile")]
