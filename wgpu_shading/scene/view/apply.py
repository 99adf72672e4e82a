"""Applying view options to a Scene: `apply_view_options`, generic by each option's key
(options.py), so that a new option whose key names a field of the Scene, its Shading,
its camera, every object, every object's material(s) or every light needs no code here.

Only what is not one field is spelled out below: the background with `transparent`,
the lights given as SPECs and the camera moves (direction, azimuth, elevation, distance).
A bare mesh's scene (Scene.bare_mesh) follows its policy (scene/view/bare_mesh.py) when
the camera moves: its depth range and its viewer lights are made again.
"""

from __future__ import annotations

from dataclasses import fields, replace
from typing import Any

import numpy as np
from pyglm import glm

from ...errors import SceneError
from ..camera import Camera
from .bare_mesh import enclosing_depth, relit
from ..lights import LIGHT_TYPES
from ..material import Material
from ..objects import Scene, SceneObject, Shading
from ..shadows import ShadowSettings
from .options import VIEW_OPTIONS, ViewOption, ViewOptions
from .reading import parse_light

# The camera keys that move the camera after the others placed it (f3d's order): not fields.
CAMERA_MOVES = ("direction", "azimuth", "elevation", "distance")
# Output keys that are not a Scene field of the same name: both change the background.
BACKGROUND_KEYS = ("background", "transparent")


def _names(cls) -> set[str]:
    return {f.name for f in fields(cls)}


def unappliable(option: ViewOption) -> str | None:
    """Why `apply_view_options` could not apply the option (its key names no field), or None."""
    section, name = option.section, option.field
    known = {
        "output": _names(Scene) | set(BACKGROUND_KEYS),
        "shading": _names(Shading),
        "camera": _names(Camera) | set(CAMERA_MOVES),
        "shadows": _names(ShadowSettings),
        "objects": _names(SceneObject) | {f"material.{key}" for key in _names(Material)},
        "lights": set.intersection(*(_names(kind) for kind in LIGHT_TYPES.values())) | {""},
    }
    if section is None or option.load == "mesh" or name in known[section]:
        return None
    return f"{option.name}: key {option.key!r} names no field of what it applies to"


# The options each section applies, in table order (mesh-reader ones acted when the file was
# read): derived once from the table, since every view of a dataset applies them anew.
_SECTION_OPTIONS: dict[str | None, tuple[ViewOption, ...]] = {}
for _option in VIEW_OPTIONS:
    if _option.load != "mesh":
        _SECTION_OPTIONS.setdefault(_option.section, ())
        _SECTION_OPTIONS[_option.section] += (_option,)
del _option


def _of(options: ViewOptions, section: str) -> list[tuple[ViewOption, Any]]:
    """(option, value) of the options given in `section`, in table order."""
    given = ((option, getattr(options, option.name)) for option in _SECTION_OPTIONS.get(section, ()))
    return [(option, value) for option, value in given if value is not None]


def with_background(background: tuple, color: tuple | None = None, transparent: bool | None = None) -> tuple:
    """`background` with the background options: a colour (RGB keeps the alpha), then
    transparent (alpha 0) or opaque (alpha 1). The scene-file reader uses it too."""
    if color is not None:
        background = tuple(color) if len(color) == 4 else (*color, background[3])
    if transparent is not None:
        background = (*background[:3], 0.0 if transparent else 1.0)
    return background


def apply_view_options(scene: Scene, options: ViewOptions) -> Scene:
    """`scene` with `options` applied, in table order: output, objects (up, material,
    shininess, shadows), shading, shadows, camera (keys, then azimuth and elevation, then
    distance), lights (their shadows after the lights themselves).

    A bare mesh's scene (scene.bare_mesh) keeps its policy: when the options move its
    camera, its depth range and its viewer lights follow, as in `render MESH`.
    crease_angle acts only when a mesh is read (load_view gives it to the loader)."""
    changes: dict[str, Any] = {}
    for option, value in _of(options, "output"):
        if option.field not in BACKGROUND_KEYS and value != getattr(scene, option.field):
            changes[option.field] = value
    background = with_background(scene.background, options.background, options.transparent)
    if background != scene.background:
        changes["background"] = background
    object_options = _of(options, "objects")
    if object_options:
        changes["objects"] = tuple(_object(obj, object_options) for obj in scene.objects)
    shading = {option.field: value for option, value in _of(options, "shading")}
    if shading:
        changes["shading"] = replace(scene.shading, **shading)
    shadows = {option.field: value for option, value in _of(options, "shadows")}
    if shadows:
        changes["shadows"] = replace(scene.shadows, **shadows)
    objects = changes.get("objects", scene.objects)
    camera = place_camera(scene.camera, options)
    if camera is not scene.camera:
        if scene.bare_mesh is not None and objects:
            camera = enclosing_depth(camera, objects[0], options.camera_near, options.camera_far)
        changes["camera"] = camera
    if options.lights is not None:
        changes["lights"] = tuple(parse_light(spec, camera) for spec in options.lights)
    elif "camera" in changes or "objects" in changes:
        # A bare mesh's viewer lights follow the camera and the materials' colour space (a
        # glTF keeps them decoded to linear light unless --material replaced its own).
        changes.update(relit(scene, objects, camera))
    light_fields = {option.field: value for option, value in _of(options, "lights") if option.field}
    if light_fields:
        changes["lights"] = tuple(replace(light, **light_fields) for light in changes.get("lights", scene.lights))
    if not changes:
        return scene
    try:
        return replace(scene, **changes)
    except SceneError as error:
        raise SceneError(f"view options: {error}") from None


def _object(obj: SceneObject, object_options: list[tuple[ViewOption, Any]]) -> SceneObject:
    """One object with the object options: its own fields (up), its material (a name from
    the table) and fields of its material(s) (shininess), the file's part by part."""
    for option, value in object_options:
        value = option.to_scene(value) if option.to_scene else value
        _, _, material_field = option.field.partition(".")
        if not material_field:
            if getattr(obj, option.field) != value:
                obj = replace(obj, **{option.field: value})
        elif obj.material is not None:
            obj = replace(obj, material=replace(obj.material, **{material_field: value}))
        else:  # the file's own materials, part by part
            parts = tuple(replace(part, material=replace(material, **{material_field: value}))
                          for part, material in zip(obj.mesh.parts, obj.part_materials()))
            obj = replace(obj, mesh=replace(obj.mesh, parts=parts))
    return obj


def place_camera(camera: Camera, options: ViewOptions) -> Camera:
    """The camera moved by the camera options (f3d's order): its fields (position, focal
    point, view up, view angle, planes, projection), the direction (ignored when a position
    is given); then the azimuth and elevation turns about the target; then the distance.
    Unchanged: `camera`."""
    given = {option.field: value for option, value in _of(options, "camera")}
    changes = {key: value for key, value in given.items() if key not in CAMERA_MOVES}
    if "direction" in given and "eye" not in given:
        view = np.asarray(given["direction"], dtype=np.float64)
        target = np.asarray(changes.get("target", camera.target), dtype=np.float64)
        distance = float(np.linalg.norm(np.subtract(camera.eye, camera.target)))
        changes["eye"] = tuple(float(v) for v in target - view / np.linalg.norm(view) * distance)
    if "ortho_height" in given and "projection" not in given:
        changes["projection"] = "orthographic"
    try:
        placed = replace(camera, **changes) if changes else camera
        placed = placed.orbited(given.get("azimuth", 0.0), given.get("elevation", 0.0))
        if "distance" in given:
            target = glm.dvec3(*placed.target)
            offset = glm.dvec3(*placed.eye) - target
            placed = replace(placed, eye=tuple(target + offset * (given["distance"] / glm.length(offset))))
    except SceneError as error:
        raise SceneError(f"camera options: {error}") from None
    return placed


def scene_value(scene: Scene, option: ViewOption) -> Any:
    """The value an option has in `scene` (the first object's, for object options): where
    the live viewer's keys start from. None where the scene holds no such value."""
    section, name = option.section, option.field
    if section == "lights":  # a light field: the value every light has (None: they differ)
        values = {getattr(light, name) for light in scene.lights} if name else set()
        return values.pop() if len(values) == 1 else None
    holder = {"output": scene, "shading": scene.shading, "camera": scene.camera, "shadows": scene.shadows}.get(section)
    if section == "objects" and scene.objects:
        holder = scene.objects[0]
        if name.startswith("material."):
            holder, name = holder.surface_material, name.removeprefix("material.")
        elif name == "material":
            return getattr(holder.material, "name", None) or None
    return getattr(holder, name, None) if holder is not None and name else None
