"""A glTF file's own cameras (glTF 2.0 §3.10): `--camera-index N` views the file through
its N-th camera, as f3d does (VTK's glTF importer: N indexes the document's `cameras`,
placed by the node of the scene that uses it).

The camera looks along its node's local −Z axis with +Y up (§3.10.1). Perspective: `yfov`
(radians) is the vertical field of view, `znear`, and `zfar` (absent: an infinite
projection, here a far plane just beyond the scene); the image's aspect ratio is the
output size's, as three.js and f3d use the viewport's (`aspectRatio` is not used to
stretch the picture). Orthographic: `ymag` is half the view's height (`xmag` follows the
output's aspect ratio), between `znear` and `zfar`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .animations import read_posed
from .document import GltfData, gltf_error
from .nodes import scene_nodes, scene_roots, world_matrices


@dataclass(frozen=True)
class FileCamera:
    """One glTF camera where its node puts it, in the file's space (float64)."""

    world: np.ndarray  # (4, 4): the camera node's world matrix
    projection: str  # "perspective" | "orthographic"
    fov_y: float | None  # degrees (perspective)
    half_height: float | None  # ymag (orthographic)
    near: float
    far: float | None  # None: infinite (perspective without zfar)
    name: str


def gltf_camera(path: Path, index: int, animation_time: float | None = None, animation_index: int | str = 0) -> FileCamera:
    """cameras[index] placed by the first node of the scene that uses it, the nodes posed at
    `animation_time` if given (animations.py)."""
    data, nodes = read_posed(path, animation_time, animation_index)
    cameras = data.items("cameras")
    count = len(cameras)
    if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < count:
        span = f" (0..{count - 1})" if count else ""
        raise gltf_error(data.path, "cameras", f"camera index {index!r} is out of range: the file has {count} camera{'s' if count != 1 else ''}{span}")
    camera = data.item("cameras", index, "camera index")
    where = f"cameras[{index}]"
    world, roots = world_matrices(data, nodes)
    placed = nodes if nodes is not None else data.items("nodes")
    node = next((n for n in scene_nodes(data, scene_roots(data, roots)) if placed[n].get("camera") == index), None)
    if node is None:
        raise gltf_error(data.path, where, "no node of the scene uses this camera, so it has no place (glTF places cameras by nodes)")
    if world[node] is None:
        raise gltf_error(data.path, where, f"its node {node} is scaled to zero (hidden): the camera has no direction")
    kind = camera.get("type")
    settings = camera.get(kind) if kind in ("perspective", "orthographic") else None
    if not isinstance(settings, dict):
        raise gltf_error(data.path, where, f"expected type perspective or orthographic with its object, got {kind!r:.40}")
    name = str(camera.get("name", where))
    if kind == "perspective":
        fov = _number(data, settings.get("yfov"), f"{where}.perspective.yfov", 0.0, np.pi)
        near = _number(data, settings.get("znear"), f"{where}.perspective.znear", 0.0, np.inf)
        far = settings.get("zfar")
        far = None if far is None else _number(data, far, f"{where}.perspective.zfar", near, np.inf)
        return FileCamera(world[node], "perspective", float(np.degrees(fov)), None, near, far, name)
    half_height = _number(data, settings.get("ymag"), f"{where}.orthographic.ymag", 0.0, np.inf)
    near = _number(data, settings.get("znear"), f"{where}.orthographic.znear", 0.0, np.inf, low_open=False)
    far = _number(data, settings.get("zfar"), f"{where}.orthographic.zfar", near, np.inf)
    return FileCamera(world[node], "orthographic", None, half_height, near, far, name)


def _number(data: GltfData, value: object, field: str, low: float, high: float, low_open: bool = True) -> float:
    """A finite number in (low, high) (or [low, high) when not low_open)."""
    if type(value) not in (int, float) or not np.isfinite(value) or not (value > low if low_open else value >= low) or not value < high:
        bound = f"greater than {low:g}" if low_open else f"at least {low:g}"
        raise gltf_error(data.path, field, f"expected a finite number {bound}{f' and below {high:g}' if np.isfinite(high) else ''}, got {value!r:.40}")
    return float(value)
