"""Per-view camera records for cameras.json: intrinsics and extrinsics in OpenCV's
convention, with the OpenGL pose beside them, so a dataset is usable without this package.

Convention (docs/datasets.md):
- Image: pixel (u, v) = (column, row), row 0 at the top, OpenCV's pixel centres at integer
  coordinates (pixel (0, 0) covers [-0.5, 0.5]²).
- K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]: a point X_cv in the camera frame projects to
  (u, v) = (fx X/Z + cx, fy Y/Z + cy). Square pixels (fx == fy); cx = W/2 - 0.5, cy = H/2 - 0.5.
- world_to_camera_opencv: 4×4, X_cv = M @ [X_world, 1]; camera frame x right, y down, z forward.
- camera_to_world_opengl: 4×4, the camera's pose in OpenGL's frame (x right, y up, z
  backward, looking down -z): the inverse of the view (gluLookAt) matrix.
  Relation: world_to_camera_opencv = diag(1, -1, -1, 1) @ inverse(camera_to_world_opengl).
- depth (.npy) is Z of the OpenCV frame (= -z of OpenGL's eye space), not the ray length.
"""

from __future__ import annotations

import math

import numpy as np

from ..scene import Scene

OPENGL_TO_OPENCV = np.diag([1.0, -1.0, -1.0, 1.0])


def camera_record(scene: Scene) -> dict:
    """The JSON-ready camera of one rendered view."""
    camera = scene.camera
    width, height = scene.size
    eye_from_world = camera.eye_from_world()
    if camera.orthographic:
        # No pinhole: u = s·X + cx, v = s·Y + cy in the OpenCV camera frame, s pixels per unit.
        scale = height / camera.view_height()
        projection = {"projection": "orthographic", "pixels_per_unit": scale, "ortho_height": camera.view_height(), "K": None}
        focal = None
    else:
        focal = (height / 2.0) / math.tan(math.radians(camera.fov_y) / 2.0)
        projection = {
            "projection": "perspective",
            "K": [[focal, 0.0, width / 2.0 - 0.5], [0.0, focal, height / 2.0 - 0.5], [0.0, 0.0, 1.0]],
        }
    return {
        "width": width,
        "height": height,
        "fx": focal,
        "fy": focal,
        "cx": width / 2.0 - 0.5,
        "cy": height / 2.0 - 0.5,
        **projection,
        "fov_y_degrees": camera.fov_y,
        "near": camera.near,
        "far": camera.far,
        "world_to_camera_opencv": (OPENGL_TO_OPENCV @ eye_from_world).tolist(),
        "camera_to_world_opengl": np.linalg.inv(eye_from_world).tolist(),
        "eye": list(camera.eye),
        "target": list(camera.target),
        "up": list(camera.up),
    }


CONVENTION = {
    "pixels": "u = column, v = row from the top; OpenCV pixel centres at integer coordinates",
    "K": "OpenCV intrinsics: u = fx*X/Z + cx, v = fy*Y/Z + cy in the OpenCV camera frame "
    "(projection 'orthographic': K, fx, fy are null and u = s*X + cx, v = s*Y + cy, s = pixels_per_unit)",
    "world_to_camera_opencv": "X_cv = M @ [X_world, 1]; camera x right, y down, z forward",
    "camera_to_world_opengl": "camera pose in OpenGL axes (x right, y up, looking down -z); "
    "world_to_camera_opencv = diag(1,-1,-1,1) @ inverse(camera_to_world_opengl)",
    "depth": "*_depth.npy: float32 Z in the OpenCV camera frame (inf = background); "
    "*_depth.png: uint16, 0 = background, 1..65535 = near..far linearly in Z (near, far also in its text chunks)",
    "normals": "*_normals_eye.npy: OpenGL eye space (x right, y up, z toward the camera); "
    "*_normals_world.npy: world space; float32 unit vectors, 0 = background",
    "ids": "*_ids.png: uint16, 0 = background, k = the entry with id k of the view's 'ids' list "
    "(an object, or one part of a multi-part mesh)",
}


def id_legend(scene: Scene) -> list[dict]:
    """What each value of an ids mask is: object index, part index within its mesh, names."""
    from ..render.passes.extra_outputs import segments

    legend = []
    for segment, (obj, part) in enumerate(segments(scene), 1):
        object_index = next(i for i, candidate in enumerate(scene.objects) if candidate is obj)
        legend.append(
            {"id": segment, "object": object_index, "part": obj.mesh.parts.index(part), "mesh": obj.mesh.name, "part_name": part.name}
        )
    return legend
