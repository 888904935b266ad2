"""How ``study.peers.pybullet_runner`` describes a ``sim.Scene``'s polygons to Bullet: the URDF
and Wavefront OBJ texts it writes and loads, and the scene geometry they are made from (each
body's centre of mass and vertices about it, the scene's x extent, a sim angle as Bullet's
quaternion). The axes are the runner's (sim's plane is Bullet's x-z plane; a sim angle theta is a
rotation by -theta about Bullet's +y; see its docstring).

- The link frame is the centre of mass; mass and moment about y are sim's own values
  (URDF_USE_INERTIA_FROM_FILE; the body is extruded 1 m in y, density unchanged, so the mass and
  the moment about the extrusion axis equal sim's 2D values).
- Shapes: an axis-aligned rectangle (in the body frame) becomes a URDF box, anything else a convex
  OBJ mesh (the polygon extruded in y). Bullet inflates a convex hull by its collision margin
  (0.001 m) but keeps a box's surface where it is, so meshes are inset by the margin: the contact
  surface is then the polygon itself, with corners rounded by 1 mm.
- Numbers are written as ``repr(float(x))``, which reads back to the same double.
"""

import math
from pathlib import Path

import numpy as np


from .pose import com_pose

#: Bullet's collision margin for URDF shapes, m; meshes are inset by it.
COLLISION_MARGIN = 0.001
#: Half the extrusion depth in y, m.
HALF_DEPTH = 0.5


def x_extent(scene):
    """Smallest and largest x any body or static polygon reaches at the start, m."""
    xs = [
        c[0] + sign * float(np.max(np.hypot(local[:, 0], local[:, 1])))
        for b in list(scene.bodies) + list(scene.static_bodies)
        for c, local, _, _ in [com_pose(b)]
        for sign in (-1.0, 1.0)
    ]
    return min(xs), max(xs)


def _num(x):
    """A number as text that reads back to the same double (numpy scalars included)."""
    return repr(float(x))


def box_size(local):
    """(width, height) if ``local`` (K,2) is an axis-aligned rectangle centred on the origin
    (within 1e-12 of its size), else None."""
    v = np.asarray(local, dtype=np.float64)
    if len(v) != 4:
        return None
    w, h = np.abs(v).max(axis=0)
    tol = 1e-12 * max(w, h)
    corners = {(1, 1), (1, -1), (-1, 1), (-1, -1)}
    found = set()
    for x, y in v:
        if abs(abs(x) - w) > tol or abs(abs(y) - h) > tol:
            return None
        found.add((int(math.copysign(1, x)), int(math.copysign(1, y))))
    return (2.0 * float(w), 2.0 * float(h)) if found == corners else None


def inset(local, distance):
    """The convex CCW polygon (K,2) with every edge moved ``distance`` inwards."""
    v = np.asarray(local, dtype=np.float64)
    e = np.roll(v, -1, axis=0) - v
    n = np.stack([e[:, 1], -e[:, 0]], axis=1)
    n /= np.hypot(n[:, 0], n[:, 1])[:, None]  # outward normal of edge i (v_i -> v_i+1)
    n_prev = np.roll(n, 1, axis=0)  # edge ending at vertex i
    # vertex i moves to where the two offset edges meet: along n_prev + n by d / (1 + n_prev.n)
    denom = 1.0 + np.einsum("ij,ij->i", n_prev, n)
    return v - distance * (n_prev + n) / denom[:, None]


def _obj_text(local):
    """A Wavefront OBJ of the polygon (K,2) extruded over y in [-HALF_DEPTH, HALF_DEPTH], inset by
    the collision margin in every direction."""
    v = inset(local, COLLISION_MARGIN)
    k = len(v)
    y = HALF_DEPTH - COLLISION_MARGIN
    lines = [f"v {_num(x)} {_num(-y)} {_num(z)}" for x, z in v] + [
        f"v {_num(x)} {_num(y)} {_num(z)}" for x, z in v
    ]
    for i in range(1, k - 1):  # caps as fans (OBJ indices from 1)
        lines.append(f"f 1 {i + 2} {i + 1}")
        lines.append(f"f {k + 1} {k + i + 1} {k + i + 2}")
    for i in range(k):  # sides as two triangles each
        j = (i + 1) % k
        lines.append(f"f {i + 1} {j + 1} {k + j + 1}")
        lines.append(f"f {i + 1} {k + j + 1} {k + i + 1}")
    return "\n".join(lines) + "\n"


def geometry_xml(local, folder, stem):
    """The URDF ``<geometry>`` element of the polygon ``local`` (K,2), about its centre of mass,
    and its kind ("box" or "mesh"): a box if it is an axis-aligned rectangle, else a convex mesh
    written to ``folder``/``stem``.obj."""
    size = box_size(local)
    if size is not None:
        return f'<box size="{_num(size[0])} {_num(2 * HALF_DEPTH)} {_num(size[1])}"/>', "box"
    path = Path(folder) / f"{stem}.obj"
    path.write_text(_obj_text(local))
    return f'<mesh filename="{path}" scale="1 1 1"/>', "mesh"


def dynamic_urdf(geometry, mass, inertia, com, angle):
    """A fixed massless base and a link on a planar joint (axis y) at the body's initial pose."""
    # Only rotation about y is possible; ixx and izz just need to be valid (positive, triangle
    # inequality), so they repeat iyy.
    i = _num(inertia)
    return f"""<?xml version="1.0"?>
<robot name="body">
  <link name="base">
    <inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
  </link>
  <joint name="plane" type="planar">
    <parent link="base"/>
    <child link="body"/>
    <origin xyz="{_num(com[0])} 0 {_num(com[1])}" rpy="0 {_num(-angle)} 0"/>
    <axis xyz="0 1 0"/>
    <dynamics damping="0" friction="0"/>
  </joint>
  <link name="body">
    <inertial>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <mass value="{_num(mass)}"/>
      <inertia ixx="{i}" ixy="0" ixz="0" iyy="{i}" iyz="0" izz="{i}"/>
    </inertial>
    <collision><origin xyz="0 0 0" rpy="0 0 0"/><geometry>{geometry}</geometry></collision>
  </link>
</robot>
"""


def static_urdf(geometry):
    """A single fixed massless link with the collision ``geometry`` (placed by loadURDF's base
    pose)."""
    return f"""<?xml version="1.0"?>
<robot name="static">
  <link name="body">
    <inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
    <collision><origin xyz="0 0 0" rpy="0 0 0"/><geometry>{geometry}</geometry></collision>
  </link>
</robot>
"""


def pitch_quaternion(angle):
    """Bullet quaternion (x, y, z, w) of the sim angle ``angle``: a rotation by -angle about y."""
    return (0.0, math.sin(-0.5 * angle), 0.0, math.cos(-0.5 * angle))
