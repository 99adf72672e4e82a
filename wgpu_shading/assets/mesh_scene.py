"""A scene for a bare mesh file (what `wgpu-shading render teapot.obj` draws)."""

from __future__ import annotations

from ..scene import Scene, SceneObject, material
from ..scene.framing import framing_camera
from ..scene.lighting import viewer_lights
from .meshes import load_mesh


def mesh_scene(mesh_source: str, size: tuple[int, int], material_name: str | None, up=(0.0, 1.0, 0.0)):
    """A scene for a bare mesh: framed by the camera from its `up` axis (f3d's --up), lit by
    a key light and a headlight fill (scene/lighting.py), the file's material or gold."""
    mesh = load_mesh(mesh_source)
    if material_name:
        chosen = material(material_name)
    else:
        chosen = mesh.material or material("gold")
    camera = framing_camera(mesh, size, up=up)
    return Scene(
        objects=(SceneObject(mesh, chosen),),
        lights=viewer_lights(camera),
        camera=camera,
        size=size,
    )
