"""A scene for a bare mesh file (what `wgpu-shading render teapot.obj` draws)."""

from __future__ import annotations

import numpy as np

from ..scene import Material, Mesh, PositionalLight, Scene, SceneObject, material
from ..scene.framing import framing_camera
from .meshes import DEFAULT_CREASE_ANGLE, load_mesh


def mesh_scene(
    mesh_source: str,
    size: tuple[int, int],
    material_name: str | None,
    *,
    crease_angle: float = DEFAULT_CREASE_ANGLE,
    up: str = "+Y",
):
    """A scene for a bare mesh: framed by the camera, lit like the seeds' demo (a white light
    up, right and in front, global ambient 0.2), the file's materials or gold. `up` is the
    file's up axis: the mesh is turned so that it points up on screen (like f3d's --up)."""
    mesh = load_mesh(mesh_source, crease_angle=crease_angle)
    if material_name:
        chosen = material(material_name)
    elif any(part.material is not None for part in mesh.parts):
        chosen = None  # the file's materials, part by part
    elif mesh.colors is not None:
        chosen = Material()  # OpenGL's default white-grey: the vertex colors show as they are
    else:
        chosen = material("gold")
    placed = SceneObject(mesh, chosen, up=up)
    if placed.up != "+Y":  # frame the turned mesh: a mesh with the turn baked in, for framing only
        world = mesh.world_positions() @ np.array(placed.model_matrix())[:3, :3].T
        mesh = Mesh.from_arrays(world, mesh.indices, normals=mesh.normals, name=mesh.name)
    lower, upper = mesh.bounds()
    center = (lower + upper) / 2.0
    radius = max(float(np.linalg.norm(upper - lower)) / 2.0, 1e-12)
    light_position = center + np.array([5.0, 2.0, 2.0]) * radius * 1.5
    return Scene(
        objects=(placed,),
        lights=(PositionalLight(position=tuple(light_position)),),
        camera=framing_camera(mesh, size),
        size=size,
    )
