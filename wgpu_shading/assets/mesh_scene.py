"""A scene for a bare mesh file (what `wgpu-shading render teapot.obj` draws): the file read
here, every choice made by the bare-mesh policy (scene/view/bare_mesh.py)."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ..errors import MeshError, SceneError
from ..scene.view.bare_mesh import DEFAULT_SIZE, bare_mesh_scene
from .meshes import DEFAULT_CREASE_ANGLE, load_mesh


def mesh_scene(
    mesh_source: str,
    size: tuple[int, int] = DEFAULT_SIZE,
    material_name: str | None = None,
    *,
    crease_angle: float = DEFAULT_CREASE_ANGLE,
    up: str | None = None,
    file_lights: bool = True,
    reading: Mapping[str, Any] | None = None,
    camera_index: int | None = None,
    framing=None,
):
    """A scene for a bare mesh: framed by the camera, lit by a key light and a headlight fill
    as model viewers do (global ambient 0.2), the file's materials or gold (all of it:
    scene/view/bare_mesh.py). `up` is the file's up axis (default +Y): the mesh is turned
    so that it points up on screen, which is f3d's --up view (its camera turned instead:
    the same picture). A glTF file with KHR_lights_punctual lights is lit by them instead
    (as viewers do; gltf/punctual_lights.py), unless `file_lights` is False
    (`--viewer-lights`). `reading`: more of the mesh reader's options
    (ViewOptions.mesh_reading()), its crease_angle replacing `crease_angle`; the file's
    lights and camera are posed at its animation time as the mesh is. `camera_index`: the
    glTF file's own camera N instead of the framing one (gltf/cameras.py). `framing`: a Mesh
    to frame instead of the file's (animation_frames.py: every pose of an animation)."""
    reading = {"crease_angle": crease_angle, **(reading or {})}
    mesh = load_mesh(mesh_source, **reading)
    try:
        own = _file_lights(mesh_source, reading) if file_lights else ()
        camera = None if camera_index is None else _file_camera(mesh_source, camera_index, reading)
        return bare_mesh_scene(mesh, size, material_name, up=up, file_lights=own, file_camera=camera, framing=framing)
    except SceneError as error:
        # The camera and the lights are ours, derived from the mesh: the mesh is the culprit.
        lower, upper = mesh.bounds()
        center, radius = (lower + upper) / 2.0, float(np.linalg.norm(upper - lower)) / 2.0
        raise MeshError(
            f"mesh {str(mesh_source)!r} ({mesh.vertex_count} vertices around {center.tolist()}, radius {radius:.3g}): "
            f"the automatic camera and lights cannot be placed for it ({error})"
        ) from None


def _gltf_path(mesh_source: str):
    """The file's path when it is a glTF file (the one format with lights and cameras), else None."""
    from pathlib import Path

    from .examples import resolve_example

    path = Path(resolve_example(str(mesh_source)))
    return path if path.suffix.lower() in (".gltf", ".glb") else None


def _animation(reading: Mapping[str, Any]) -> tuple[float | None, int | str]:
    """(time, animation) the mesh was read at, as load_mesh reads them: an animation chosen
    alone is shown at its start."""
    time, animation = reading.get("animation_time"), reading.get("animation_index")
    if animation is not None and time is None:
        time = 0.0
    return time, 0 if animation is None else animation


def _file_lights(mesh_source: str, reading: Mapping[str, Any]) -> list:
    """The file's own lights with their nodes' matrices, in the file's space (glTF
    KHR_lights_punctual), their nodes posed as the mesh's; [] when it has none."""
    from .gltf.punctual_lights import gltf_lights

    path = _gltf_path(mesh_source)
    return [] if path is None else gltf_lights(path, *_animation(reading))


def _file_camera(mesh_source: str, index: int, reading: Mapping[str, Any]):
    """The glTF file's camera `index` (gltf/cameras.py), its node posed as the mesh's; None,
    with a warning, for the formats that hold no cameras."""
    import warnings

    from .gltf.cameras import gltf_camera

    path = _gltf_path(mesh_source)
    if path is None:
        warnings.warn(f"{mesh_source}: only glTF files hold cameras; the camera index {index} is ignored", stacklevel=3)
        return None
    return gltf_camera(path, index, *_animation(reading))
