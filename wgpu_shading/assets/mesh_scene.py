"""A scene for a bare mesh file (what `wgpu-shading render teapot.obj` draws)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping

import numpy as np

from ..errors import MeshError, SceneError
from ..scene import Material, Mesh, Scene, SceneObject, material
from ..scene.view.bare_mesh import framing_camera
from ..scene.maps import bare_mesh_lighting
from .meshes import DEFAULT_CREASE_ANGLE, load_mesh


def mesh_scene(
    mesh_source: str,
    size: tuple[int, int] = (512, 512),
    material_name: str | None = None,
    *,
    crease_angle: float = DEFAULT_CREASE_ANGLE,
    up: str = "+Y",
    file_lights: bool = True,
    reading: Mapping[str, Any] | None = None,
):
    """A scene for a bare mesh: framed by the camera, lit by a key light and a headlight fill
    as model viewers do (scene/view/viewer_lights.py; global ambient 0.2), the file's materials or gold.
    `up` is the file's up axis: the mesh is turned so that it points up on screen, which is
    f3d's --up view (its camera turned instead: the same picture). A glTF file with
    KHR_lights_punctual lights is lit by them instead (as viewers do; gltf/punctual_lights.py),
    unless `file_lights` is False (`--viewer-lights`). `reading`: more of the mesh reader's
    options (ViewOptions.mesh_reading()), its crease_angle replacing `crease_angle`."""
    mesh = load_mesh(mesh_source, **{"crease_angle": crease_angle, **(reading or {})})
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
        own = file_lights and _file_lights(mesh_source, placed)  # a glTF file's own lights, if any
        return Scene(objects=(placed,), lights=own or lights, camera=camera, size=size, ambient=ambient)
    except SceneError as error:
        # The camera and the lights are ours, derived from the mesh: the mesh is the culprit.
        lower, upper = mesh.bounds()
        center, radius = (lower + upper) / 2.0, float(np.linalg.norm(upper - lower)) / 2.0
        raise MeshError(
            f"mesh {str(mesh_source)!r} ({mesh.vertex_count} vertices around {center.tolist()}, radius {radius:.3g}): "
            f"the automatic camera and lights cannot be placed for it ({error})"
        ) from None


def _file_lights(mesh_source: str, placed: SceneObject) -> tuple:
    """The file's own lights (glTF KHR_lights_punctual) in world space: turned with the
    object (its `up`); () when it has none."""
    from pathlib import Path

    from .examples import resolve_example
    from .gltf.punctual_lights import gltf_lights

    path = Path(resolve_example(str(mesh_source)))
    if path.suffix.lower() not in (".gltf", ".glb"):
        return ()
    model = placed.world_from_model()
    linear, origin = model[:3, :3], np.asarray(placed.mesh.origin)
    placed_lights = []
    for light, node in gltf_lights(path):
        to_world = model.copy()
        to_world[:3, 3] = model[:3, 3] - linear @ origin  # the file's space, not the mesh's centred one
        matrix = to_world @ node
        changes = {}
        if hasattr(light, "position"):
            changes["position"] = tuple(float(v) for v in matrix[:3, 3])
        if hasattr(light, "direction"):
            axis = -matrix[:3, 2]
            changes["direction"] = tuple(float(v) for v in axis / np.linalg.norm(axis))
        placed_lights.append(replace(light, **changes))
    return tuple(placed_lights)
