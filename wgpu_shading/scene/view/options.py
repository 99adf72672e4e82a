"""What a view is, once: the table of view options. Everything else about an option is made
from its row (docs/view-options.md, "Adding an option"):

  - `ViewOptions`, the dataclass with a field per row (None = leave the scene as it is);
  - its `render` flags, which are also its `batch`, `turntable`, `check`, `shader` and `view`
    flags (cli/viewer_options.py adds them to each command from this table);
  - its manifest column (dataset/manifest.py reads rows through `COLUMNS`);
  - its scene-file key and what the scene-file reader accepts (assets/scenefile.py asks
    `scene_file_keys`), per light or per object where the row's key says so;
  - how it changes a Scene (apply.py `apply_view_options`, generic by its key);
  - the live viewer's settings (live/state.py: `Settings` is ViewOptions plus a camera);
  - the tests' samples (tests/test_view_options.py draws every row's `example`).
`render_command` writes options back as a `wgpu-shading render` command line.

A row's `key` says where the value lives, in a Scene and in a scene file alike:
"output.size" (a Scene field, [output] size), "shading.frequency" (a Shading field),
"camera.eye" (the camera), "objects.up" (a field of every object), "objects.material.shininess"
(a field of every object's material(s)), "lights.NAME" (a field of every light) or "lights"
(the lights themselves). `load` marks the options that act when a file is read: "mesh"
ones are keywords of the mesh reader (assets/meshes.py load_mesh), "frame" ones also shape
a bare mesh's scene (assets/view_loader.py gives both to the loader).
"""

from __future__ import annotations

from dataclasses import dataclass, field, make_dataclass
from typing import Any, Callable

from ..camera import PROJECTIONS
from ..maps import SCENE_COLOR_SPACES
from ..shadows import AUTO, MAX_SHADOW_BIAS_TEXELS, MAX_SHADOW_MAP_SIZE, MIN_SHADOW_MAP_SIZE, SHADOW_FILTERS
from ..material_table import material as named_material
from ..values import FREQUENCIES, MAX_STROKE_PIXELS, MIN_STROKE_PIXELS, REFLECTIONS
from .reading import (
    LIGHT_SYNTAX,
    read_bool,
    read_choice,
    read_color,
    read_crease_angle,
    read_direction,
    read_animation_index,
    read_float,
    read_index,
    read_lights,
    read_material,
    read_samples,
    read_seconds,
    read_shadow_bias,
    read_shadow_map_size,
    read_shininess,
    read_size,
    read_up,
    read_vector,
    spell,
)

SECTIONS = {"output": "[output]", "shading": "[shading]", "camera": "[camera]", "shadows": "[shadows]",
            "objects": "[[objects]]", "lights": "[[lights]]"}
LOAD_KINDS = (None, "mesh", "frame")


@dataclass(frozen=True)
class ViewOption:
    """One view option: its value's reader, where it lives, and its spellings.

    read:     (value, where) → the value, from flag text, a CSV cell, JSON or TOML
    key:      where it lives in a Scene and a scene file (module docstring); None: nowhere
              in a scene file (it only changes how a mesh file becomes a scene)
    example:  a value that changes the picture of a plain scene (the tests draw it)
    flags:    command-line flags taking a value (flags[0] is the one render_command writes)
    switches: flags without a value, each storing its constant: (flag, constant, help)
    aliases:  older spellings, (alias, the flag or switch it stands for): they work, but
              --help and the docs' table show one spelling per meaning and render_command
              never writes them (docs/view-options.md lists them)
    column:   the manifest column (default: the key's last word, else the name)
    to_scene: turns the option's value into the Scene's (a material name into a Material)
    load:     None, "mesh" or "frame" (module docstring)"""

    name: str
    read: Callable[[Any, str], Any]
    key: str | None
    help: str
    example: Any
    flags: tuple[str, ...] = ()
    switches: tuple[tuple[str, Any, str], ...] = ()
    aliases: tuple[tuple[str, str], ...] = ()
    metavar: str | None = None
    column: str = ""
    group: str = ""
    repeated: bool = False
    load: str | None = None
    to_scene: Callable[[Any], Any] | None = None

    def __post_init__(self) -> None:
        section = self.section
        assert section in SECTIONS or section is None, f"{self.name}: key {self.key!r} names no scene section"
        assert self.load in LOAD_KINDS, f"{self.name}: load {self.load!r}"
        current = self.flags + tuple(flag for flag, _, _ in self.switches)
        assert all(target in current for _, target in self.aliases), f"{self.name}: an alias stands for no flag of its own"
        if not self.column:
            object.__setattr__(self, "column", self.key.rpartition(".")[2] if self.key else self.name)
        if not self.group:
            object.__setattr__(self, "group", section if section in ("output", "camera", "lights") else "view")

    @property
    def section(self) -> str | None:
        """The key's first word: output, shading, camera, objects or lights."""
        return self.key.partition(".")[0] if self.key else None

    @property
    def field(self) -> str:
        """The key after its section: "size", "material.shininess"; "" for "lights"."""
        return self.key.partition(".")[2] if self.key else ""

    @property
    def scene_key(self) -> str:
        """How docs/scene-files.md writes the key: `[output] size`, `[[objects]] material.shininess`."""
        if self.key is None:
            return "(none)"
        return f"{SECTIONS[self.section]} {self.field}".rstrip()

    @property
    def all_flags(self) -> tuple[str, ...]:
        """Every spelling that works: flags, switches and aliases."""
        return self.flags + tuple(flag for flag, _, _ in self.switches) + tuple(alias for alias, _ in self.aliases)

    def switch_constant(self, flag: str) -> tuple[bool, Any]:
        """(whether `flag` is a switch, the constant it stores), aliases followed."""
        flag = dict(self.aliases).get(flag, flag)
        for switch, constant, _ in self.switches:
            if switch == flag:
                return True, constant
        return False, None


def _positive(value: Any, where: str) -> float:
    return read_float(value, where, 0.0, low_open=True)


def _pixels(value: Any, where: str) -> float:
    """A point size or line width in pixels (docs/valid-ranges.md)."""
    return read_float(value, where, MIN_STROKE_PIXELS, MAX_STROKE_PIXELS)


def _switches(true_flag: str, true_help: str, false_flag: str, false_help: str) -> tuple:
    return ((true_flag, True, true_help), (false_flag, False, false_help))


def _choices(options: tuple[str, ...]) -> str:
    return "{" + ",".join(options) + "}"


_O = ViewOption
_TRANSPARENT = "transparent background: alpha 0 where nothing is drawn (PNG, TIFF, .npy)"
_CLAMP = "flat/Gouraud: clamp each vertex's color before interpolation, as OpenGL fixed-function does"
# Table order is the order of application (docs/view-options.md).
VIEW_OPTIONS: tuple[ViewOption, ...] = (
    _O("size", read_size, "output.size", "image size, WIDTHxHEIGHT, WIDTH,HEIGHT or SIZE (default: the scene's, or 512)", (40, 32),
       flags=("--size",), aliases=(("--resolution", "--size"),), metavar="SIZE", load="frame"),
    _O("samples", read_samples, "output.samples", "antialiasing: 4 = MSAA with 4 samples per pixel (default: the scene's, 1)", 4,
       flags=("--samples",), metavar="{1,4}"),
    _O("background", read_color, "output.background", "background color, components 0..1", (0.2, 0.3, 0.4),
       flags=("--background-color",), metavar="R,G,B[,A]"),
    _O("transparent", read_bool, "output.transparent", _TRANSPARENT, True,
       switches=(("--transparent", True, _TRANSPARENT),
                 ("--no-transparent", False, "opaque background (alpha 1), whatever the scene file says")),
       aliases=(("--no-background", "--transparent"),)),
    _O("material", read_material, "objects.material", "material name for every object (see `wgpu-shading materials`)", "silver",
       flags=("--material",), metavar="NAME", to_scene=named_material),
    _O("shininess", read_shininess, "objects.material.shininess", "specular exponent of every object's material(s), 0..1e6", 3.0,
       flags=("--shininess",), metavar="N"),
    _O("frequency", read_choice(FREQUENCIES), "shading.frequency", "shading frequency (overrides the scene)", "gouraud",
       flags=("--frequency",), metavar=_choices(FREQUENCIES)),
    _O("reflection", read_choice(REFLECTIONS), "shading.reflection", "reflection model (overrides the scene)", "blinn-phong",
       flags=("--reflection",), metavar=_choices(REFLECTIONS)),
    _O("blinn_exponent_scale", read_float, "shading.blinn_exponent_scale",
       "k_blinn: Blinn-Phong exponent = shininess × K (seed: 3, OpenGL: 1)", 0.25, flags=("--blinn-exponent-scale",), metavar="K"),
    _O("local_viewer", read_bool, "shading.local_viewer",
       "the viewer: local (V towards the eye, the default) or infinite (OpenGL's default, V = (0, 0, 1))", False,
       switches=_switches("--local-viewer", "V towards the eye at every point (the default)",
                          "--infinite-viewer", "OpenGL's default viewer: V = (0, 0, 1)")),
    _O("two_sided", read_bool, "shading.two_sided", "light back faces with the flipped normal", True,
       switches=_switches("--two-sided", "light back faces with the flipped normal",
                          "--one-sided", "light back faces as front faces are lit (the default)")),
    _O("clamp_vertex_colors", read_bool, "shading.clamp_vertex_colors", _CLAMP, True,
       switches=_switches("--clamp-vertex-colors", _CLAMP,
                          "--no-clamp-vertex-colors", "interpolate the unclamped vertex colors (the default)")),
    _O("color_space", read_choice(SCENE_COLOR_SPACES), "shading.color_space",
       "colour values: auto (glTF linear with sRGB output, others display values), display or linear for every material", "linear",
       flags=("--color-space",), metavar=_choices(SCENE_COLOR_SPACES)),
    _O("point_size", _pixels, "shading.point_size",
       "points (point clouds, glTF POINTS) PX pixels across: squares, discs facing their normals when they have them (default 3)",
       6.0, flags=("--point-size",), metavar="PX"),
    _O("line_width", _pixels, "shading.line_width", "lines (OBJ l, glTF LINES) PX pixels wide (default 1)", 3.0,
       flags=("--line-width",), metavar="PX"),
    _O("edges", read_bool, "shading.edges", "draw the triangles' edges over the surfaces (f3d's --edges)", True,
       switches=_switches("--edges", "draw the triangles' edges over the surfaces (f3d's --edges)",
                          "--no-edges", "draw no edges (the default)")),
    _O("edge_color", read_color, "shading.edge_color", "the edges' colour, components 0..1 (default black)", (1.0, 0.5, 0.0),
       flags=("--edge-color",), metavar="R,G,B[,A]"),
    _O("edge_width", _pixels, "shading.edge_width", "the edges PX pixels wide (default 1)", 2.0,
       flags=("--edge-width",), metavar="PX"),
    _O("crease_angle", read_crease_angle, "objects.crease_angle",
       "mesh files without normals: edges sharper than this are creases (default 60; 180 smooth, 0 flat)", 120.0,
       flags=("--crease-angle",), metavar="DEG", load="mesh"),
    _O("up", read_up, "objects.up", "the mesh files' up axis: +Y (default), -Y, +Z, -Z, +X, -X (like f3d)", "+Z",
       flags=("--up",), metavar="AXIS", load="frame"),
    _O("animation_time", read_seconds, "objects.animation_time",
       "glTF: draw the file as its animation poses it at this time (node transforms, skins, morph weights; f3d's "
       "--animation-time; default: unanimated)", 0.5, flags=("--animation-time",), metavar="SECONDS", load="mesh"),
    _O("animation_index", read_animation_index, "objects.animation_index",
       "glTF: the animation --animation-time and `animate` play: 0 (default), 1, ... or all (every one at once); "
       "alone, the animation's start", 1,
       flags=("--animation-index",), metavar="N", load="mesh"),
    _O("camera_index", read_index, None,
       "glTF: view the file through its own camera N (perspective or orthographic, where its node puts it, like f3d's "
       "--camera-index); the --camera-* options then move it", 0, flags=("--camera-index",), metavar="N", group="camera",
       load="frame"),
    _O("camera_position", read_vector, "camera.eye", "the eye", (2.0, 1.0, 5.0), flags=("--camera-position",), metavar="X,Y,Z"),
    _O("camera_focal_point", read_vector, "camera.target", "the point looked at", (0.3, 0.2, 0.1),
       flags=("--camera-focal-point",), metavar="X,Y,Z"),
    _O("camera_direction", read_direction, "camera.direction",
       "look along DIR (-Z or X,Y,Z) at the same distance; --camera-position overrides it", (-1.0, -1.0, -1.0),
       flags=("--camera-direction",), metavar="DIR"),
    _O("camera_view_up", read_direction, "camera.up", "the camera's up vector, +Z or X,Y,Z", (1.0, 1.0, 0.0),
       flags=("--camera-view-up",), metavar="DIR", column="camera_up"),  # manifest `up` is the model's axis
    _O("camera_view_angle", read_float, "camera.fov_y", "vertical field of view", 30.0, flags=("--camera-view-angle",), metavar="DEG"),
    _O("camera_near", read_float, "camera.near", "near plane distance (default: the scene's; a bare mesh's encloses it)", 5.0,
       flags=("--camera-near",), metavar="D"),
    _O("camera_far", read_float, "camera.far", "far plane distance (default: the scene's; a bare mesh's encloses it)", 5.5,
       flags=("--camera-far",), metavar="D"),
    _O("camera_projection", read_choice(PROJECTIONS), "camera.projection",
       "perspective or orthographic; orthographic keeps the framing (height = the perspective view's at the target)", "orthographic",
       flags=("--camera-projection",), metavar="P",
       switches=(("--camera-orthographic", "orthographic",
                  "orthographic projection keeping the framing (height = the perspective view's at the target)"),)),
    _O("camera_ortho_height", read_float, "camera.ortho_height", "orthographic view height in world units (implies --camera-orthographic)",
       8.0, flags=("--camera-ortho-height",), metavar="H"),
    _O("camera_azimuth", read_float, "camera.azimuth", "turn the camera about the up vector through the target, after the options above",
       40.0, flags=("--camera-azimuth-angle",),
       aliases=(("--camera-azimuth", "--camera-azimuth-angle"),), metavar="DEG"),
    _O("camera_elevation", read_float, "camera.elevation", "raise the camera about its right axis through the target, after the azimuth",
       -30.0, flags=("--camera-elevation-angle",),
       aliases=(("--camera-elevation", "--camera-elevation-angle"),), metavar="DEG"),
    _O("camera_distance", _positive, "camera.distance", "then move the eye along its line of sight to this distance from the target",
       9.0, flags=("--camera-distance",), metavar="D"),
    _O("lights", read_lights, "lights", f"replace the lights (repeat for more): {LIGHT_SYNTAX}",
       ("directional:dir=-1,-1,-1:color=1,0.5,0.5",), flags=("--light",), metavar="SPEC", repeated=True),
    _O("shadows", read_bool, "lights.shadows", "every light casts shadows", True,
       switches=_switches("--shadows", "every light casts shadows",
                          "--no-shadows", "no light casts shadows, whatever the scene says")),
    _O("cast_shadows", read_bool, "objects.cast_shadows", "objects hide the lights that cast shadows from what is behind them", False,
       switches=_switches("--cast-shadows", "every object casts shadows (the default)",
                          "--no-cast-shadows", "no object casts shadows")),
    _O("receive_shadows", read_bool, "objects.receive_shadows", "objects are darkened where a casting light is hidden", False,
       switches=_switches("--receive-shadows", "every object receives shadows (the default)",
                          "--no-receive-shadows", "no object receives shadows")),
    _O("shadow_map_size", read_shadow_map_size, "shadows.map_size",
       f"side of each shadow map in texels, {MIN_SHADOW_MAP_SIZE}..{MAX_SHADOW_MAP_SIZE}, or auto (the accuracy study's choice)", 512,
       flags=("--shadow-map-size",), metavar="N", column="shadow_map_size"),
    _O("shadow_filter", read_choice((AUTO,) + SHADOW_FILTERS), "shadows.filter",
       "how a shadow map is read: the nearest texel, a bilinear comparison, 3×3 or 5×5 PCF, or auto", "pcf3",
       flags=("--shadow-filter",), metavar=_choices((AUTO,) + SHADOW_FILTERS), column="shadow_filter"),
    _O("shadow_bias", read_shadow_bias, "shadows.bias",
       f"how far each receiver is moved towards the light, in shadow-map texels (0..{MAX_SHADOW_BIAS_TEXELS:g}), or auto", 4.0,
       flags=("--shadow-bias",), metavar="TEXELS", column="shadow_bias"),
    _O("viewer_lights", read_bool, None,
       "a glTF file with its own lights (KHR_lights_punctual) is lit by them; true: by the viewer's key light and headlight instead", True,
       switches=_switches("--viewer-lights", "light a glTF file that has its own lights with the viewer's key light and headlight instead",
                          "--file-lights", "light a glTF file with its own KHR_lights_punctual lights when it has them (the default)"),
       group="lights", load="frame"),
)
OPTIONS_BY_NAME = {option.name: option for option in VIEW_OPTIONS}
COLUMNS = {option.column: option for option in VIEW_OPTIONS}  # manifest column → option
assert len(OPTIONS_BY_NAME) == len(COLUMNS) == len(VIEW_OPTIONS), "option names and manifest columns are unique"


def scene_file_keys(section: str, within: str = "") -> dict[str, ViewOption]:
    """The options a scene file spells in `section` ("output", "camera", "objects", ...), by
    key: scene_file_keys("objects") → material, crease_angle, up; within="material": the
    options inside an object's inline material table (shininess)."""
    keys = {}
    for option in VIEW_OPTIONS:
        *path, key = option.field.split(".")
        if option.section == section and key and path == ([within] if within else []):
            keys[key] = option
    return keys


# --------------------------------------------------------------------------- the dataclass


def _post_init(self) -> None:
    for option in VIEW_OPTIONS:
        value = getattr(self, option.name)
        if value is not None:
            object.__setattr__(self, option.name, option.read(value, option.name))


def _given(self) -> dict[str, Any]:
    """The options that are set, by name, in table order."""
    return {option.name: getattr(self, option.name) for option in VIEW_OPTIONS if getattr(self, option.name) is not None}


def _reading(self) -> dict[str, Any]:
    """The options given to the mesh reader (load="mesh": crease_angle ...), as its keywords."""
    return {option.field: getattr(self, option.name) for option in VIEW_OPTIONS
            if option.load == "mesh" and getattr(self, option.name) is not None}


def _loading(self) -> "ViewOptions":
    """Only the options that act when a file is read (`load`): what selects the scene read."""
    return type(self)(**{option.name: getattr(self, option.name) for option in VIEW_OPTIONS if option.load})


ViewOptions = make_dataclass(
    "ViewOptions",
    [(option.name, f"{type(option.example).__name__} | None", field(default=None)) for option in VIEW_OPTIONS],
    namespace={
        "__doc__": (
            "One value (or None: not given) per view option of VIEW_OPTIONS: the CLI's flags, "
            "a scene file's keys and the live view's settings, read into one record."
        ),
        "__post_init__": _post_init, "given": _given, "mesh_reading": _reading, "loading": _loading,
    },
    frozen=True,
)
ViewOptions.__module__ = __name__  # pickled by jobs and workers: found here by name
ViewOptions.__doc__ = """A value for each view option (the fields are VIEW_OPTIONS' names, in its order);
None leaves the scene's own. Values are read (and checked) by the table's readers, so Python
values, flag text and CSV text all work."""


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


if __name__ == "__main__":  # python -m wgpu_shading.scene.view.options > the table for docs/view-options.md
    print(spellings_table(), end="")
