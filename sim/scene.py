"""``sim.Scene``: bodies, static polygons, the floor and gravity. Loadable from / writable to TOML."""
from dataclasses import dataclass, field
import math
import tomllib

from .body import Body, _finite, _finite_pair


@dataclass
class Scene:
    """Everything a run needs besides solver settings.

    bodies          dynamic bodies; their order is the index order of every World array.
    static_bodies   fixed polygons (walls, ledges); density is ignored, velocities must be zero.
    floor_y         m, the floor is the half-plane y <= floor_y; ``None`` means no floor.
    gravity         (2,) m/s^2.
    floor_friction, floor_restitution: the floor's material (and the static bodies' own fields).
    name, params    what built the scene; recorded in every results file.
    """
    bodies: list
    floor_y: float | None = 0.0
    gravity: tuple = (0.0, -9.81)
    floor_friction: float = 0.6
    floor_restitution: float = 0.0
    static_bodies: list = field(default_factory=list)
    name: str = "custom"
    params: dict = field(default_factory=dict)

    def __post_init__(self):
        self.validate()

    def validate(self):
        if not isinstance(self.bodies, (list, tuple)) or len(self.bodies) == 0:
            raise ValueError("scene: needs at least one body in `bodies`")
        self.bodies = list(self.bodies)
        self.static_bodies = list(self.static_bodies)
        for kind, seq in (("body", self.bodies), ("static body", self.static_bodies)):
            for i, b in enumerate(seq):
                if not isinstance(b, Body):
                    raise ValueError(f"{kind} {i}: expected sim.Body, got {type(b).__name__}")
                b.validate(b.name or f"{kind} {i}")
        for i, b in enumerate(self.static_bodies):
            if b.velocity != (0.0, 0.0) or b.angular_velocity != 0.0:
                raise ValueError(f"static body {i}: static bodies cannot move (velocity must be zero)")
        if self.floor_y is not None:
            self.floor_y = _finite(self.floor_y, "floor_y", "scene")
        self.gravity = _finite_pair(self.gravity, "gravity", "scene")
        self.floor_friction = _finite(self.floor_friction, "floor_friction", "scene")
        if self.floor_friction < 0:
            raise ValueError(f"scene: floor_friction must be >= 0, got {self.floor_friction}")
        self.floor_restitution = _finite(self.floor_restitution, "floor_restitution", "scene")
        if not 0.0 <= self.floor_restitution <= 1.0:
            raise ValueError(f"scene: floor_restitution must be in [0, 1], got {self.floor_restitution}")

    def body_name(self, i):
        """Name of dynamic body ``i`` for messages."""
        b = self.bodies[i]
        return b.name or f"body {i}"

    # ---- files -------------------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data):
        data = dict(data)
        def make(entries, kind):
            out = []
            for i, e in enumerate(entries):
                e = dict(e)
                if "box" in e:                       # shorthand: box = [width, height]
                    w, h = e.pop("box")
                    out.append(Body.box(w, h, **e))
                elif "vertices" in e:
                    out.append(Body(**e))
                else:
                    raise ValueError(f"{kind} {i}: needs `vertices` or `box = [width, height]`")
            return out
        try:
            bodies = make(data.pop("bodies", []), "body")
            statics = make(data.pop("static_bodies", []), "static body")
            if data.get("floor_y", 0.0) == "none":
                data["floor_y"] = None
            return cls(bodies=bodies, static_bodies=statics, **data)
        except TypeError as exc:                     # unknown or missing keys
            raise ValueError(f"scene file: {exc}") from None

    @classmethod
    def from_file(cls, path):
        """Load a scene from TOML: top-level scene fields, ``[[bodies]]`` and ``[[static_bodies]]``
        tables with Body fields (or ``box = [w, h]`` instead of ``vertices``). ``floor_y = "none"``
        removes the floor."""
        with open(path, "rb") as f:
            try:
                data = tomllib.load(f)
            except tomllib.TOMLDecodeError as exc:
                raise ValueError(f"{path}: not valid TOML ({exc})") from None
        data.setdefault("name", str(path))
        return cls.from_dict(data)

    def to_dict(self):
        return {"name": self.name, "params": dict(self.params),
                "floor_y": "none" if self.floor_y is None else self.floor_y,
                "gravity": list(self.gravity), "floor_friction": self.floor_friction,
                "floor_restitution": self.floor_restitution,
                "bodies": [b.to_dict() for b in self.bodies],
                "static_bodies": [b.to_dict() for b in self.static_bodies]}

    def to_file(self, path):
        """Write the scene as TOML that ``from_file`` reads back to an equal scene."""
        with open(path, "w") as f:
            f.write(_toml(self.to_dict()))


def _toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(float(v)) if isinstance(v, float) and math.isfinite(v) else repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _toml(d):
    lines = [f"{k} = {_toml_value(v)}" for k, v in d.items() if not isinstance(v, list) or not v or not isinstance(v[0], dict)]
    for k, v in d.items():
        if isinstance(v, list) and v and isinstance(v[0], dict):
            for item in v:
                lines.append(f"\n[[{k}]]")
                lines.extend(f"{kk} = {_toml_value(vv)}" for kk, vv in item.items())
    return "\n".join(lines) + "\n"
