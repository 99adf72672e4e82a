"""Arguments shared by the commands: the scene to render and the command-line overrides."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Sequence

from ..assets.image_writers import output_path
from ..assets.view_loader import load_view, source_name
from ..errors import UsageError
from .viewer_options import add_view_arguments, view_options_from_args

__all__ = ["add_view_arguments", "load_view", "view_options_from_args"]


def scene_from_args(args: argparse.Namespace):
    """The scene named on the command line, with the command-line view options applied."""
    return load_view(args.input, view_options_from_args(args))


def add_scene_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "input",
        help="a scene file (.toml), a mesh file (OBJ, PLY, STL, OFF, GLB, XYZ), builtin:NAME, or example:NAME (`wgpu-shading examples`)",
    )
    add_view_arguments(parser)


# --------------------------------------------------------------------------- commands


def default_output(args: argparse.Namespace, suffix: str) -> Path:
    """-o, or the input's name with `suffix` in the current folder (builtin:torus → torus.png)."""
    if args.output:
        return Path(args.output)
    return Path(source_name(args.input, "") + suffix)


def check_output(path: Path, allowed: Sequence[str], float_target: bool = False) -> None:
    output_path(path, allowed)
    if float_target and path.suffix.lower() != ".npy":
        raise UsageError(f"output {str(path)!r}: --float writes exact float32 values to .npy, not {path.suffix!r}")


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
