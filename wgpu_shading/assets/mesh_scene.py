"""A scene for a bare mesh file (what `wgpu-shading render teapot.obj` draws): the file read
here, every choice made by the bare-mesh policy (scene/view/bare_mesh.py)."""

from __future__ import annotations

import warnings
from dataclasses import replace
from typing import Any, Mapping

import numpy as np

from ..errors import MeshError, SceneError
from ..scene.view.bare_mesh import DEFAULT_SIZE, bare_mesh_scene
from .meshes import DEFAULT_CREASE_ANGLE, LoadedMesh, read_mesh


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
    loaded: LoadedMesh | None = None,
):
    """A scene for a bare mesh: framed by the camera, lit by a key light and a headlight fill
    as model viewers do (global ambient 0.2), the file's materials or gold (all of it:
    scene/view/bare_mesh.py). `up` is the file's up axis (default +Y): the mesh is turned
    so that it points up on screen, which is f3d's --up view (its camera turned instead:
    the same picture). A glTF file with KHR_lights_punctual lights is lit by them instead
    (as viewers do; gltf/punctual_lights.py), unless `file_lights` is False
    (`--viewer-lights`). `reading`: more of the mesh reader's options
    (ViewOptions.mesh_reading()), its crease_angle replacing `crease_angle`; the file's
    lights and camera hang on its nodes as posed at its animation time. `camera_index`: the
    glTF file's own camera N instead of the framing one (gltf/cameras.py; other formats have
    none: a warning). `framing`: a Mesh to frame instead of the file's (animation_frames.py:
    every pose of an animation). `loaded`: the file as already read (and posed), not read
    again (animation_frames.py parses a file once for all its frames)."""
    if loaded is None:
        loaded = read_mesh(mesh_source, **{"crease_angle": crease_angle, **(reading or {})})  # the file, parsed once
    mesh = loaded.mesh
    try:
        own = loaded.lights() if file_lights else ()
        camera = None if camera_index is None else loaded.camera(camera_index)
        if camera_index is not None and camera is None:
            warnings.warn(f"{mesh_source}: only glTF files hold cameras; the camera index {camera_index} is ignored", stacklevel=2)
        scene = bare_mesh_scene(mesh, size, material_name, up=up, file_lights=own, file_camera=camera, framing=framing)
        return scene if loaded.shows else replace(scene, objects=())  # a moment when nothing shows (meshes.LoadedMesh)
    except SceneError as error:
        # The camera and the lights are ours, derived from the mesh: the mesh is the culprit.
        lower, upper = mesh.bounds()
        center, radius = (lower + upper) / 2.0, float(np.linalg.norm(upper - lower)) / 2.0
        raise MeshError(
            f"mesh {str(mesh_source)!r} ({mesh.vertex_count} vertices around {center.tolist()}, radius {radius:.3g}): "
            f"the automatic camera and lights cannot be placed for it ({error})"
        ) from None
