"""Framing a bare mesh: a camera that shows all of it.

The camera sits on +Z looking along −Z with +Y up, as f3d's default view; a file with
another up axis (`--up +Z`) is turned to +Y first (SceneObject.up), which shows what f3d
shows when it turns its camera instead (from −Y, +Z up on screen). Unlike f3d's exact front
view the camera is raised 19° (direction (0, 0.35, 1)), so a shape lying flat, such as a
torus, is not seen edge-on.
"""

from __future__ import annotations

import math

import numpy as np
from pyglm import glm

from ...errors import SceneError
from ..camera import Camera
from ..mesh import Mesh
from ..objects import SceneObject
from ..values import Vec3, direction

_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}
# The view direction of the default framing (+Y up): from the front, a little above.
FRAMING_DIRECTION = (0.0, 0.35, 1.0)


def parse_direction(value: str | Vec3, name: str = "direction") -> Vec3:
    """A direction as f3d spells it: an axis '+Y', '-Z', 'X', or a vector 'X,Y,Z' / (x, y, z)
    (not normalized; zero is an error). `name` is the flag or key for the message."""
    if isinstance(value, str):
        text = value.strip().upper()
        sign = -1.0 if text.startswith("-") else 1.0
        axis = text.lstrip("+-")
        if axis in _AXES and len(text) - len(axis) <= 1:
            return tuple(sign * c for c in _AXES[axis])
        try:
            value = tuple(float(part) for part in text.split(","))
        except ValueError:
            raise SceneError(f"{name}: expected +X, -X, +Y, -Y, +Z, -Z or a direction X,Y,Z, got {value!r}") from None
    return direction(value, name)


def bounding_sphere(mesh: Mesh) -> tuple[np.ndarray, float]:
    """Centre and radius of the mesh's bounding box's sphere (world units)."""
    lower, upper = mesh.bounds()
    return (lower + upper) / 2.0, max(float(np.linalg.norm(upper - lower)) / 2.0, 1e-12)


def depth_range(eye, center, radius: float) -> tuple[float, float]:
    """near and far planes that enclose a sphere seen from `eye` (eye inside it: near tiny)."""
    distance = float(np.linalg.norm(np.asarray(eye, dtype=np.float64) - np.asarray(center, dtype=np.float64)))
    far = distance + 1.5 * radius
    return max(distance - 1.5 * radius, far * 1e-4), far


def object_depth_range(eye, obj: "SceneObject") -> tuple[float, float]:
    """near and far planes that enclose a placed object seen from `eye`: its mesh's bounding
    sphere moved by the object's model matrix (which may turn the mesh, e.g. `--up`)."""
    center, radius = bounding_sphere(obj.mesh)
    model = glm.dmat4(obj.world_from_model())
    center = glm.dvec3(model * glm.dvec4(*(center - np.asarray(obj.mesh.origin)), 1.0))
    radius *= abs(glm.determinant(glm.dmat3(model))) ** (1.0 / 3.0)
    return depth_range(eye, np.array(center), radius)


def framing_camera(mesh: Mesh, size: tuple[int, int], fov_y: float = 45.0) -> Camera:
    """A camera that frames the whole mesh, looking along −Z, a little from above."""
    center, radius = bounding_sphere(mesh)
    aspect = size[0] / size[1]
    half_fov = math.radians(fov_y) / 2.0
    narrowest = min(half_fov, math.atan(math.tan(half_fov) * aspect))
    distance = radius / math.sin(narrowest) * 1.05
    view_from = np.array(glm.normalize(glm.dvec3(*FRAMING_DIRECTION)))
    eye = center + view_from * distance
    near, far = depth_range(eye, center, radius)
    return Camera(
        eye=tuple(float(v) for v in eye),
        target=tuple(float(v) for v in center),
        up=(0.0, 1.0, 0.0),
        fov_y=fov_y,
        near=near,
        far=far,
    )
