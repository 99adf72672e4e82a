"""A scene for a bare mesh file (what `wgpu-shading render teapot.obj` draws)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping

import numpy as np

from ..errors import MeshError, SceneError
from ..scene import Camera, Material, Mesh, Scene, SceneObject, material
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
    file_lights: bool = True,
    reading: Mapping[str, Any] | None = None,
    camera_index: int | None = None,
    framing: Mesh | None = None,
):
    """A scene for a bare mesh: framed by the camera, lit by a key light and a headlight fill
    as model viewers do (scene/viewer_lights.py; global ambient 0.2), the file's materials or gold.
    `up` is the file's up axis: the mesh is turned so that it points up on screen, which is
    f3d's --up view (its camera turned instead: the same picture). A glTF file with
    KHR_lights_punctual lights is lit by them instead (as viewers do; gltf/punctual_lights.py),
    unless `file_lights` is False (`--viewer-lights`). `reading`: more of the mesh reader's
    options (ViewOptions.mesh_reading()), its crease_angle replacing `crease_angle`.
    `camera_index`: the glTF file's own camera N instead of the framing one (gltf/cameras.py).
    `framing`: frame this mesh (in the file's space) instead of the file's, as an animation
    frames every pose it takes (animation_frames.py)."""
    reading = {"crease_angle": crease_angle, **(reading or {})}
    mesh = load_mesh(mesh_source, **reading)
    if material_name:
        chosen = material(material_name)
    elif any(part.material is not None for part in mesh.parts):
        chosen = None  # the file's materials, part by part
    elif mesh.colors is not None:
        chosen = Material()  # OpenGL's default white-grey: the vertex colors show as they are
    else:
        chosen = material("gold")
    placed = SceneObject(mesh, chosen, up=up)
    mesh = framing or mesh
    if placed.up != "+Y":  # frame the turned mesh: a mesh with the turn baked in, for framing only
        world = mesh.world_positions() @ placed.world_from_model()[:3, :3].T
        mesh = Mesh.from_arrays(world, mesh.indices, normals=mesh.normals, name=mesh.name)
    try:
        camera = framing_camera(mesh, size)
        if camera_index is not None:
            camera = _file_camera(mesh_source, placed, camera_index, reading, mesh) or camera
        lights, ambient = bare_mesh_lighting((placed,), camera)  # decoded for a bare glTF (scene/maps.py)
        own = file_lights and _file_lights(mesh_source, placed, reading)  # a glTF file's own lights, if any
        return Scene(objects=(placed,), lights=own or lights, camera=camera, size=size, ambient=ambient)
    except SceneError as error:
        # The camera and the lights are ours, derived from the mesh: the mesh is the culprit.
        lower, upper = mesh.bounds()
        center, radius = (lower + upper) / 2.0, float(np.linalg.norm(upper - lower)) / 2.0
        raise MeshError(
            f"mesh {str(mesh_source)!r} ({mesh.vertex_count} vertices around {center.tolist()}, radius {radius:.3g}): "
            f"the automatic camera and lights cannot be placed for it ({error})"
        ) from None


def _file_lights(mesh_source: str, placed: SceneObject, reading: Mapping[str, Any]) -> tuple:
    """The file's own lights (glTF KHR_lights_punctual) in world space: turned with the
    object (its `up`), their nodes posed as the mesh's are; () when it has none."""
    from pathlib import Path

    from .examples import resolve_example
    from .gltf.punctual_lights import gltf_lights

    path = Path(resolve_example(str(mesh_source)))
    if path.suffix.lower() not in (".gltf", ".glb"):
        return ()
    animation = _animation(reading)
    to_world = _to_world(placed)
    placed_lights = []
    for light, node in gltf_lights(path, *animation):
        matrix = to_world @ node
        changes = {}
        if hasattr(light, "position"):
            changes["position"] = tuple(float(v) for v in matrix[:3, 3])
        if hasattr(light, "direction"):
            axis = -matrix[:3, 2]
            changes["direction"] = tuple(float(v) for v in axis / np.linalg.norm(axis))
        placed_lights.append(replace(light, **changes))
    return tuple(placed_lights)


def _to_world(placed: SceneObject) -> np.ndarray:
    """The file's space to the world: the object's model matrix without the mesh's centring
    (Mesh.origin), so that what hangs on the file's nodes lands where the mesh does."""
    model = placed.world_from_model()
    model[:3, 3] -= model[:3, :3] @ np.asarray(placed.mesh.origin)
    return model


def _file_camera(mesh_source: str, placed: SceneObject, index: int, reading: Mapping[str, Any], framed: Mesh):
    """The glTF file's camera `index` as a Camera in world space (gltf/cameras.py): looking
    along its node's −Z with its +Y up; the target on that axis at the depth of the scene's
    centre; an infinite far plane just beyond the scene. None (with a warning) for files
    that cannot hold cameras."""
    import warnings
    from pathlib import Path

    from .examples import resolve_example
    from .gltf.cameras import gltf_camera

    path = Path(resolve_example(str(mesh_source)))
    if path.suffix.lower() not in (".gltf", ".glb"):
        warnings.warn(f"{path.name}: only glTF files hold cameras; the camera index {index} is ignored", stacklevel=3)
        return None
    file_camera = gltf_camera(path, index, *_animation(reading))
    matrix = _to_world(placed) @ file_camera.world
    eye = matrix[:3, 3]
    forward, up = -matrix[:3, 2], matrix[:3, 1]
    forward, up = forward / np.linalg.norm(forward), up / np.linalg.norm(up)  # a node's scale does not zoom
    lower, upper = framed.bounds()
    center, radius = (lower + upper) / 2.0, max(float(np.linalg.norm(upper - lower)) / 2.0, 1e-9)
    depth = float(np.dot(center - eye, forward))
    target = eye + forward * (depth if depth > 1e-6 * radius else radius)
    reach = float(np.linalg.norm(center - eye)) + radius  # beyond every point of the scene
    far = file_camera.far if file_camera.far is not None else max(reach * 1.01, file_camera.near * 2.0)
    near = file_camera.near if file_camera.near > 0.0 else far * 1e-6  # orthographic znear may be 0
    common = dict(eye=tuple(map(float, eye)), target=tuple(map(float, target)), up=tuple(map(float, up)), near=near, far=far)
    if file_camera.projection == "perspective":
        return Camera(fov_y=file_camera.fov_y, **common)
    return Camera(projection="orthographic", ortho_height=2.0 * file_camera.half_height, **common)


def _animation(reading: Mapping[str, Any]) -> tuple[float | None, int | str]:
    """(time, animation) the mesh was read at, as load_mesh reads them: an animation chosen
    alone is shown at its start."""
    time, animation = reading.get("animation_time"), reading.get("animation_index")
    if animation is not None and time is None:
        time = 0.0
    return time, 0 if animation is None else animation
