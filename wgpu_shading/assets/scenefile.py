"""Scene files (TOML, docs/scene-files.md) → Scene.

Every key is checked: an unknown key is an error with a suggestion (a typo such as
`difuse` must not silently fall back to a default), and every error names the file, the
table and the key. Paths (meshes, textures) are relative to the scene file.

Extensions beyond the contract (additions only, nothing renamed):
  material = { base = "gold", emission = [...] }   start from a named material
  material = { texture = "t.png" }                 no colors given: the seed's material-less
                                                   case, ambient = diffuse = specular = 1
  mesh = "builtin:sphere?slices=20&stacks=20"      parameters of built-in meshes
An object without `material` uses its mesh file's own materials, part by part (OBJ/MTL,
glTF), else OpenGL's default. `crease_angle` (degrees) and `up` ("+Y", "+Z", ...) on an
object: docs/real-world-files.md.
"""

from __future__ import annotations

import os
from dataclasses import fields as dataclass_fields
from pathlib import Path
from typing import Any, Mapping

from ..errors import MeshError, SceneError, UsageError, shown
from ..scene.view.apply import BACKGROUND_KEYS, CAMERA_MOVES, place_camera, with_background
from ..scene.view.options import ViewOptions, scene_file_keys
from ..scene import BUILTIN_PREFIX
from ..scene.material_table import material as named_material
from .examples import EXAMPLE_PREFIX, models_hint, resolve_example
from .meshes import load_mesh
from ..scene.maps import MAP_FIELDS, alpha_pixels
from ..scene.material import Texture
from ..scene.values import MAX_LIGHTS, MAX_OBJECTS
from .files import check_regular_file
from .textures import load_texture
from ..scene import (
    LIGHT_TYPES,
    Camera,
    Material,
    Scene,
    SceneObject,
    ShadowSettings,
    Shading,
    image_size,
)

# The keys of each table. [output], [shading] and [camera] hold view options only, and the
# view options of objects, their materials and lights join those tables' own keys: all
# from the one table of options (scene/view/options.py), so a new option is a new key.
_TOP_LEVEL = {"output", "shading", "camera", "shadows", "ambient", "lights", "objects"}
_SECTIONS = {
    "output": set(scene_file_keys("output")),
    "shading": set(scene_file_keys("shading")),
    "camera": set(scene_file_keys("camera")),
    "shadows": set(scene_file_keys("shadows")),
    "ambient": {"color"},
}
_LIGHT_KEYS = {
    kind: {"type", *(f.name for f in dataclass_fields(light_type)), *scene_file_keys("lights")} for kind, light_type in LIGHT_TYPES.items()
}
_OBJECT_PLACEMENT = ("translate", "rotate", "scale")
_OBJECT_KEYS = {"mesh", *_OBJECT_PLACEMENT, *scene_file_keys("objects")}
_MATERIAL_IMAGES = ("texture", *MAP_FIELDS)  # paths of image files, relative to the scene file
_MATERIAL_VALUES = tuple(dict.fromkeys((
    "ambient", "diffuse", "specular", "emission", "shininess", "texture_mode", "alpha_mode", "alpha_cutoff",
    "normal_scale", "bump_scale", "occlusion_strength", "color_space", *scene_file_keys("objects", "material"),
)))
_MATERIAL_KEYS = {"base", *_MATERIAL_IMAGES, *_MATERIAL_VALUES}
_COLOR_KEYS = ("ambient", "diffuse", "specular")


# Scene files are small: a bigger one is not a scene (and tomllib would hold it all).
MAX_SCENE_FILE_BYTES = 16 << 20


def _check_keys(table: Mapping[str, Any], allowed: set[str], where: str, note: str = "") -> None:
    for key in table:
        if key not in allowed:
            import difflib  # (imported on a mistake only: ~2 ms of every start)
            close = difflib.get_close_matches(key[:100], allowed, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else f"; expected one of {', '.join(sorted(allowed))}"
            raise SceneError(f"{where}: unknown key {shown(key)}{note}{hint}")


def _table(document: Mapping[str, Any], name: str) -> Mapping[str, Any]:
    value = document.get(name, {})
    if not isinstance(value, dict):
        raise SceneError(f"[{name}]: expected a table, got {type(value).__name__} {shown(value)}")
    _check_keys(value, _SECTIONS[name], f"[{name}]")
    return value


def _array_of_tables(document: Mapping[str, Any], name: str) -> list[Mapping[str, Any]]:
    value = document.get(name, [])
    if not isinstance(value, list) or not all(isinstance(item, dict) for item in value):
        raise SceneError(f"[[{name}]]: expected an array of tables ([[{name}]] sections)")
    return value


def _resolve(path_text: str, base: Path) -> Path:
    path = Path(os.path.expanduser(path_text))
    return path if path.is_absolute() else base / path


def _material(value: Any, base: Path, where: str) -> Material:
    if isinstance(value, str):
        return named_material(value)
    if not isinstance(value, dict):
        raise SceneError(f"{where}.material: expected a material name or an inline table, got {shown(value)}")
    _check_keys(value, _MATERIAL_KEYS, f"{where}.material")
    fields: dict[str, Any] = {}
    if "base" in value:
        if not isinstance(value["base"], str):
            raise SceneError(f"{where}.material.base: expected a material name, got {shown(value['base'])}")
        start = named_material(value["base"])
        fields.update(
            ambient=start.ambient, diffuse=start.diffuse, specular=start.specular,
            emission=start.emission, shininess=start.shininess, name=start.name,
        )
    elif "texture" in value and not any(key in value for key in _COLOR_KEYS):
        # The seed's material-less texture example: lighting terms are not scaled by a material.
        fields.update(ambient=(1.0, 1.0, 1.0, 1.0), diffuse=(1.0, 1.0, 1.0, 1.0), specular=(1.0, 1.0, 1.0, 1.0))
    for key in _MATERIAL_VALUES:
        if key in value:
            fields[key] = value[key]
    for key in _MATERIAL_IMAGES:
        if key not in value:
            continue
        if not isinstance(value[key], str):
            raise SceneError(f"{where}.material.{key}: expected a path to an image, got {shown(value[key])}")
        texture_path = _resolve(value[key], base)
        try:
            fields[key] = load_texture(texture_path)
        except SceneError as error:
            raise SceneError(f"{error}{models_hint(texture_path) if not texture_path.exists() else ''}") from None
    if "alpha_map" in fields:  # its alpha channel, else its luminance (scene/maps.py); it blends unless told
        fields["alpha_map"] = Texture(alpha_pixels(fields["alpha_map"].pixels), name=fields["alpha_map"].name, encoding="linear")
        fields.setdefault("alpha_mode", "blend")
    try:
        return Material(**fields)
    except SceneError as error:
        raise SceneError(f"{where}.{error}") from None


def _light(table: Mapping[str, Any], index: int):
    where = f"[[lights]] #{index + 1}"
    kind = table.get("type", "positional")
    if not isinstance(kind, str) or kind not in _LIGHT_KEYS:
        raise SceneError(f"{where}.type: expected one of {', '.join(map(repr, _LIGHT_KEYS))}, got {shown(kind)}")
    _check_keys(table, set().union(*_LIGHT_KEYS.values()), where)
    _check_keys(table, _LIGHT_KEYS[kind], where, note=f" for a {kind} light")
    arguments = {key: value for key, value in table.items() if key != "type"}
    try:
        return LIGHT_TYPES[kind](**arguments)
    except SceneError as error:
        raise SceneError(f"{where}: {error}") from None


def _mesh_reading(table: Mapping[str, Any], where: str, reading: Mapping[str, Any]) -> dict[str, Any]:
    """The object's keys the mesh reader takes (options with load="mesh": crease_angle),
    read by their options' readers; `reading` (the command line's) replaces them."""
    found = {}
    for key, option in scene_file_keys("objects").items():
        if option.load == "mesh" and (key in reading or key in table):
            try:
                found[key] = option.read(reading[key] if key in reading else table[key], f"{where}.{key}")
            except UsageError as error:
                raise SceneError(str(error)) from None
    return found


def _object(table: Mapping[str, Any], index: int, base: Path, reading: Mapping[str, Any]) -> SceneObject:
    where = f"[[objects]] #{index + 1}"
    _check_keys(table, _OBJECT_KEYS, where)
    if "mesh" not in table:
        raise SceneError(f"{where}: missing key 'mesh' (builtin:NAME or a mesh file)")
    mesh_text = table["mesh"]
    if not isinstance(mesh_text, str):
        raise SceneError(f"{where}.mesh: expected a string, got {shown(mesh_text)}")
    source = mesh_text if mesh_text.startswith((BUILTIN_PREFIX, EXAMPLE_PREFIX)) else str(_resolve(mesh_text, base))
    mesh_reading = _mesh_reading(table, where, reading)
    try:
        mesh = load_mesh(source, **mesh_reading)
    except MeshError as error:
        hint = models_hint(Path(source)) if not Path(source).exists() else ""
        raise SceneError(f"{where}.mesh: {error}{hint}") from None
    if "material" in table:
        try:
            material = _material(table["material"], base, where)
        except SceneError as error:
            message = str(error)
            raise SceneError(message if message.startswith(where) else f"{where}.material: {message}") from None
    else:
        material = None  # the file's own materials, part by part
    # Every other key is a field of the object: its placement and its view options (up).
    placed = {key: value for key, value in table.items() if key not in ("mesh", "material", *mesh_reading)}
    try:
        return SceneObject(mesh=mesh, material=material, **placed)
    except SceneError as error:
        raise SceneError(f"{where}: {error}") from None


def _background(output: Mapping[str, Any], default) -> Any:
    """[output] background and transparent, as the options of the same names set them
    (scene/view/apply.py with_background; docs/conventions.md#the-lighting-equation)."""
    background = output.get("background", default)
    transparent = output.get("transparent")
    if transparent is not None and not isinstance(transparent, bool):
        raise SceneError(f"output.transparent: expected true or false, got {transparent!r}")
    if not isinstance(background, (list, tuple)) or len(background) not in (3, 4):
        return background  # Scene reports what is wrong with it
    return with_background(default, tuple(background), transparent)


def _camera(table: Mapping[str, Any]) -> Camera:
    """[camera]: direction, azimuth, elevation (degrees) and distance move the camera after
    the other keys placed it, as f3d's --camera-direction/--camera-azimuth-angle/... and
    the view options of the same keys do (scene/view/apply.py place_camera)."""
    keys = {key: value for key, value in table.items() if key not in CAMERA_MOVES}
    if "direction" in table and "eye" in table:
        raise SceneError("camera: give eye or direction (the eye along it at the same distance), not both")
    moves = {}
    for key, option in scene_file_keys("camera").items():
        if key in CAMERA_MOVES and key in table:
            try:
                moves[option.name] = option.read(table[key], f"camera.{key}")
            except UsageError as error:
                raise SceneError(str(error)) from None
    return place_camera(Camera(**keys), ViewOptions(**moves))


def parse_scene(
    document: Mapping[str, Any], base: str | os.PathLike[str] = ".", *,
    crease_angle: float | None = None, reading: Mapping[str, Any] | None = None,
) -> Scene:
    """A Scene from an already-parsed TOML document (paths relative to `base`).
    reading: the mesh reader's options (ViewOptions.mesh_reading(), e.g. the CLI's
    --crease-angle) replacing every object's; crease_angle is short for {"crease_angle": ...}."""
    if not isinstance(document, Mapping):
        raise SceneError(f"scene: expected a table (a parsed TOML document), got {type(document).__name__}")
    base_path = Path(base)
    _check_keys(document, _TOP_LEVEL, "scene")
    output = _table(document, "output")
    shading = _table(document, "shading")
    camera = _table(document, "camera")
    shadows = _table(document, "shadows")
    ambient = _table(document, "ambient")
    for key, limit in (("lights", MAX_LIGHTS), ("objects", MAX_OBJECTS)):  # counted before any is built or loaded
        count = len(document.get(key) or ()) if isinstance(document.get(key), list) else 0
        if count > limit:
            raise SceneError(f"[[{key}]]: {count} {key}; at most {limit} are supported")
    lights = [_light(table, i) for i, table in enumerate(_array_of_tables(document, "lights"))]
    reading = {**(reading or {}), **({} if crease_angle is None else {"crease_angle": crease_angle})}
    objects = [_object(table, i, base_path, reading) for i, table in enumerate(_array_of_tables(document, "objects"))]
    defaults = Scene()
    # [output] keys are Scene fields (size, samples, ...), but for the background's two.
    fields = {key: value for key, value in output.items() if key not in BACKGROUND_KEYS}
    if "size" in fields:
        fields["size"] = image_size(fields["size"])
    return Scene(
        objects=tuple(objects),
        lights=tuple(lights),
        camera=_camera(camera),
        shading=Shading(**shading),
        shadows=ShadowSettings(**shadows),
        ambient=ambient.get("color", defaults.ambient),
        background=_background(output, defaults.background),
        **fields,
    )


def load_scene(path: str | os.PathLike[str], *, crease_angle: float | None = None, reading: Mapping[str, Any] | None = None) -> Scene:
    """Read a scene file (or `example:NAME.toml`). Errors name the file and the offending key."""
    if not isinstance(path, (str, os.PathLike)):
        raise SceneError(f"load_scene: expected a path to a scene file, got {type(path).__name__}")
    path = Path(resolve_example(str(path)))
    check_regular_file(path, f"scene file {str(path)!r}", SceneError)  # a FIFO would block open()
    try:
        with open(path, "rb") as file:
            data = file.read(MAX_SCENE_FILE_BYTES + 1)
        if len(data) > MAX_SCENE_FILE_BYTES:
            raise SceneError(f"scene file {str(path)!r} is larger than {MAX_SCENE_FILE_BYTES >> 20} MiB; not a scene file")
        text = data.decode("utf-8")
    except FileNotFoundError:
        raise SceneError(f"scene file {str(path)!r} not found") from None
    except (OSError, UnicodeDecodeError, ValueError) as error:  # ValueError: a NUL in the path
        raise SceneError(f"scene file {str(path)!r} cannot be read: {error}") from None
    import tomllib  # here: a cold start that reads no scene file skips its ~2 ms import

    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise SceneError(f"{path}: invalid TOML: {error}") from None
    except RecursionError:
        raise SceneError(f"{path}: invalid TOML: arrays or tables nested too deeply") from None
    except ValueError as error:  # e.g. an integer of more than 4300 digits
        raise SceneError(f"{path}: invalid TOML: {error}") from None
    try:
        scene = parse_scene(document, path.parent, crease_angle=crease_angle, reading=reading)
    except (SceneError, MeshError) as error:
        raise SceneError(f"{path}: {error}") from None
    except RecursionError:
        raise SceneError(f"{path}: values nested too deeply") from None
    if not scene.objects:
        # A scene *file* is meant to be drawn: the background alone, with exit 0, looks like a
        # broken renderer (an empty or truncated file). parse_scene stays permissive for
        # library callers that add objects themselves.
        raise SceneError(f"{path}: no [[objects]] section; nothing would be drawn (add one, e.g. mesh = \"builtin:sphere\")")
    return scene
