"""The camera: gluLookAt + gluPerspective, validated."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from .values import Vec3, _set, direction, number, vec3


def _cross(a, b) -> np.ndarray:
    """np.cross for two 3-vectors, bit for bit (the same products and differences), at a
    twentieth of the cost: np.cross's axis handling is most of a frame's CPU preparation."""
    a0, a1, a2 = (float(v) for v in a)
    b0, b1, b2 = (float(v) for v in b)
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


@dataclass(frozen=True)
class Camera:
    """A perspective camera (gluLookAt + gluPerspective)."""

    eye: Vec3 = (0.0, 0.0, 3.0)
    target: Vec3 = (0.0, 0.0, 0.0)
    up: Vec3 = (0.0, 1.0, 0.0)
    fov_y: float = 45.0  # degrees, vertical
    near: float = 0.1
    far: float = 100.0

    def __post_init__(self) -> None:
        eye = vec3(self.eye, "camera.eye")
        target = vec3(self.target, "camera.target")
        up = direction(self.up, "camera.up")
        fov_y = number(self.fov_y, "camera.fov_y", 0.0, 180.0, low_open=True)
        if fov_y >= 180.0:
            raise SceneError(f"camera.fov_y: expected less than 180 degrees, got {fov_y}")
        near = number(self.near, "camera.near", 0.0, math.inf, low_open=True)
        far = number(self.far, "camera.far", 0.0, math.inf, low_open=True)
        if not far > near:
            raise SceneError(f"camera.far ({far:g}) must be greater than camera.near ({near:g})")
        forward = np.subtract(target, eye)
        distance = float(np.linalg.norm(forward))
        scale = max(float(np.abs(eye).max()), float(np.abs(target).max()), 1.0)
        if distance <= 1e-12 * scale:
            raise SceneError(f"camera: eye {list(eye)} and target {list(target)} coincide; the view direction is undefined")
        up_unit = np.asarray(up) / np.linalg.norm(up)
        if np.linalg.norm(np.cross(forward / distance, up_unit)) < 1e-9:
            raise SceneError(f"camera.up {list(up)} is parallel to the view direction; pick an up vector that is not")
        _set(self, eye=eye, target=target, up=up, fov_y=fov_y, near=near, far=far)

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit right, up and backward (eye-space +x, +y, +z) axes in world space, float64."""
        backward = np.subtract(self.eye, self.target)
        backward = backward / np.linalg.norm(backward)
        right = _cross(self.up, backward)
        right = right / np.linalg.norm(right)
        true_up = _cross(backward, right)
        return right, true_up, backward

    def eye_from_world(self) -> np.ndarray:
        """The view matrix (gluLookAt), float64 4x4, column vectors."""
        right, true_up, backward = self.basis()
        view = np.eye(4)
        view[0, :3], view[1, :3], view[2, :3] = right, true_up, backward
        view[:3, 3] = -view[:3, :3] @ np.asarray(self.eye)
        return view

