"""What a model viewer's user expects to set from the command line: camera (f3d's flag
names), lights, background. Each flag maps onto a scene-file key (docs/scene-files.md):

    (--up, the files' up axis, is in arguments.py: it turns the mesh, as f3d's view)
    --camera-position X,Y,Z        [camera] eye
    --camera-focal-point X,Y,Z     [camera] target
    --camera-direction DIR         the view direction; eye = target − DIR·(current distance)
                                   (ignored when --camera-position is given, as in f3d)
    --camera-view-up X,Y,Z         [camera] up (orthogonalised against the view direction)
    --camera-view-angle DEG        [camera] fov_y (vertical)
    --camera-azimuth-angle DEG     [camera] azimuth   } turn the camera about the target,
    --camera-elevation-angle DEG   [camera] elevation } after everything else (as f3d)
    --camera-orthographic          [camera] projection = "orthographic"
    --camera-ortho-height H        [camera] ortho_height (implies orthographic)
    --light SPEC (repeatable)      [[lights]]: replaces the scene's or the default lights
    --samples 1|4                  [output] samples (MSAA antialiasing)
    --background-color R,G,B[,A]   [output] background
    --no-background                [output] transparent = true (background alpha 0)
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

from ..errors import SceneError
from ..scene import LIGHT_TYPES, Scene
from ..scene.framing import object_depth_range, parse_direction
from ..scene.viewer_lights import headlight, viewer_lights

LIGHT_SYNTAX = (
    "TYPE[:KEY=VALUE]...: TYPE directional|positional|spot|headlight; keys dir=X,Y,Z (the way the light "
    "travels), pos=X,Y,Z, color=R,G,B (diffuse and specular), diffuse=, specular=, ambient=, "
    "attenuation=C,L,Q, cutoff=DEG, exponent=E; e.g. directional:dir=-1,-1,-1:color=1,1,1"
)
_LIGHT_KEYS = {"dir": "direction", "direction": "direction", "pos": "position", "position": "position",
               "diffuse": "diffuse", "specular": "specular", "ambient": "ambient", "attenuation": "attenuation",
               "cutoff": "cutoff", "exponent": "exponent"}


def _vector(text: str) -> tuple[float, ...]:
    try:
        values = tuple(float(part) for part in text.replace(" ", "").split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas (X,Y,Z), got {text!r}") from None
    if len(values) != 3:
        raise argparse.ArgumentTypeError(f"expected 3 numbers X,Y,Z, got {text!r}")
    return values


def _color(text: str) -> tuple[float, ...]:
    try:
        values = tuple(float(part) for part in text.replace(" ", "").split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected R,G,B or R,G,B,A (0..1), got {text!r}") from None
    if len(values) not in (3, 4):
        raise argparse.ArgumentTypeError(f"expected R,G,B or R,G,B,A (0..1), got {text!r}")
    return values


def _axis(text: str) -> str:
    try:
        parse_direction(text, "direction")
    except SceneError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    return text


def parse_light(text: str, camera) -> object:
    """One --light SPEC as a light (`headlight` is placed relative to `camera`)."""
    kind, *pairs = text.split(":")
    kind = kind.strip().lower()
    if kind not in (*LIGHT_TYPES, "headlight"):
        raise SceneError(f"--light {text!r}: unknown type {kind!r}; expected {LIGHT_SYNTAX}")
    fields: dict = {}
    given: set[str] = set()
    for pair in pairs:
        key, equals, value = pair.partition("=")
        key = key.strip().lower()
        if not equals or (key not in _LIGHT_KEYS and key != "color"):
            raise SceneError(f"--light {text!r}: cannot read {pair!r}; expected {LIGHT_SYNTAX}")
        canonical = _LIGHT_KEYS.get(key, key)
        if canonical in given:  # the last one silently won before
            raise SceneError(f"--light {text!r}: {key} is given twice")
        given.add(canonical)
        try:
            numbers = [float(v) for v in value.split(",")]
        except ValueError:
            raise SceneError(f"--light {text!r}: {key} expects numbers, got {value!r}") from None
        value_out = numbers[0] if key in ("cutoff", "exponent") and len(numbers) == 1 else tuple(numbers)
        if key == "color":
            fields["diffuse"] = fields["specular"] = value_out
        else:
            fields[_LIGHT_KEYS[key]] = value_out
    try:
        if kind == "headlight":
            extra = set(fields) - {"diffuse", "specular"}
            if extra:
                raise SceneError(f"a headlight follows the camera; it takes only color, diffuse and specular, not {sorted(extra)}")
            light = headlight(camera)
            return replace(light, **fields) if fields else light
        return LIGHT_TYPES[kind](**fields)
    except (SceneError, TypeError) as error:
        message = str(error)
        if isinstance(error, TypeError):  # a key the light type does not have (pos for directional)
            message = f"a {kind} light does not take {message.split('argument ')[-1]}"
        raise SceneError(f"--light {text!r}: {message}") from None


def add_viewer_arguments(parser: argparse.ArgumentParser) -> None:
    camera = parser.add_argument_group("camera (f3d's names; applied to scene files and bare meshes)")
    camera.add_argument("--camera-position", type=_vector, metavar="X,Y,Z", help="the eye ([camera] eye)")
    camera.add_argument("--camera-focal-point", type=_vector, metavar="X,Y,Z", help="the point looked at ([camera] target)")
    camera.add_argument("--camera-direction", type=_axis, metavar="DIR",
                        help="look along DIR (-Z or X,Y,Z) at the same distance; --camera-position overrides it")
    camera.add_argument("--camera-view-up", type=_axis, metavar="DIR", help="the up vector, +Z or X,Y,Z ([camera] up)")
    camera.add_argument("--camera-view-angle", type=float, metavar="DEG", help="vertical field of view ([camera] fov_y)")
    camera.add_argument("--camera-azimuth-angle", "--camera-azimuth", type=float, metavar="DEG", default=0.0, dest="camera_azimuth_angle",
                        help="turn the camera about the up vector through the target, after the other options")
    camera.add_argument("--camera-elevation-angle", "--camera-elevation", type=float, metavar="DEG", default=0.0, dest="camera_elevation_angle",
                        help="raise the camera about its right axis through the target, after the azimuth")
    camera.add_argument("--camera-orthographic", action="store_true",
                        help="orthographic projection keeping the framing (height = the perspective view's at the target)")
    camera.add_argument("--camera-ortho-height", type=float, metavar="H",
                        help="orthographic view height in world units ([camera] ortho_height; implies --camera-orthographic)")
    output = parser.add_argument_group("output")
    output.add_argument("--samples", type=int, choices=(1, 4), help="antialiasing: 4 = MSAA with 4 samples per pixel (default: the scene's, 1)")
    output.add_argument("--background-color", type=_color, metavar="R,G,B[,A]", help="background color, components 0..1 ([output] background)")
    output.add_argument("--no-background", action="store_true", help="transparent background: alpha 0 where nothing is drawn (PNG, TIFF, .npy)")
    lights = parser.add_argument_group("lights")
    lights.add_argument("--light", action="append", metavar="SPEC",
                        help=f"replace the lights (repeat for more): {LIGHT_SYNTAX}")


def apply_viewer_options(scene: Scene, args: argparse.Namespace, bare_mesh: bool) -> Scene:
    """The scene with the camera and light flags applied. A bare mesh's depth range and
    default lights follow its camera wherever the flags moved it."""
    camera = scene.camera
    changes: dict = {}
    for flag, key in (("camera_position", "eye"), ("camera_focal_point", "target"), ("camera_view_angle", "fov_y")):
        if getattr(args, flag, None) is not None:
            changes[key] = getattr(args, flag)
    if getattr(args, "camera_direction", None) is not None and "eye" not in changes:
        view = np.asarray(parse_direction(args.camera_direction, "--camera-direction"), dtype=np.float64)
        target = np.asarray(changes.get("target", camera.target), dtype=np.float64)
        distance = float(np.linalg.norm(np.subtract(camera.eye, camera.target)))
        changes["eye"] = tuple(float(v) for v in target - view / np.linalg.norm(view) * distance)
    if getattr(args, "camera_view_up", None) is not None:
        changes["up"] = parse_direction(args.camera_view_up, "--camera-view-up")
    if getattr(args, "camera_orthographic", False):
        changes["projection"] = "orthographic"
    if getattr(args, "camera_ortho_height", None) is not None:
        changes.update(projection="orthographic", ortho_height=args.camera_ortho_height)
    try:
        camera = replace(camera, **changes) if changes else camera
        camera = camera.orbited(getattr(args, "camera_azimuth_angle", 0.0), getattr(args, "camera_elevation_angle", 0.0))
    except SceneError as error:
        raise SceneError(f"camera options: {error}") from None
    if bare_mesh and camera is not scene.camera:
        near, far = object_depth_range(camera.eye, scene.objects[0])
        camera = replace(camera, near=near, far=far)
    lights = scene.lights
    if getattr(args, "light", None):
        lights = tuple(parse_light(spec, camera) for spec in args.light)
    elif bare_mesh and camera is not scene.camera:
        lights = viewer_lights(camera)
    output: dict = {}
    if getattr(args, "samples", None) is not None:
        output["samples"] = args.samples
    background = scene.background
    if getattr(args, "background_color", None) is not None:
        background = args.background_color if len(args.background_color) == 4 else (*args.background_color, background[3])
    if getattr(args, "no_background", False):
        background = (*background[:3], 0.0)
    if background != scene.background:
        output["background"] = background
    if camera is scene.camera and lights is scene.lights and not output:
        return scene
    try:
        return replace(scene, camera=camera, lights=lights, **output)
    except SceneError as error:
        raise SceneError(f"command-line options: {error}") from None
