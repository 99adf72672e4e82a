"""A scene for a bare mesh file (what `wgpu-shading render teapot.obj` draws)."""

from __future__ import annotations

import numpy as np

from ..errors import MeshError, SceneError
from ..scene import Material, Mesh, Scene, SceneObject, material
from ..scene.framing import framing_camera
from ..scene.maps import bare_mesh_lighting
from .meshes import DEFAULT_CREASE_ANGLE, load_mesh


def mesh_scene(
    mesh_source: str,
    size: tuple[int, int] = (512, 512),
    material_name: str | None = None,
    *,
    crease_angle: float = DEFAULT_CREASE_ANGLE,
    up: str = "+Y",
):
    """A scene for a bare mesh: framed by the camera, lit by a key light and a headlight fill
    as model viewers do (scene/viewer_lights.py; global ambient 0.2), the file's materials or gold.
    `up` is the file's up axis: the mesh is turned so that it points up on screen, which is
    f3d's --up view (its camera turned instead: the same picture)."""
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
        world = mesh.world_positions() @ placed.world_from_model()[:3, :3].T
        mesh = Mesh.from_arrays(world, mesh.indices, normals=mesh.normals, name=mesh.name)
    try:
        camera = framing_camera(mesh, size)
        lights, ambient = bare_mesh_lighting((placed,), camera)  # decoded for a bare glTF (scene/maps.py)
        return Scene(objects=(placed,), lights=lights, camera=camera, size=size, ambient=ambient)
    except SceneError as error:
        # The camera and the lights are ours, derived from the mesh: the mesh is the culprit.
        lower, upper = mesh.bounds()
        center, radius = (lower + upper) / 2.0, float(np.linalg.norm(upper - lower)) / 2.0
        raise MeshError(
            f"mesh {str(mesh_source)!r} ({mesh.vertex_count} vertices around {center.tolist()}, radius {radius:.3g}): "
            f"the automatic camera and lights cannot be placed for it ({error})"
        ) from None
