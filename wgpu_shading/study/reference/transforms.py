"""The spaces of the float64 reference: model → world → eye with 4×4 matrices derived here
from docs/conventions.md (gluLookAt, T · Rz · Ry · Rx · S, the inverse-transpose normal
matrix), and eye → window per point (the perspective divide written out, no projection
matrix; glOrtho's box for orthographic cameras), plus the eye-space rays back through the
pixel centres.

Why numpy and not pyglm, as the renderer uses: this reference exists to check the renderer,
so it derives every matrix itself from the written conventions. Importing the renderer's
pyglm matrices would make a bug in them invisible to every test that compares against it."""

from __future__ import annotations

import math

import numpy as np

from ...errors import SceneError
from ...scene import Camera, SceneObject

# --------------------------------------------------------------------------- transforms


def eye_from_world(camera: Camera) -> np.ndarray:
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


def world_from_model(obj: SceneObject) -> np.ndarray:
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
    model = world_from_model(obj)
    # The model-space centre (0, 0, 0) is stored as -origin.
    center = transform_points(model, -np.asarray(obj.mesh.origin, dtype=np.float64)[None])[0]
    return center, float(radius * scale[0])


# --------------------------------------------------------------------------- pixels and rays


def half_extents(camera: Camera, size: tuple[int, int]) -> tuple[float, float]:
    """Half the image's width and height on the plane at eye depth 1 (perspective: the
    tangents of the half angles) or in world units (orthographic: glOrtho's box)."""
    width, height = size
    half_height = camera.view_height() / 2.0 if camera.orthographic else math.tan(math.radians(camera.fov_y) / 2.0)
    return half_height * width / height, half_height


def window_rays(camera: Camera, size: tuple[int, int], x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eye-space rays through window positions (x right, y down, in pixels; pixel centres
    at +0.5): (origins, directions), each (..., 3). Perspective: from the eye, z = -1;
    orthographic: from the plane z = 0, along -Z."""
    width, height = size
    half_width, half_height = half_extents(camera, size)
    x_ndc = 2.0 * np.asarray(x, dtype=np.float64) / width - 1.0
    y_ndc = 1.0 - 2.0 * np.asarray(y, dtype=np.float64) / height
    x_ndc, y_ndc = np.broadcast_arrays(x_ndc, y_ndc)
    on_plane = np.stack([x_ndc * half_width, y_ndc * half_height, -np.ones_like(x_ndc)], axis=-1)
    if not camera.orthographic:
        return np.zeros_like(on_plane), on_plane
    origins = on_plane.copy()
    origins[..., 2] = 0.0
    directions = np.zeros_like(on_plane)
    directions[..., 2] = -1.0
    return origins, directions


def pixel_rays(camera: Camera, size: tuple[int, int]) -> np.ndarray:
    """(H, W, 3) eye-space directions through the pixel centres, z = -1, from the eye at the
    origin. Perspective cameras only: orthographic rays start at different points
    (`window_rays` gives both)."""
    if camera.orthographic:
        raise SceneError("pixel_rays: an orthographic camera's rays do not start at the eye; use window_rays")
    width, height = size
    columns, rows = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    return window_rays(camera, size, columns, rows)[1]


def window_coordinates(eye_points: np.ndarray, camera: Camera, size: tuple[int, int]) -> np.ndarray:
    """Eye space → window coordinates (x right, y down, in pixels); perspective needs depth > 0."""
    width, height = size
    half_width, half_height = half_extents(camera, size)
    scale = 1.0 if camera.orthographic else -eye_points[..., 2]  # the perspective divide by depth
    x_ndc = eye_points[..., 0] / (scale * half_width)
    y_ndc = eye_points[..., 1] / (scale * half_height)
    return np.stack([(x_ndc + 1.0) * width / 2.0, (1.0 - y_ndc) * height / 2.0], axis=-1)
