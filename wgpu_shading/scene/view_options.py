"""What a view is, once: the table of view options, `ViewOptions` (a value for each, None =
leave the scene as it is) and `apply_view_options`, the one function that applies them.

Each option has four spellings, all taken from VIEW_OPTIONS below (docs/view-options.md
lists them; tests/test_view_options.py checks that they agree):
  - its `render` flag(s), which are also its `batch` (and `turntable`, `check`, `shader`)
    flags: cli/arguments.py adds them to each command from this table;
  - its manifest column (dataset/manifest.py reads rows through `read`);
  - its scene-file key (assets/scenefile.py).
`render_command` writes options back as a `wgpu-shading render` command line.

Options that act when a file is read (crease_angle; up and size also frame a bare mesh)
are given to the loader as well: assets/view_loader.py `load_view` does both.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Any, Callable

import numpy as np
from pyglm import glm

from ..errors import SceneError, UsageError
from .camera import PROJECTIONS, Camera
from .framing import object_depth_range
from .viewer_lights import viewer_lights
from .material_table import material as named_material
from .maps import SCENE_COLOR_SPACES, bare_mesh_lighting
from .objects import Scene
from .values import FREQUENCIES, REFLECTIONS
from .view_values import (
    LIGHT_SYNTAX,
    parse_light,
    read_bool,
    read_choice,
    read_color,
    read_crease_angle,
    read_direction,
    read_float,
    read_lights,
    read_material,
    read_samples,
    read_shininess,
    read_size,
    read_up,
    read_vector,
    spell,
)


@dataclass(frozen=True)
class ViewOption:
    """One view option and its spellings.

    flags:    command-line flags taking a value (flags[0] is the one render_command writes)
    switches: flags without a value, each storing its constant: (flag, constant, help)
    column:   the manifest column; scene_key: where a scene file holds it
    load:     it acts when the file is read (the loader must be given it too)"""

    name: str
    read: Callable[[Any, str], Any]
    column: str
    scene_key: str
    help: str
    flags: tuple[str, ...] = ()
    switches: tuple[tuple[str, Any, str], ...] = ()
    metavar: str | None = None
    group: str = "view"
    repeated: bool = False
    load: bool = False

    @property
    def all_flags(self) -> tuple[str, ...]:
        return self.flags + tuple(flag for flag, _, _ in self.switches)


def _positive(value: Any, where: str) -> float:
    return read_float(value, where, 0.0, low_open=True)


def _degrees(value: Any, where: str) -> float:
    return read_float(value, where)


_O = ViewOption
VIEW_OPTIONS: tuple[ViewOption, ...] = (
    _O("size", read_size, "size", "[output] size", "image size, WIDTHxHEIGHT, WIDTH,HEIGHT or SIZE (default: the scene's, or 512)",
       flags=("--size", "--resolution"), metavar="SIZE", group="output", load=True),
    _O("samples", read_samples, "samples", "[output] samples",
       "antialiasing: 4 = MSAA with 4 samples per pixel (default: the scene's, 1)", flags=("--samples",), metavar="{1,4}", group="output"),
    _O("background", read_color, "background", "[output] background", "background color, components 0..1",
       flags=("--background-color",), metavar="R,G,B[,A]", group="output"),
    _O("transparent", read_bool, "transparent", "[output] transparent",
       "transparent background: alpha 0 where nothing is drawn (PNG, TIFF, .npy)",
       switches=(("--no-background", True, "transparent background: alpha 0 where nothing is drawn (PNG, TIFF, .npy)"),
                 ("--transparent", True, "the same as --no-background"),
                 ("--no-transparent", False, "opaque background (alpha 1), whatever the scene file says")), group="output"),
    _O("material", read_material, "material", "[[objects]] material", "material name for every object (see `wgpu-shading materials`)",
       flags=("--material",), metavar="NAME"),
    _O("shininess", read_shininess, "shininess", "[[objects]] material.shininess",
       "specular exponent of every object's material(s), 0..1e6", flags=("--shininess",), metavar="N"),
    _O("frequency", read_choice(FREQUENCIES), "frequency", "[shading] frequency", "shading frequency (overrides the scene)",
       flags=("--frequency",), metavar="{" + ",".join(FREQUENCIES) + "}"),
    _O("reflection", read_choice(REFLECTIONS), "reflection", "[shading] reflection", "reflection model (overrides the scene)",
       flags=("--reflection",), metavar="{" + ",".join(REFLECTIONS) + "}"),
    _O("blinn_exponent_scale", read_float, "blinn_exponent_scale", "[shading] blinn_exponent_scale",
       "k_blinn: Blinn-Phong exponent = shininess × K (seed: 3, OpenGL: 1)", flags=("--blinn-exponent-scale",), metavar="K"),
    _O("local_viewer", read_bool, "local_viewer", "[shading] local_viewer",
       "the viewer: local (V towards the eye, the default) or infinite (OpenGL's default, V = (0, 0, 1))",
       switches=(("--local-viewer", True, "V towards the eye at every point (the default)"),
                 ("--infinite-viewer", False, "OpenGL's default viewer: V = (0, 0, 1)"))),
    _O("two_sided", read_bool, "two_sided", "[shading] two_sided", "light back faces with the flipped normal",
       switches=(("--two-sided", True, "light back faces with the flipped normal"),
                 ("--one-sided", False, "light back faces as front faces are lit (the default)"))),
    _O("clamp_vertex_colors", read_bool, "clamp_vertex_colors", "[shading] clamp_vertex_colors",
       "flat/Gouraud: clamp each vertex's color before interpolation, as OpenGL fixed-function does",
       switches=(("--clamp-vertex-colors", True, "flat/Gouraud: clamp each vertex's color before interpolation, as OpenGL fixed-function does"),
                 ("--no-clamp-vertex-colors", False, "interpolate the unclamped vertex colors (the default)"))),
    _O("color_space", read_choice(SCENE_COLOR_SPACES), "color_space", "[shading] color_space",
       "colour values: auto (glTF linear with sRGB output, others display values), display or linear for every material",
       flags=("--color-space",), metavar="{" + ",".join(SCENE_COLOR_SPACES) + "}"),
    _O("crease_angle", read_crease_angle, "crease_angle", "[[objects]] crease_angle",
       "mesh files without normals: edges sharper than this are creases (default 60; 180 smooth, 0 flat)",
       flags=("--crease-angle",), metavar="DEG", load=True),
    _O("up", read_up, "up", "[[objects]] up", "the mesh files' up axis: +Y (default), -Y, +Z, -Z, +X, -X (like f3d)",
       flags=("--up",), metavar="AXIS", load=True),
    _O("camera_position", read_vector, "eye", "[camera] eye", "the eye", flags=("--camera-position",), metavar="X,Y,Z", group="camera"),
    _O("camera_focal_point", read_vector, "target", "[camera] target", "the point looked at",
       flags=("--camera-focal-point",), metavar="X,Y,Z", group="camera"),
    _O("camera_direction", read_direction, "direction", "[camera] direction",
       "look along DIR (-Z or X,Y,Z) at the same distance; --camera-position overrides it",
       flags=("--camera-direction",), metavar="DIR", group="camera"),
    _O("camera_view_up", read_direction, "camera_up", "[camera] up", "the camera's up vector, +Z or X,Y,Z",
       flags=("--camera-view-up",), metavar="DIR", group="camera"),
    _O("camera_view_angle", read_float, "fov_y", "[camera] fov_y", "vertical field of view",
       flags=("--camera-view-angle",), metavar="DEG", group="camera"),
    _O("camera_near", read_float, "near", "[camera] near", "near plane distance (default: the scene's; a bare mesh's encloses it)",
       flags=("--camera-near",), metavar="D", group="camera"),
    _O("camera_far", read_float, "far", "[camera] far", "far plane distance (default: the scene's; a bare mesh's encloses it)",
       flags=("--camera-far",), metavar="D", group="camera"),
    _O("camera_projection", read_choice(PROJECTIONS), "projection", "[camera] projection",
       "perspective or orthographic; orthographic keeps the framing (height = the perspective view's at the target)",
       flags=("--camera-projection",), metavar="P", group="camera",
       switches=(("--camera-orthographic", "orthographic",
                  "orthographic projection keeping the framing (height = the perspective view's at the target)"),)),
    _O("camera_ortho_height", read_float, "ortho_height", "[camera] ortho_height",
       "orthographic view height in world units (implies --camera-orthographic)",
       flags=("--camera-ortho-height",), metavar="H", group="camera"),
    _O("camera_azimuth", _degrees, "azimuth", "[camera] azimuth",
       "turn the camera about the up vector through the target, after the options above",
       flags=("--camera-azimuth-angle", "--camera-azimuth"), metavar="DEG", group="camera"),
    _O("camera_elevation", _degrees, "elevation", "[camera] elevation",
       "raise the camera about its right axis through the target, after the azimuth",
       flags=("--camera-elevation-angle", "--camera-elevation"), metavar="DEG", group="camera"),
    _O("camera_distance", _positive, "distance", "[camera] distance",
       "then move the eye along its line of sight to this distance from the target",
       flags=("--camera-distance",), metavar="D", group="camera"),
    _O("lights", read_lights, "lights", "[[lights]]", f"replace the lights (repeat for more): {LIGHT_SYNTAX}",
       flags=("--light",), metavar="SPEC", group="lights", repeated=True),
    _O("viewer_lights", read_bool, "viewer_lights", "(none: a scene file lists its [[lights]])",
       "a glTF file with its own lights (KHR_lights_punctual) is lit by them; true: by the viewer's key light and headlight instead",
       switches=(("--viewer-lights", True, "light a glTF file that has its own lights with the viewer's key light and headlight instead"),
                 ("--file-lights", False, "light a glTF file with its own KHR_lights_punctual lights when it has them (the default)")),
       group="lights", load=True),
)
OPTIONS_BY_NAME = {option.name: option for option in VIEW_OPTIONS}


@dataclass(frozen=True)
class ViewOptions:
    """A value for each view option; None leaves the scene's own. Values are read (and
    checked) by the table's readers, so Python values, flag text and CSV text all work."""

    size: tuple[int, int] | None = None
    samples: int | None = None
    background: tuple[float, ...] | None = None
    transparent: bool | None = None
    material: str | None = None
    shininess: float | None = None
    frequency: str | None = None
    reflection: str | None = None
    blinn_exponent_scale: float | None = None
    local_viewer: bool | None = None
    two_sided: bool | None = None
    clamp_vertex_colors: bool | None = None
    color_space: str | None = None
    crease_angle: float | None = None
    up: str | None = None
    camera_position: tuple[float, float, float] | None = None
    camera_focal_point: tuple[float, float, float] | None = None
    camera_direction: tuple[float, float, float] | None = None
    camera_view_up: tuple[float, float, float] | None = None
    camera_view_angle: float | None = None
    camera_near: float | None = None
    camera_far: float | None = None
    camera_projection: str | None = None
    camera_ortho_height: float | None = None
    camera_azimuth: float | None = None
    camera_elevation: float | None = None
    camera_distance: float | None = None
    lights: tuple[str, ...] | None = None
    viewer_lights: bool | None = None

    def __post_init__(self) -> None:
        for option in VIEW_OPTIONS:
            value = getattr(self, option.name)
            if value is not None:
                object.__setattr__(self, option.name, option.read(value, option.name))

    def given(self) -> dict[str, Any]:
        """The options that are set, by name, in table order."""
        return {option.name: getattr(self, option.name) for option in VIEW_OPTIONS if getattr(self, option.name) is not None}


assert [f.name for f in fields(ViewOptions)] == [option.name for option in VIEW_OPTIONS]


def render_command(source: str, options: ViewOptions) -> list[str]:
    """`wgpu-shading render SOURCE FLAGS...` drawing the same pixels as load_view(source,
    options): ["wgpu-shading", "render", source, ...]; cli.main's argv is [1:]. Values go
    as --flag=value (a value may start with "-") and floats through repr (exact)."""
    argv = ["wgpu-shading", "render", source]
    for name, value in options.given().items():
        option = OPTIONS_BY_NAME[name]
        switch = next((flag for flag, constant, _ in option.switches if constant == value), None)
        if switch is not None:
            argv.append(switch)
        elif option.repeated:
            argv.extend(f"{option.flags[0]}={spell(item)}" for item in value)
        else:
            argv.append(f"{option.flags[0]}={spell(value)}")
    return argv


# --------------------------------------------------------------------------- applying


def apply_view_options(scene: Scene, options: ViewOptions, *, follow_camera: bool = False) -> Scene:
    """`scene` with `options` applied, in table order: output, objects (up, material,
    shininess), shading, camera (keys, then azimuth and elevation, then distance), lights.

    follow_camera: the scene is a framed bare mesh (assets/mesh_scene.py): when the options
    move its camera, its depth range and its viewer lights follow, as in `render MESH`.
    crease_angle acts only when a mesh is read (load_view gives it to the loader)."""
    changes: dict[str, Any] = {}
    if options.size is not None and options.size != scene.size:
        changes["size"] = options.size
    if options.samples is not None:
        changes["samples"] = options.samples
    background = scene.background
    if options.background is not None:
        background = options.background if len(options.background) == 4 else (*options.background, background[3])
    if options.transparent is not None:
        background = (*background[:3], 0.0 if options.transparent else 1.0)
    if background != scene.background:
        changes["background"] = background
    objects = _objects(scene, options)
    if objects is not scene.objects:
        changes["objects"] = objects
    shading = {
        key: getattr(options, key)
        for key in ("frequency", "reflection", "blinn_exponent_scale", "local_viewer", "two_sided", "clamp_vertex_colors", "color_space")
        if getattr(options, key) is not None
    }
    if shading:
        changes["shading"] = replace(scene.shading, **shading)
    camera = place_camera(scene.camera, options)
    if camera is not scene.camera:
        if follow_camera and scene.objects:
            near, far = object_depth_range(camera.eye, changes.get("objects", scene.objects)[0])
            near = near if options.camera_near is None else options.camera_near
            far = far if options.camera_far is None else options.camera_far
            try:
                camera = replace(camera, near=near, far=far)
            except SceneError as error:
                raise SceneError(f"camera options: {error}") from None
        changes["camera"] = camera
    if options.lights is not None:
        changes["lights"] = tuple(parse_light(spec, camera) for spec in options.lights)
    elif follow_camera and (camera is not scene.camera or "objects" in changes) and (
        scene.lights in (viewer_lights(scene.camera), bare_mesh_lighting(scene.objects, scene.camera)[0])
    ):
        # A bare mesh's viewer lights follow the camera and the materials' colour space (a
        # glTF keeps them decoded to linear light unless --material replaced its own); a
        # glTF file's own lights stay where they are.
        changes["lights"], changes["ambient"] = bare_mesh_lighting(changes.get("objects", scene.objects), camera)
    if not changes:
        return scene
    try:
        return replace(scene, **changes)
    except SceneError as error:
        raise SceneError(f"view options: {error}") from None


def _objects(scene: Scene, options: ViewOptions) -> tuple:
    if options.up is None and options.material is None and options.shininess is None:
        return scene.objects
    objects = []
    for obj in scene.objects:
        changes: dict[str, Any] = {}
        if options.up is not None and obj.up != options.up:
            changes["up"] = options.up
        if options.material is not None:
            changes["material"] = named_material(options.material)
        if options.shininess is not None:
            chosen = changes.get("material", obj.material)
            if chosen is not None:
                changes["material"] = replace(chosen, shininess=options.shininess)
            else:  # the file's own materials, part by part
                parts = tuple(replace(part, material=replace(material, shininess=options.shininess))
                              for part, material in zip(obj.mesh.parts, obj.part_materials()))
                changes["mesh"] = replace(obj.mesh, parts=parts)
        objects.append(replace(obj, **changes) if changes else obj)
    return tuple(objects)


def place_camera(camera: Camera, options: ViewOptions) -> Camera:
    """The camera moved by the camera options (f3d's order): position, focal point, direction
    (ignored when a position is given), view up, view angle, planes, projection; then the
    azimuth and elevation turns about the target; then the distance. Unchanged: `camera`."""
    changes: dict[str, Any] = {}
    for name, key in (("camera_position", "eye"), ("camera_focal_point", "target"), ("camera_view_up", "up"),
                      ("camera_view_angle", "fov_y"), ("camera_near", "near"), ("camera_far", "far"),
                      ("camera_projection", "projection"), ("camera_ortho_height", "ortho_height")):
        if getattr(options, name) is not None:
            changes[key] = getattr(options, name)
    if options.camera_direction is not None and options.camera_position is None:
        view = np.asarray(options.camera_direction, dtype=np.float64)
        target = np.asarray(changes.get("target", camera.target), dtype=np.float64)
        distance = float(np.linalg.norm(np.subtract(camera.eye, camera.target)))
        changes["eye"] = tuple(float(v) for v in target - view / np.linalg.norm(view) * distance)
    if options.camera_ortho_height is not None and options.camera_projection is None:
        changes["projection"] = "orthographic"
    try:
        placed = replace(camera, **changes) if changes else camera
        placed = placed.orbited(options.camera_azimuth or 0.0, options.camera_elevation or 0.0)
        if options.camera_distance is not None:
            target = glm.dvec3(*placed.target)
            offset = glm.dvec3(*placed.eye) - target
            placed = replace(placed, eye=tuple(target + offset * (options.camera_distance / glm.length(offset))))
    except SceneError as error:
        raise SceneError(f"camera options: {error}") from None
    return placed


COLUMNS = {option.column: option for option in VIEW_OPTIONS}  # manifest column → option


def spellings_table() -> str:
    """The Markdown table of every option's spellings (docs/view-options.md holds it; a test
    checks that the two agree)."""
    rows = ["| option | `render` and `batch` flags | manifest column | scene-file key | what it does |", "|---|---|---|---|---|"]
    for option in VIEW_OPTIONS:
        flags = [f"`{flag} {option.metavar}`" if option.metavar else f"`{flag}`" for flag in option.flags]
        flags += [f"`{flag}`" for flag, _, _ in option.switches]
        help_text = option.help.replace("|", "\\|")
        rows.append(f"| {option.name} | {', '.join(flags)} | `{option.column}` | `{option.scene_key}` | {help_text} |")
    return "\n".join(rows) + "\n"


if __name__ == "__main__":  # python -m wgpu_shading.scene.view_options > the table for docs/view-options.md
    print(spellings_table(), end="")
