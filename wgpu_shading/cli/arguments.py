"""Arguments shared by the commands: the scene to render and the command-line overrides."""

from __future__ import annotations

import argparse
import math
from dataclasses import replace
from pathlib import Path
from typing import Sequence

from ..assets.images import output_path
from ..errors import SceneError
from ..scene.maps import SCENE_COLOR_SPACES
from ..scene import FREQUENCIES, REFLECTIONS, image_size
from .viewer_options import add_viewer_arguments, apply_viewer_options


def _size(text: str) -> tuple[int, int]:
    """'512', '640x480' or f3d's '640,480'."""
    parts = text.lower().replace("×", "x").replace(",", "x").split("x")
    try:
        numbers = [int(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT or SIZE, got {text!r}") from None
    if len(numbers) == 1:
        numbers *= 2
    if len(numbers) != 2:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT or SIZE, got {text!r}")
    return numbers[0], numbers[1]


def scene_from_args(args: argparse.Namespace):
    """The scene named on the command line, with the command-line overrides applied."""
    from ..assets.mesh_scene import mesh_scene
    from ..assets.meshes import DEFAULT_CREASE_ANGLE
    from ..assets.scenefile import load_scene
    from ..scene import material

    source: str = args.input
    if args.size is not None:
        args.size = image_size(args.size, "--size")  # before anything divides by it
    if source.lower().endswith(".toml"):
        scene = load_scene(source, crease_angle=args.crease_angle)
        if args.up:
            scene = replace(scene, objects=tuple(replace(o, up=args.up) for o in scene.objects))
        if args.size:
            scene = replace(scene, size=args.size)
        if args.material:
            chosen = material(args.material)
            scene = replace(scene, objects=tuple(replace(o, material=chosen) for o in scene.objects))
    else:
        scene = mesh_scene(
            source,
            args.size or (512, 512),
            args.material,
            crease_angle=DEFAULT_CREASE_ANGLE if args.crease_angle is None else args.crease_angle,
            up=args.up or "+Y",
        )
    scene = apply_viewer_options(scene, args, bare_mesh=not source.lower().endswith(".toml"))
    shading = scene.shading
    overrides = {
        key: value
        for key, value in (
            ("frequency", args.frequency),
            ("reflection", args.reflection),
            ("blinn_exponent_scale", args.blinn_exponent_scale),
        )
        if value is not None
    }
    if args.infinite_viewer:
        overrides["local_viewer"] = False
    if args.two_sided:
        overrides["two_sided"] = True
    if getattr(args, "clamp_vertex_colors", False):
        overrides["clamp_vertex_colors"] = True
    if getattr(args, "color_space", None):
        overrides["color_space"] = args.color_space
    if overrides:
        scene = replace(scene, shading=replace(shading, **overrides))
    return scene


def add_scene_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "input",
        help="a scene file (.toml), a mesh file (OBJ, PLY, STL, OFF, GLB), builtin:NAME, or example:NAME (`wgpu-shading examples`)",
    )
    parser.add_argument(
        "--size", "--resolution", type=_size, dest="size",
        help="image size, WIDTHxHEIGHT, WIDTH,HEIGHT or SIZE (default: the scene's, or 512)",
    )
    parser.add_argument("--frequency", choices=FREQUENCIES, help="shading frequency (overrides the scene)")
    parser.add_argument("--reflection", choices=REFLECTIONS, help="reflection model (overrides the scene)")
    parser.add_argument(
        "--blinn-exponent-scale", type=float, metavar="K", help="Blinn-Phong exponent = shininess × K (seed: 3, OpenGL: 1)"
    )
    parser.add_argument("--material", help="material name for every object (see `wgpu-shading materials`)")
    parser.add_argument("--infinite-viewer", action="store_true", help="OpenGL's default viewer: V = (0, 0, 1)")
    parser.add_argument("--two-sided", action="store_true", help="light back faces with the flipped normal")
    parser.add_argument(
        "--crease-angle", type=_degrees, metavar="DEG",
        help="mesh files without normals: edges sharper than this are creases (default 60; 180 smooth, 0 flat)",
    )
    parser.add_argument(
        "--up", type=_up, metavar="AXIS", help="the mesh files' up axis: +Y (default), -Y, +Z, -Z, +X, -X (like f3d)"
    )
    parser.add_argument(
        "--clamp-vertex-colors", action="store_true",
        help="flat/Gouraud: clamp each vertex's color before interpolation, as OpenGL fixed-function does",
    )
    parser.add_argument(
        "--color-space", choices=SCENE_COLOR_SPACES,
        help="auto (default): glTF colours linear with sRGB output, others as display values (OpenGL); "
        "display or linear for every material (docs/conventions.md)",
    )
    add_viewer_arguments(parser)


# --------------------------------------------------------------------------- commands


def default_output(args: argparse.Namespace, suffix: str) -> Path:
    """-o, or the input's name with `suffix` in the current folder (builtin:torus → torus.png)."""
    if args.output:
        return Path(args.output)
    return Path(Path(args.input.split("?")[0].replace("builtin:", "").replace("example:", "")).stem + suffix)


def check_output(path: Path, allowed: Sequence[str], float_target: bool = False) -> None:
    output_path(path, allowed)
    if float_target and path.suffix.lower() != ".npy":
        raise SceneError(f"output {str(path)!r}: --float writes exact float32 values to .npy, not {path.suffix!r}")


def _number_in(text: str, convert, low: float, high: float, expected: str, out_of_range: str | None = None):
    """`convert(text)` if it lies in [low, high]; otherwise the argparse error saying what
    was expected (`out_of_range`, when given, for a number outside the range)."""
    try:
        value = convert(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}") from None
    if not low <= value <= high:
        raise argparse.ArgumentTypeError(f"expected {out_of_range or expected}, got {text!r}")
    return value


def _degrees(text: str) -> float:
    """A crease angle, 0..180 degrees."""
    return _number_in(text, float, 0.0, 180.0, "degrees between 0 and 180")


def _up(text: str) -> str:
    from ..scene.objects import up_axis

    try:
        return up_axis(text, "--up")
    except SceneError as error:
        raise argparse.ArgumentTypeError(str(error).removeprefix("--up: ")) from None


def fraction(text: str) -> float:
    """'0.001' or '0.1%'."""
    def convert(value: str) -> float:
        return float(value[:-1]) / 100.0 if value.endswith("%") else float(value)

    return _number_in(
        text, convert, 0.0, 1.0, "a fraction such as 0.001 or 0.1%", "a fraction between 0 and 1 (or 0%..100%)"
    )


def level_255(text: str) -> int:
    """An integer 0..255."""
    return _number_in(text, int, 0, 255, "an integer 0..255 (units of 1/255)")


def error_budget(text: str) -> float:
    """A number >= 0 in units of 1/255 ('1', '0.5', '2/255')."""
    number = text[:-4] if text.endswith("/255") else text
    try:
        value = float(number)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an error in units of 1/255 such as 1 or 0.5, got {text!r}") from None
    if not (math.isfinite(value) and value >= 0):
        raise argparse.ArgumentTypeError(f"expected an error >= 0 (units of 1/255), got {text!r}")
    return value
