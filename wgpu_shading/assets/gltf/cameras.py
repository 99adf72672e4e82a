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

import numpy as np

from ...errors import SceneError
from ...scene.camera import Camera
from .document import GltfData, gltf_error
from .nodes import scene_nodes, scene_roots, world_matrices


def gltf_camera(data: GltfData, index: int, nodes: list | None = None) -> tuple[Camera, np.ndarray, bool]:
    """cameras[index] as (the Camera in its node's frame: at the origin looking down −Z with
    +Y up; its node's world matrix; whether its far plane is infinite), the node the first
    of the scene that uses it; `nodes`: the nodes as an animation poses them
    (animations.posed_nodes), else the file's own. Where it lands in the world is the
    bare-mesh policy's (scene/view/bare_mesh.py)."""
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
    local = {"eye": (0.0, 0.0, 0.0), "target": (0.0, 0.0, -1.0), "up": (0.0, 1.0, 0.0)}
    try:
        if kind == "perspective":
            fov = _number(data, settings.get("yfov"), f"{where}.perspective.yfov", 0.0, np.pi)
            near = _number(data, settings.get("znear"), f"{where}.perspective.znear", 0.0, np.inf)
            far = settings.get("zfar")
            far = None if far is None else _number(data, far, f"{where}.perspective.zfar", near, np.inf)
            # without zfar the projection is infinite: the policy puts the far plane beyond the scene
            return Camera(fov_y=float(np.degrees(fov)), near=near, far=near * 2.0 if far is None else far, **local), world[node], far is None
        half_height = _number(data, settings.get("ymag"), f"{where}.orthographic.ymag", 0.0, np.inf)
        near = _number(data, settings.get("znear"), f"{where}.orthographic.znear", 0.0, np.inf, low_open=False)
        far = _number(data, settings.get("zfar"), f"{where}.orthographic.zfar", near, np.inf)
        near = near if near > 0.0 else far * 1e-6  # znear 0 is valid for orthographic cameras; ours needs a plane in front
        return Camera(projection="orthographic", ortho_height=2.0 * half_height, near=near, far=far, **local), world[node], False
    except SceneError as error:  # a projection float32 cannot hold (a yfov of 1e-30 ...)
        raise gltf_error(data.path, where, str(error)) from None


def _number(data: GltfData, value: object, field: str, low: float, high: float, low_open: bool = True) -> float:
    """A finite number in (low, high) (or [low, high) when not low_open)."""
    if type(value) not in (int, float) or not np.isfinite(value) or not (value > low if low_open else value >= low) or not value < high:
        bound = f"greater than {low:g}" if low_open else f"at least {low:g}"
        raise gltf_error(data.path, field, f"expected a finite number {bound}{f' and below {high:g}' if np.isfinite(high) else ''}, got {value!r:.40}")
    return float(value)
