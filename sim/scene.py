"""``sim.Scene``: bodies, static polygons, the floor and gravity. Loadable from / writable to TOML.

A scene's dynamic bodies are either a list of ``sim.Body`` (``Scene(bodies=[...])``) or arrays
(``Scene.from_arrays``). Arrays exist for scale: 10^6 Body objects take seconds to minutes to
create and check one by one (more for varied polygons), the same bodies as arrays are checked in
a fraction of a second. An array-backed scene creates its Body objects only if ``scene.bodies``
is read; from then on that list is the scene's truth (edits to those bodies are seen, as in any
Body-list scene)."""

import copy as _copy
from dataclasses import dataclass, field
import tomllib
from typing import NamedTuple

import numpy as np
import tomli_w

from .body import Body, check_fields, failing_fields, finite_number, finite_pair
from .files import check_seal, seal, write_text_atomically
from .arguments import kind_of, numeric_array, plain_copy
from .polygons import check_packed, polygon_suspects, validate_polygon


class BodyArrays(NamedTuple):
    """The N dynamic bodies of an array-backed Scene: validated, read-only (the fields of
    ``sim.Body``, one row per body)."""

    vertices: np.ndarray  # (V,2) m, body frame, every body's polygon concatenated
    vert_start: np.ndarray  # (N+1,) int64: body i's vertices are rows vert_start[i]:vert_start[i+1]
    position: np.ndarray  # (N,2) m, where each body frame's origin is placed
    angle: np.ndarray  # (N,) rad, CCW
    velocity: np.ndarray  # (N,2) m/s of the centre of mass
    angular_velocity: np.ndarray  # (N,) rad/s
    density: np.ndarray  # (N,) kg/m^2
    friction: np.ndarray  # (N,) Coulomb mu
    restitution: np.ndarray  # (N,) in [0, 1]
    bullet: np.ndarray  # (N,) bool
    names: tuple | None  # N str ("" = unnamed: "body <i>" in messages), or None

    def body_name(self, i):
        """Name of body ``i`` for messages."""
        return (self.names[i] if self.names is not None else "") or f"body {i}"

    @classmethod
    def from_bodies(cls, bodies):
        """The fields of validated Body objects gathered into arrays (one pass each, no checks:
        validate the bodies first, as ``Scene.validate`` does)."""
        n = len(bodies)
        vert_start = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(np.fromiter((len(b.vertices) for b in bodies), np.int64, n), out=vert_start[1:])
        vertices = np.concatenate([b.vertices for b in bodies]) if n else np.empty((0, 2))
        return cls(
            vertices=vertices.astype(np.float64, copy=False),
            vert_start=vert_start,
            position=np.array([b.position for b in bodies], np.float64).reshape(n, 2),
            angle=np.array([b.angle for b in bodies], np.float64),
            velocity=np.array([b.velocity for b in bodies], np.float64).reshape(n, 2),
            angular_velocity=np.array([b.angular_velocity for b in bodies], np.float64),
            density=np.array([b.density for b in bodies], np.float64),
            friction=np.array([b.friction for b in bodies], np.float64),
            restitution=np.array([b.restitution for b in bodies], np.float64),
            bullet=np.array([b.bullet for b in bodies], dtype=bool),
            names=tuple(b.name for b in bodies),
        )


@dataclass
class Scene:
    """Everything a run needs besides solver settings.

    bodies          dynamic bodies; their order is the index order of every World array.
    static_bodies   fixed polygons (walls, ledges); density is ignored, velocities must be zero.
    floor_y         m, the floor is the half-plane y <= floor_y; ``None`` means no floor.
    gravity         (2,) m/s^2.
    floor_friction, floor_restitution: the floor's material (and the static bodies' own fields).
    name, params    what built the scene; recorded in every results file.

    ``n_bodies`` counts the dynamic bodies without creating Body objects of an array-backed
    scene, and ``body_arrays`` gives that scene's arrays (None for a Body-list scene).
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
        """Check every body and field; raise ValueError naming the first problem. An array-backed
        scene's dynamic bodies were checked when it was built and their arrays are read-only, so
        for them this costs nothing."""
        if self.body_arrays is None:
            if not isinstance(self.bodies, (list, tuple)):
                # a lone Body or a generator was reported as "no body"
                hint = " (put it in a list)" if isinstance(self.bodies, Body) else ""
                raise ValueError(
                    f"scene: bodies must be a list of sim.Body, got "
                    f"{type(self.bodies).__name__}{hint}"
                )
            if len(self.bodies) == 0:
                raise ValueError("scene: needs at least one body in `bodies`")
            self.bodies = list(self.bodies)
            _check_bodies(self.bodies, "body")
        if self.static_bodies is None or isinstance(self.static_bodies, (str, bytes)):
            raise ValueError(
                f"static_bodies must be a list of sim.Body, got {self.static_bodies!r}"
            )
        try:
            self.static_bodies = list(self.static_bodies)
        except TypeError:
            raise ValueError(
                f"static_bodies must be a list of sim.Body, got {self.static_bodies!r}"
            ) from None
        _check_bodies(self.static_bodies, "static body")
        for i, b in enumerate(self.static_bodies):
            if b.velocity != (0.0, 0.0) or b.angular_velocity != 0.0:
                raise ValueError(
                    f"static body {i}: static bodies cannot move (velocity must be zero)"
                )
        if not isinstance(self.name, str):
            raise ValueError(f"scene: name must be a string, got {self.name!r}")
        if not isinstance(self.params, dict):
            raise ValueError(f"scene: params must be a dict, got {self.params!r}")
        if self.floor_y is not None:
            self.floor_y = finite_number(self.floor_y, "floor_y", "scene")
        self.gravity = finite_pair(self.gravity, "gravity", "scene")
        self.floor_friction = finite_number(self.floor_friction, "floor_friction", "scene")
        if self.floor_friction < 0:
            raise ValueError(f"scene: floor_friction must be >= 0, got {self.floor_friction}")
        self.floor_restitution = finite_number(self.floor_restitution, "floor_restitution", "scene")
        if not 0.0 <= self.floor_restitution <= 1.0:
            raise ValueError(
                f"scene: floor_restitution must be in [0, 1], got {self.floor_restitution}"
            )

    # ---- array-backed scenes ------------------------------------------------------------------
    @classmethod
    def from_arrays(
        cls,
        vertices,
        position,
        *,
        vert_start=None,
        angle=0.0,
        velocity=(0.0, 0.0),
        angular_velocity=0.0,
        density=1.0,
        friction=0.5,
        restitution=0.0,
        bullet=False,
        names=None,
        static_bodies=(),
        floor_y=0.0,
        gravity=(0.0, -9.81),
        floor_friction=0.6,
        floor_restitution=0.0,
        name="custom",
        params=None,
    ):
        """A scene of N dynamic bodies given as arrays, without creating Body objects.

        vertices   m, body frame, counter-clockwise: (K,2) one polygon shared by every body,
                   (N,K,2) one per body, or (V,2) all polygons concatenated with ``vert_start``
                   (N+1,) int offsets (body i is rows vert_start[i]:vert_start[i+1]).
        position   (N,2) m: N is the number of bodies.
        angle, angular_velocity, density, friction, restitution: a number for all, or (N,).
        velocity   a pair for all, or (N,2) m/s.    bullet: a bool for all, or (N,) bool.
        names      None, or N strings ("" = unnamed: "body <i>" in messages).
        The other arguments are the Scene fields. Bodies obey the rules of ``sim.Body`` and a
        bad one is refused with the message the same Body in a Body-list scene would get; a bad
        argument shape with a ValueError naming the argument and the expected shape."""
        arrays = _body_arrays(
            vertices,
            vert_start,
            position,
            angle,
            velocity,
            angular_velocity,
            density,
            friction,
            restitution,
            bullet,
            names,
        )
        scene = object.__new__(cls)
        scene.floor_y, scene.gravity = floor_y, gravity
        scene.floor_friction, scene.floor_restitution = floor_friction, floor_restitution
        scene.static_bodies, scene.name = static_bodies, name
        # a copy of a dict; anything else as given, for validate() to refuse in the Scene's own
        # words (dict(5) was a TypeError)
        scene.params = dict(params) if isinstance(params, dict) else params
        if params is None:
            scene.params = {}
        scene._arrays = arrays
        scene.validate()
        return scene

    def snapshot(self):
        """This scene as it stands now, as a separate array-backed Scene: later edits to this one
        (its fields, its body list, its bodies) do not reach the snapshot, nor the reverse.
        What a World or a runner keeps: a run must not half-see an edit made after it was built
        (``potential_energy`` used the new gravity while the steps kept the old). Cheap: the
        bodies are gathered into arrays once (``pack`` reuses them), not copied one by one."""
        self.validate()
        arrays = self.body_arrays
        if arrays is None:
            arrays = BodyArrays.from_bodies(self.bodies)
            for a in arrays[:-1]:
                a.flags.writeable = False  # as in every array-backed scene
        copy = object.__new__(type(self))
        copy.floor_y, copy.gravity = self.floor_y, tuple(self.gravity)
        copy.floor_friction, copy.floor_restitution = self.floor_friction, self.floor_restitution
        copy.static_bodies = _copy.deepcopy(self.static_bodies)
        copy.name, copy.params = self.name, plain_copy(self.params, "scene: params")
        copy._arrays = arrays
        return copy

    @property
    def body_arrays(self):
        """The dynamic bodies as ``BodyArrays`` while the scene is array-backed; None once
        ``bodies`` is a list of Body (given as one, or created from the arrays on first use)."""
        return None if "bodies" in self.__dict__ else self.__dict__.get("_arrays")

    def __getattr__(self, attr):
        # Runs only when normal lookup fails: for `bodies` of an array-backed scene, on first use.
        arrays = self.__dict__.get("_arrays")
        if attr == "bodies" and arrays is not None:
            self.bodies = _materialise(arrays)
            self._arrays = None  # the Body list is the truth from now on
            return self.bodies
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {attr!r}")

    @property
    def n_bodies(self):
        """Number of dynamic bodies (creates no Body objects)."""
        arrays = self.body_arrays
        return len(arrays.position) if arrays is not None else len(self.bodies)

    def body_name(self, i):
        """Name of dynamic body ``i`` for messages."""
        arrays = self.body_arrays
        if arrays is not None:
            return arrays.body_name(i)
        b = self.bodies[i]
        return b.name or f"body {i}"

    def __repr__(self):
        arrays = self.body_arrays
        bodies = (
            f"<{len(arrays.position)} bodies in arrays>"
            if arrays is not None
            else repr(self.bodies)
        )
        return (
            f"Scene(bodies={bodies}, floor_y={self.floor_y!r}, gravity={self.gravity!r}, "
            f"floor_friction={self.floor_friction!r}, "
            f"floor_restitution={self.floor_restitution!r}, "
            f"static_bodies={self.static_bodies!r}, name={self.name!r}, params={self.params!r})"
        )

    # ---- files -------------------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data):
        """A scene from the dict ``to_dict`` gives (and ``from_file`` reads): ValueError naming
        the entry ("body 3", "static body 0 (wall)") and the field for a bad one."""
        if not isinstance(data, dict):
            raise ValueError(f"scene: expected a table of scene fields, got {type(data).__name__}")
        data = dict(data)
        bodies = _from_entries(data.pop("bodies", []), "body")
        statics = _from_entries(data.pop("static_bodies", []), "static body")
        if data.get("floor_y", 0.0) == "none":
            data["floor_y"] = None
        try:
            return cls(bodies=bodies, static_bodies=statics, **data)
        except TypeError as exc:  # unknown or missing keys
            raise ValueError(f"scene: {exc}") from None

    @classmethod
    def from_file(cls, path):
        """Load a scene from TOML: top-level scene fields, ``[[bodies]]`` and ``[[static_bodies]]``
        tables with Body fields (or ``box = [w, h]`` instead of ``vertices``). ``floor_y = "none"``
        removes the floor. Every error in the file's contents is a ValueError that starts with
        the file's path; a file that cannot be opened raises the OSError open() raises."""
        with open(path, "rb") as f:
            try:
                data = tomllib.load(f)
            except tomllib.TOMLDecodeError as exc:
                raise ValueError(f"{path}: not valid TOML ({exc})") from None
            except UnicodeDecodeError as exc:  # a binary file, or not UTF-8
                raise ValueError(f"{path}: not valid TOML (not UTF-8 text: {exc})") from None
            except RecursionError:  # tomllib parses nested arrays recursively
                raise ValueError(
                    f"{path}: not valid TOML for a scene (nested too deeply)"
                ) from None
        data = check_seal(data, tomli_w.dumps, path)  # cut short or edited since written
        data.setdefault("name", str(path))
        try:
            return cls.from_dict(data)
        except ValueError as exc:
            raise ValueError(f"{path}: {exc}") from None

    def to_dict(self):
        return {
            "name": self.name,
            "params": dict(self.params),
            "floor_y": "none" if self.floor_y is None else self.floor_y,
            "gravity": list(self.gravity),
            "floor_friction": self.floor_friction,
            "floor_restitution": self.floor_restitution,
            "bodies": (
                _body_dicts(self.body_arrays)
                if self.body_arrays is not None
                else [b.to_dict() for b in self.bodies]
            ),
            "static_bodies": [b.to_dict() for b in self.static_bodies],
        }

    def to_file(self, path):
        """Write the scene as TOML that ``from_file`` reads back to an equal scene (any name,
        any string params key; another key is a ValueError). The text is made before the file
        is touched, and written atomically: a value TOML cannot hold is a ValueError, and a
        failed write leaves the old file whole."""
        try:
            text = tomli_w.dumps(seal(self.to_dict(), tomli_w.dumps))
        except TypeError as exc:  # e.g. None or an object in params
            raise ValueError(f"scene {self.name!r}: cannot be written as TOML ({exc})") from None
        write_text_atomically(path, text)


def _from_entries(entries, kind):
    """Body objects from a scene file's ``[[bodies]]`` (or ``[[static_bodies]]``) tables; a bad
    entry is a ValueError naming it by index (and name, if it has one) and the field."""
    if not isinstance(entries, (list, tuple)):
        raise ValueError(f"{kind} entries must be a list of tables, got {type(entries).__name__}")
    out = []
    for i, e in enumerate(entries):
        if not isinstance(e, dict):
            raise ValueError(f"{kind} {i}: expected a table of body fields, got {e!r}")
        e = dict(e)
        name = e.get("name")
        where = f"{kind} {i}" + (f" ({name})" if isinstance(name, str) and name else "")
        try:
            if "box" in e:  # shorthand: box = [width, height]
                box = e.pop("box")
                if not isinstance(box, (list, tuple)) or len(box) != 2:
                    raise ValueError(f"box must be [width, height], got {box!r}")
                out.append(Body.box(*box, **e))
            elif "vertices" in e:
                out.append(Body(**e))
            else:
                raise ValueError("needs `vertices` or `box = [width, height]`")
        except TypeError as exc:  # unknown or missing fields
            raise ValueError(f"{where}: {exc}") from None
        except ValueError as exc:
            # Body's own messages start with its name, or "body" when unnamed: say which entry
            message = str(exc)
            unnamed = ("body: ", "box: ")  # Body's and Body.box's default names
            for prefix in (f"{name}: ",) if isinstance(name, str) and name else unnamed:
                if message.startswith(prefix):
                    message = message[len(prefix) :]
            raise ValueError(f"{where}: {message}") from None
    return out


def _check_bodies(bodies, kind):
    """Each of ``bodies`` must be a valid sim.Body; messages name "<kind> <i>" or the body."""
    for i, b in enumerate(bodies):
        if not isinstance(b, Body):
            raise ValueError(f"{kind} {i}: expected sim.Body, got {type(b).__name__}")
        b.validate(b.name if isinstance(b.name, str) and b.name else f"{kind} {i}")


# ---- array-backed scenes: arguments to BodyArrays, BodyArrays to Body objects and dicts ---------
def _floats(value, what):
    try:
        a = np.array(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError) as exc:  # the last: an int beyond float's range
        raise ValueError(f"Scene.from_arrays: {what} must be numbers ({exc})") from None
    if not numeric_array(value):  # float64 took text, switches or complex numbers
        raise ValueError(
            f"Scene.from_arrays: {what} must be numbers, not text, switches or complex numbers "
            f"(got {kind_of(value)})"
        )
    return a


def _per_body(value, n, what):
    """(n,) float64 from a number or an (n,) array."""
    a = _floats(value, what)
    if a.ndim == 0:
        return np.full(n, float(a))
    if a.shape != (n,):
        raise ValueError(
            f"Scene.from_arrays: {what} must be a number or have shape (N,) = ({n},), "
            f"got shape {a.shape}"
        )
    return a


def _per_body_pair(value, n, what):
    """(n,2) float64 from one pair or an (n,2) array."""
    a = _floats(value, what)
    if a.shape == (2,):
        return np.tile(a, (n, 1))
    if a.shape != (n, 2):
        raise ValueError(
            f"Scene.from_arrays: {what} must be a pair or have shape (N, 2) = ({n}, 2), "
            f"got shape {a.shape}"
        )
    return a


def _packed_vertices(vertices, vert_start, n):
    """(vertices (V,2), vert_start (n+1,) int64, shared): the polygons packed; ``shared`` when one
    (K,2) polygon was given for every body (it is then checked once)."""
    v = _floats(vertices, "vertices")
    if vert_start is not None:
        try:
            v, starts = check_packed(v, vert_start)
        except ValueError as exc:
            raise ValueError(f"Scene.from_arrays: {exc}") from None
        if len(starts) != n + 1:
            raise ValueError(
                f"Scene.from_arrays: vert_start must have shape (N+1,) = ({n + 1},), "
                f"got shape {starts.shape}"
            )
        return v, starts.copy(), False
    if v.ndim == 2 and v.shape[1] == 2:
        k = len(v)
        return np.tile(v, (n, 1)), np.arange(n + 1, dtype=np.int64) * k, True
    if v.ndim == 3 and v.shape[0] == n and v.shape[2] == 2:
        k = v.shape[1]
        return v.reshape(n * k, 2), np.arange(n + 1, dtype=np.int64) * k, False
    raise ValueError(
        f"Scene.from_arrays: vertices must have shape (K, 2) (one polygon for every "
        f"body), (N, K, 2) = ({n}, K, 2), or (V, 2) with vert_start, got shape {v.shape}"
    )


def _bullets(value, n):
    """(flags (n,), ok (n,) bool): ok is False where a flag is not a bool (Body's rule; a list
    is read element by element, so that [True, 1] blames the 1)."""
    a = value if isinstance(value, np.ndarray) else np.array(value, dtype=object)
    if a.ndim == 0:
        a = np.full(n, a[()], dtype=a.dtype)
    if a.shape != (n,):
        raise ValueError(
            f"Scene.from_arrays: bullet must be a bool or have shape (N,) = ({n},), "
            f"got shape {a.shape}"
        )
    if a.dtype == bool:
        return a, np.ones(n, dtype=bool)
    if a.dtype == object:
        return a, np.fromiter((isinstance(x, (bool, np.bool_)) for x in a), dtype=bool, count=n)
    return a, np.zeros(n, dtype=bool)


def _names(names, n):
    if names is None:
        return None
    try:
        names = () if isinstance(names, (str, bytes)) else tuple(names)
    except TypeError:  # not a collection at all
        names = ()
    if len(names) != n or not all(isinstance(s, str) for s in names):
        raise ValueError(f"Scene.from_arrays: names must be None or N = {n} strings")
    return tuple(map(str, names))


def _body_arrays(
    vertices,
    vert_start,
    position,
    angle,
    velocity,
    angular_velocity,
    density,
    friction,
    restitution,
    bullet,
    names,
):
    """Validated, read-only BodyArrays from Scene.from_arrays' arguments."""
    position = _floats(position, "position")
    if position.ndim != 2 or position.shape[1] != 2:
        raise ValueError(
            f"Scene.from_arrays: position must have shape (N, 2), got shape {position.shape}"
        )
    n = len(position)
    if n == 0:
        raise ValueError("scene: needs at least one body in `bodies`")
    verts, starts, shared = _packed_vertices(vertices, vert_start, n)
    angle = _per_body(angle, n, "angle")
    velocity = _per_body_pair(velocity, n, "velocity")
    angular_velocity = _per_body(angular_velocity, n, "angular_velocity")
    density = _per_body(density, n, "density")
    friction = _per_body(friction, n, "friction")
    restitution = _per_body(restitution, n, "restitution")
    bullet, bullet_ok = _bullets(bullet, n)
    names = _names(names, n)
    arrays = BodyArrays(
        verts,
        starts,
        position,
        angle,
        velocity,
        angular_velocity,
        density,
        friction,
        restitution,
        bullet,
        names,
    )
    # Screen every body at once; the one-body checks then give the first failure its message.
    if shared:
        suspect = np.repeat(polygon_suspects(verts[starts[0] : starts[1]], starts[:2]), n)
    else:
        suspect = polygon_suspects(verts, starts)
    suspect |= failing_fields(
        position, velocity, angle, angular_velocity, density, friction, restitution
    )
    suspect |= ~bullet_ok
    for i in np.flatnonzero(suspect).tolist():
        name = arrays.body_name(i)
        validate_polygon(verts[starts[i] : starts[i + 1]], name)
        check_fields(
            name,
            position[i].tolist(),
            velocity[i].tolist(),
            float(angle[i]),
            float(angular_velocity[i]),
            float(density[i]),
            float(friction[i]),
            float(restitution[i]),
            bullet[i] if bullet.dtype == object else bullet[i].item(),
        )
    arrays = arrays._replace(bullet=bullet.astype(bool))
    for a in arrays[:-1]:
        a.flags.writeable = False  # validated once: edits must go through `bodies`
    return arrays


def _materialise(a):
    """Body objects of BodyArrays, without checking again (they were checked as arrays)."""
    verts = a.vertices.copy()  # writable; each body gets a view of its rows
    starts = a.vert_start.tolist()
    position, velocity = a.position.tolist(), a.velocity.tolist()
    angle, spin = a.angle.tolist(), a.angular_velocity.tolist()
    density, friction, restitution = a.density.tolist(), a.friction.tolist(), a.restitution.tolist()
    bullet = a.bullet.tolist()
    names = a.names if a.names is not None else ("",) * len(position)
    return [
        Body.prevalidated(
            verts[starts[i] : starts[i + 1]],
            tuple(position[i]),
            angle[i],
            tuple(velocity[i]),
            spin[i],
            density[i],
            friction[i],
            restitution[i],
            names[i],
            bullet[i],
        )
        for i in range(len(position))
    ]


def _body_dicts(a):
    """``Body.to_dict`` of every body of BodyArrays, without creating the bodies."""
    verts = a.vertices.tolist()
    starts = a.vert_start.tolist()
    position, velocity = a.position.tolist(), a.velocity.tolist()
    angle, spin = a.angle.tolist(), a.angular_velocity.tolist()
    density, friction, restitution = a.density.tolist(), a.friction.tolist(), a.restitution.tolist()
    bullet = a.bullet.tolist()
    names = a.names if a.names is not None else ("",) * len(position)
    return [
        {
            "vertices": verts[starts[i] : starts[i + 1]],
            "position": position[i],
            "angle": angle[i],
            "velocity": velocity[i],
            "angular_velocity": spin[i],
            "density": density[i],
            "friction": friction[i],
            "restitution": restitution[i],
            **({"name": names[i]} if names[i] else {}),
            **({"bullet": True} if bullet[i] else {}),
        }
        for i in range(len(position))
    ]
