"""Framing a bare mesh: a camera that shows all of it."""

from __future__ import annotations

import math

import numpy as np

from .camera import Camera
from .mesh import Mesh


def framing_camera(mesh: Mesh, size: tuple[int, int], fov_y: float = 45.0):
    """A camera that frames the whole mesh, looking from the front and a little above."""
    lower, upper = mesh.bounds()
    center = (lower + upper) / 2.0
    radius = max(float(np.linalg.norm(upper - lower)) / 2.0, 1e-12)
    aspect = size[0] / size[1]
    half_fov = math.radians(fov_y) / 2.0
    narrowest = min(half_fov, math.atan(math.tan(half_fov) * aspect))
    distance = radius / math.sin(narrowest) * 1.05
    direction = np.array([0.0, 0.35, 1.0]) / np.linalg.norm([0.0, 0.35, 1.0])
    eye = center + direction * distance
    return Camera(
        eye=tuple(eye),
        target=tuple(center),
        up=(0.0, 1.0, 0.0),
        fov_y=fov_y,
        near=max(distance - 1.5 * radius, distance * 1e-3),
        far=distance + 1.5 * radius,
    )
