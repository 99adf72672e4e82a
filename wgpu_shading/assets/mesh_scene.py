"""A scene for a bare mesh file (what `wgpu-shading render teapot.obj` draws)."""

from __future__ import annotations

import numpy as np

from ..errors import MeshError, SceneError
from ..scene import PositionalLight, Scene, SceneObject, material
from ..scene.framing import framing_camera
from .meshes import load_mesh


def mesh_scene(mesh_source: str, size: tuple[int, int], material_name: str | None):
    """A scene for a bare mesh: framed by the camera, lit like the seeds' demo (a white light
    up, right and in front, global ambient 0.2), the file's material or gold."""
    mesh = load_mesh(mesh_source)
    if material_name:
        chosen = material(material_name)
    else:
        chosen = mesh.material or material("gold")
    lower, upper = mesh.bounds()
    center = (lower + upper) / 2.0
    radius = max(float(np.linalg.norm(upper - lower)) / 2.0, 1e-12)
    light_position = center + np.array([5.0, 2.0, 2.0]) * radius * 1.5
    try:
        return Scene(
            objects=(SceneObject(mesh, chosen),),
            lights=(PositionalLight(position=tuple(light_position)),),
            camera=framing_camera(mesh, size),
            size=size,
        )
    except SceneError as error:
        # The camera and the light are ours, derived from the mesh: the mesh is the culprit.
        raise MeshError(
            f"mesh {str(mesh_source)!r} ({mesh.vertex_count} vertices around {center.tolist()}, radius {radius:.3g}): "
            f"the automatic camera and light cannot be placed for it ({error})"
        ) from None
