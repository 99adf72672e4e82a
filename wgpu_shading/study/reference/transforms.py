"""The spaces of the float64 reference: model → world → eye with 4×4 matrices derived here
from docs/conventions.md (gluLookAt, T · Rz · Ry · Rx · S, the inverse-transpose normal
matrix), and eye → window per point (the perspective divide written out, no projection
matrix), plus the eye-space rays back through the pixel centres.

Why numpy and not pyglm, as the renderer uses: this reference exists to check the renderer,
so it derives every matrix itself from the written conventions. Importing the renderer's
pyglm matrices would make a bug in them invisible to every test that compares against it."""

from __future__ import annotations

import math

import numpy as np

from ...errors import SceneError
from ...scene import Camera, SceneObject

# --------------------------------------------------------------------------- transforms


def view_matrix(camera: Camera) -> np.ndarray:
    """gluLookAt, derived here from eye/target/up: rows are the eye-space axes in world space."""
    eye = np.asarray(camera.eye, dtype=np.float64)
    forward = np.asarray(camera.target, dtype=np.float64) - eye
    forward /= np.linalg.norm(forward)
    side = np.cross(forward, np.asarray(camera.up, dtype=np.float64))
    side /= np.linalg.norm(side)
    up = np.cross(side, forward)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = side, up, -forward  # the camera looks down -Z
    view[:3, 3] = -view[:3, :3] @ eye
    return view


def model_matrix(obj: SceneObject) -> np.ndarray:
    """T · Rz · Ry · Rx · S · translate(mesh.origin): the matrix for the mesh's stored
    (origin-relative) positions, derived here from the conventions."""
    ax, ay, az = np.radians(np.asarray(obj.rotate, dtype=np.float64))
    rx = np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]])
    ry = np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]])
    rz = np.array([[math.cos(az), -math.sin(az), 0], [math.sin(az), math.cos(az), 0], [0, 0, 1]])
    linear = rz @ ry @ rx @ np.diag(np.asarray(obj.scale, dtype=np.float64))
    model = np.eye(4)
    model[:3, :3] = linear
    model[:3, 3] = np.asarray(obj.translate, dtype=np.float64) + linear @ np.asarray(obj.mesh.origin, dtype=np.float64)
    return model


def normal_matrix(model_view: np.ndarray) -> np.ndarray:
    """Inverse transpose of the upper 3×3: normals stay perpendicular under non-uniform scale."""
    return np.linalg.inv(model_view[:3, :3]).T


def transform_points(matrix: np.ndarray, points: np.ndarray) -> np.ndarray:
    return points @ matrix[:3, :3].T + matrix[:3, 3]


def sphere_in_world(obj: SceneObject, radius: float = 1.0) -> tuple[np.ndarray, float]:
    """World centre and radius of a sphere mesh of `radius` centred on its model origin
    (meshes.uv_sphere), placed by `obj`, whose scale must be uniform."""
    scale = np.abs(np.asarray(obj.scale, dtype=np.float64))
    if not np.allclose(scale, scale[0], rtol=1e-12, atol=0.0):
        raise ValueError(f"an analytic sphere needs a uniform scale, got {obj.scale}")
    model = model_matrix(obj)
    # The model-space centre (0, 0, 0) is stored as -origin.
    center = transform_points(model, -np.asarray(obj.mesh.origin, dtype=np.float64)[None])[0]
    return center, float(radius * scale[0])


# --------------------------------------------------------------------------- pixels and rays


def pixel_rays(camera: Camera, size: tuple[int, int]) -> np.ndarray:
    """(H, W, 3) eye-space directions through the pixel centres, z = -1."""
    if camera.orthographic:  # every path of the reference starts from these rays
        raise SceneError("the float64 reference renders perspective cameras only; camera.projection is 'orthographic'")
    width, height = size
    tan_half = math.tan(math.radians(camera.fov_y) / 2.0)
    aspect = width / height
    x = 2.0 * (np.arange(width) + 0.5) / width - 1.0
    y = 1.0 - 2.0 * (np.arange(height) + 0.5) / height
    rays = np.empty((height, width, 3))
    rays[:, :, 0] = x[None, :] * tan_half * aspect
    rays[:, :, 1] = y[:, None] * tan_half
    rays[:, :, 2] = -1.0
    return rays


def window_coordinates(eye_points: np.ndarray, camera: Camera, size: tuple[int, int]) -> np.ndarray:
    """Eye space → window coordinates (x right, y down, in pixels); needs depth > 0."""
    width, height = size
    tan_half = math.tan(math.radians(camera.fov_y) / 2.0)
    depth = -eye_points[..., 2]
    x_ndc = eye_points[..., 0] / (depth * tan_half * (width / height))
    y_ndc = eye_points[..., 1] / (depth * tan_half)
    return np.stack([(x_ndc + 1.0) * width / 2.0, (1.0 - y_ndc) * height / 2.0], axis=-1)
