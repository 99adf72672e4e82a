"""How a bare mesh becomes a scene: the one policy for a mesh drawn without a scene file
(`wgpu-shading render teapot.obj`, builtin:NAME, example:NAME), as model viewers show one.
assets/mesh_scene.py reads the file and its lights; everything decided is decided here.

- Material: the file's own, part by part; else OpenGL's default white-grey where the mesh
  has vertex colours (they show as they are); else gold.
- Placement: the object is turned so that the file's up axis (`--up`, f3d's rule) points
  along +Y.
- Camera: the file's own when the view asks for one (`--camera-index`, placed_file_camera);
  else on +Z looking along −Z with +Y up, as f3d's default view, but raised 19°
  (FRAMING_DIRECTION (0, 0.35, 1)) so that a shape lying flat, such as a torus, is not seen
  edge-on; as far as the turned mesh's bounding sphere needs to fit the narrower field of
  view, near and far enclosing it. Turning the mesh shows what f3d shows when it turns its
  camera instead (from −Y, +Z up on screen, for `--up +Z`).
- Lights: a key light plus a headlight fill (below) and global ambient 0.2; decoded to
  linear light when every part is drawn in linear colour space (a glTF: neutral grey, as
  viewers show it). A file with its own lights (glTF KHR_lights_punctual) is lit by them
  instead, as viewers do, unless the view asks for the viewer's (`--viewer-lights`).
- When a view moves the camera (scene/view/apply.py): near and far enclose the object
  again (unless the view gives them), and the viewer lights are made again for the new
  camera as long as the scene's lights are the ones made here; a file's lights, or lights
  the view or a caller replaced, stay.

What was made is recorded on the scene as data, `Scene.bare_mesh` (a `BareMesh`: the
viewer lights it made, or None for a file's own), so nothing later has to guess.

The viewer lights. A single light leaves the side away from it black (ambient alone is
0.2 × the material's ambient: 12/255 for gold), which hides the shape. Viewers add light
from the camera: f3d (VTK's light kit) uses a key light 50° above the view plus a fill,
back lights and a headlight of a third of the key. Two directional lights give most of it:
the key, from KEY_ELEVATION above and KEY_AZIMUTH to the right of the view direction, with
the one highlight; and a headlight fill along the view direction without specular (a second
highlight in the middle of every sphere looks wrong), so every surface the camera sees is
lit. Measured in tests/test_viewer_lighting.py: on the built-in and sample meshes, under 5 %
of the covered pixels are darker than 32/255.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, Iterable, Sequence

import numpy as np
from pyglm import glm

from ...errors import SceneError
from ..camera import Camera
from ..lights import DirectionalLight
from ..maps import srgb_decode
from ..material import Material
from ..material_table import material as named_material
from ..geometry.mesh import Mesh
from ..objects import BareMesh, Scene, SceneObject

DEFAULT_SIZE = (512, 512)  # the image, when the view gives no size
DEFAULT_MATERIAL = "gold"  # for a mesh without materials or vertex colours
AMBIENT = (0.2, 0.2, 0.2, 1.0)  # global ambient (OpenGL's default)
# The view direction of the framing (+Y up): from the front, a little above.
FRAMING_DIRECTION = (0.0, 0.35, 1.0)
KEY_ELEVATION = 45.0  # degrees above the view direction
KEY_AZIMUTH = 30.0  # degrees to the right
KEY_DIFFUSE = (0.7, 0.7, 0.7, 1.0)
KEY_SPECULAR = (1.0, 1.0, 1.0, 1.0)
HEADLIGHT_DIFFUSE = (0.5, 0.5, 0.5, 1.0)
SINGLE_PLACE_RADIUS = 1.0  # the framing of a mesh without extent (a single point), world units


def bare_mesh_scene(
    mesh: Mesh,
    size: tuple[int, int] | None = None,
    material_name: str | None = None,
    *,
    up: str | None = None,
    file_lights: Sequence[tuple[Any, np.ndarray]] = (),
    file_camera: tuple[Camera, np.ndarray, bool] | None = None,
    framing: Mesh | None = None,
) -> Scene:
    """The scene of a bare mesh (module docstring). file_lights: the file's own lights,
    each with its node's matrix in the file's space (glTF KHR_lights_punctual); () uses the
    viewer's. file_camera: the file's own camera instead of the framing one (`--camera-index`:
    the camera in its node's frame, the node's matrix in the file's space, whether its far
    plane is infinite). framing: a mesh to frame instead of `mesh`, in the file's space (an
    animation frames every pose it takes). A camera or lights that cannot be placed for the
    mesh raise SceneError."""
    size = size or DEFAULT_SIZE
    if material_name:
        chosen = named_material(material_name)
    elif any(part.material is not None for part in mesh.parts):
        chosen = None  # the file's materials, part by part
    elif mesh.colors is not None:
        chosen = Material()  # OpenGL's default white-grey: the vertex colors show as they are
    else:
        chosen = named_material(DEFAULT_MATERIAL)
    placed = SceneObject(mesh, chosen, up=up or "+Y")
    framed = framing or mesh
    if placed.up != "+Y":  # frame the turned mesh: a mesh with the turn baked in, for framing only
        world = framed.world_positions() @ placed.world_from_model()[:3, :3].T
        framed = Mesh.from_arrays(world, framed.indices, normals=framed.normals, name=framed.name)
    camera = framing_camera(framed, size) if file_camera is None else placed_file_camera(*file_camera, placed, framed)
    lights, ambient = viewer_lighting((placed,), camera)
    own = _placed_file_lights(file_lights, placed)
    return Scene(objects=(placed,), lights=own or lights, camera=camera, size=size, ambient=ambient,
                 bare_mesh=BareMesh(viewer_lights=None if own else lights))


# --------------------------------------------------------------------------- a view moves the camera


def enclosing_depth(camera: Camera, obj: SceneObject, near: float | None = None, far: float | None = None) -> Camera:
    """`camera` with near and far enclosing the object again, where the view gives no plane."""
    fitted_near, fitted_far = object_depth_range(camera.eye, obj)
    try:
        return replace(camera, near=fitted_near if near is None else near, far=fitted_far if far is None else far)
    except SceneError as error:
        raise SceneError(f"camera options: {error}") from None


def relit(scene: Scene, objects: tuple[SceneObject, ...], camera: Camera) -> dict[str, Any]:
    """The scene's changes when the view gave it `objects` and `camera`: the viewer lights
    made for them, while the scene's lights are the ones the policy made ({} otherwise)."""
    made = scene.bare_mesh.viewer_lights if scene.bare_mesh is not None else None
    if made is None or scene.lights != made:
        return {}
    lights, ambient = viewer_lighting(objects, camera)
    return {"lights": lights, "ambient": ambient, "bare_mesh": replace(scene.bare_mesh, viewer_lights=lights)}


# --------------------------------------------------------------------------- framing


def bounding_sphere(mesh: Mesh) -> tuple[np.ndarray, float]:
    """Centre and radius of the mesh's bounding box's sphere (world units); a unit sphere
    around a mesh at a single place (a point cloud of one point: Mesh allows no other mesh
    without extent), whose points show at their size in pixels from any distance."""
    lower, upper = mesh.bounds()
    radius = float(np.linalg.norm(upper - lower)) / 2.0
    return (lower + upper) / 2.0, radius if radius > 0.0 else SINGLE_PLACE_RADIUS


def depth_range(eye, center, radius: float) -> tuple[float, float]:
    """near and far planes that enclose a sphere seen from `eye` (eye inside it: near tiny)."""
    distance = float(np.linalg.norm(np.asarray(eye, dtype=np.float64) - np.asarray(center, dtype=np.float64)))
    far = distance + 1.5 * radius
    return max(distance - 1.5 * radius, far * 1e-4), far


def object_depth_range(eye, obj: SceneObject) -> tuple[float, float]:
    """near and far planes that enclose a placed object seen from `eye`: its mesh's bounding
    sphere moved by the object's model matrix (which may turn the mesh, e.g. `--up`)."""
    center, radius = bounding_sphere(obj.mesh)
    model = glm.dmat4(obj.world_from_model())
    center = glm.dvec3(model * glm.dvec4(*(center - np.asarray(obj.mesh.origin)), 1.0))
    radius *= abs(glm.determinant(glm.dmat3(model))) ** (1.0 / 3.0)
    return depth_range(eye, np.array(center), radius)


def framing_camera(mesh: Mesh, size: tuple[int, int], fov_y: float = 45.0) -> Camera:
    """A camera that frames the whole mesh, looking along −Z, a little from above."""
    center, radius = bounding_sphere(mesh)
    aspect = size[0] / size[1]
    half_fov = math.radians(fov_y) / 2.0
    narrowest = min(half_fov, math.atan(math.tan(half_fov) * aspect))
    distance = radius / math.sin(narrowest) * 1.05
    view_from = np.array(glm.normalize(glm.dvec3(*FRAMING_DIRECTION)))
    eye = center + view_from * distance
    near, far = depth_range(eye, center, radius)
    return Camera(
        eye=tuple(float(v) for v in eye),
        target=tuple(float(v) for v in center),
        up=(0.0, 1.0, 0.0),
        fov_y=fov_y,
        near=near,
        far=far,
    )


# --------------------------------------------------------------------------- lights


def camera_axes(camera: Camera) -> tuple[glm.dvec3, glm.dvec3, glm.dvec3]:
    """World-space right, up and backward (towards the viewer) unit vectors of the camera."""
    backward = glm.normalize(glm.dvec3(*camera.eye) - glm.dvec3(*camera.target))
    right = glm.normalize(glm.cross(glm.dvec3(*camera.up), backward))
    return right, glm.cross(backward, right), backward


def headlight(camera: Camera, diffuse=HEADLIGHT_DIFFUSE, specular=(0.0, 0.0, 0.0, 1.0)) -> DirectionalLight:
    """A directional light travelling along the view direction (from the eye)."""
    _, _, backward = camera_axes(camera)
    return DirectionalLight(direction=tuple(-backward), diffuse=diffuse, specular=specular)


def key_light(camera: Camera) -> DirectionalLight:
    right, up, backward = camera_axes(camera)
    elevation, azimuth = math.radians(KEY_ELEVATION), math.radians(KEY_AZIMUTH)
    to_light = math.cos(elevation) * (math.sin(azimuth) * right + math.cos(azimuth) * backward) + math.sin(elevation) * up
    return DirectionalLight(direction=tuple(-to_light), diffuse=KEY_DIFFUSE, specular=KEY_SPECULAR)


def viewer_lights(camera: Camera) -> tuple[DirectionalLight, DirectionalLight]:
    """The viewer lights for `camera`, as display values: key light and headlight fill."""
    return key_light(camera), headlight(camera)


def viewer_lighting(objects: Iterable[SceneObject], camera: Camera) -> tuple[tuple, tuple[float, float, float, float]]:
    """The viewer lights and global ambient for `objects` seen by `camera`.

    Objects all drawn with their file's linear-colour-space materials (a bare glTF) get them
    decoded to linear light: they were chosen as display values, and decoding keeps a white
    surface as bright as in display values (neutral grey, as viewers show it)."""
    objects = tuple(objects)
    lights, ambient = viewer_lights(camera), AMBIENT
    linear = bool(objects) and all(
        obj.material is None and all(part.material is not None and part.material.color_space == "linear" for part in obj.mesh.parts)
        for obj in objects
    )
    if not linear:
        return lights, ambient
    return tuple(replace(light, ambient=_linear(light.ambient), diffuse=_linear(light.diffuse),
                         specular=_linear(light.specular)) for light in lights), _linear(ambient)


def _linear(color) -> tuple[float, float, float, float]:
    """An RGBA colour given as display values, in linear light (RGB decoded, alpha kept)."""
    rgb = srgb_decode(np.clip(np.asarray(color[:3], dtype=np.float64), 0.0, 1.0))
    return (float(rgb[0]), float(rgb[1]), float(rgb[2]), float(color[3]))


def _file_to_world(placed: SceneObject) -> np.ndarray:
    """The file's space to the world: the object's model matrix without the mesh's centring
    (Mesh.origin), so that what hangs on the file's nodes lands where the mesh does."""
    model = placed.world_from_model()
    model[:3, 3] -= model[:3, :3] @ np.asarray(placed.mesh.origin)
    return model


def placed_file_camera(camera: Camera, node: np.ndarray, infinite: bool, placed: SceneObject, framed: Mesh) -> Camera:
    """A file's camera (in its node's frame) in the world: at the node's origin, looking
    along its −Z with its +Y up (glTF 2.0 §3.10; the node's scale does not zoom), turned with
    the object; its target on that axis at the depth of the framed mesh's centre, and an
    infinite far plane put just beyond it."""
    matrix = _file_to_world(placed) @ node
    eye, forward, up = matrix[:3, 3], -matrix[:3, 2], matrix[:3, 1]
    forward, up = forward / np.linalg.norm(forward), up / np.linalg.norm(up)
    center, radius = bounding_sphere(framed)
    depth = float(np.dot(center - eye, forward))
    target = eye + forward * (depth if depth > 1e-6 * radius else radius)
    far = max((float(np.linalg.norm(center - eye)) + radius) * 1.01, camera.near * 2.0) if infinite else camera.far
    return replace(camera, eye=tuple(map(float, eye)), target=tuple(map(float, target)), up=tuple(map(float, up)), far=far)


def _placed_file_lights(file_lights: Sequence[tuple[Any, np.ndarray]], placed: SceneObject) -> tuple:
    """The file's own lights in world space: each by its node's matrix in the file's space,
    then turned with the object (its `up`); () when it has none."""
    to_world = _file_to_world(placed)
    placed_lights = []
    for light, node in file_lights:
        matrix = to_world @ node
        changes = {}
        if hasattr(light, "position"):
            changes["position"] = tuple(float(v) for v in matrix[:3, 3])
        if hasattr(light, "direction"):
            axis = -matrix[:3, 2]
            changes["direction"] = tuple(float(v) for v in axis / np.linalg.norm(axis))
        placed_lights.append(replace(light, **changes))
    return tuple(placed_lights)
