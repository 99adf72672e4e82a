"""Validation of user values: every scene dataclass normalizes its fields through these.

Each function returns the normalized value or raises SceneError with a message that
names the key (`name`) and the value, so the same text reaches the CLI and the library.
"""

from __future__ import annotations

import math
from typing import Literal, Sequence

import numpy as np

from ..errors import SceneError, shown

Color = tuple[float, float, float, float]
Vec3 = tuple[float, float, float]

Frequency = Literal["flat", "gouraud", "phong"]
Reflection = Literal["phong", "blinn-phong"]
TextureMode = Literal["modulate", "modulate_all", "blend"]

FREQUENCIES: tuple[str, ...] = ("flat", "gouraud", "phong")
REFLECTIONS: tuple[str, ...] = ("phong", "blinn-phong")
TEXTURE_MODES: tuple[str, ...] = ("modulate", "modulate_all", "blend")

# Limits (docs/valid-ranges.md). Every value derived from these for the GPU (matrices, normal
# matrices, eye-space positions, squared distances, lit colours summed over MAX_LIGHTS)
# stays finite in float32 (max 3.4e38).
MAX_COORDINATE = 1e15
MAX_EXPONENT = 1e6
MAX_IMAGE_SIDE = 16384
MAX_COLOR = 1e6  # light and material colour components (HDR intensities allowed, not 1e39)
MIN_DIRECTION_LENGTH = 1e-30  # shorter vectors have no direction worth the name
MIN_SCALE, MAX_SCALE = 1e-12, 1e12  # |object.scale| components
MAX_LIGHTS = 256  # all kinds together: the frame uniforms must fit WebGPU's 64 KiB
# Objects of one scene: each is a draw with its own uniform block (and a mesh to load);
# 2,000 cubes take ~3 s to render on lavapipe, 100,000 took minutes with no end in sight.
MAX_OBJECTS = 4096
# Points, lines and edges are drawn this many pixels across at most (docs/primitives.md):
# OpenGL implementations cap point sizes at 64..256; from 1, every one covers a pixel.
MIN_STROKE_PIXELS, MAX_STROKE_PIXELS = 1.0, 256.0


# --------------------------------------------------------------------------- validation


def finite_numbers(value: object, name: str, lengths: Sequence[int]) -> tuple[float, ...]:
    """A tuple of finite floats of one of the allowed lengths, or a SceneError naming `name`."""
    if type(value) is tuple and len(value) in lengths and all(type(item) is float for item in value) and math.isfinite(sum(value)):
        # Already normalized (a scene derived from another: every view of a dataset). A
        # finite sum proves every item finite; an overflowing one takes the checks below.
        return value
    expected = " or ".join(str(n) for n in lengths)
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__"):
        raise SceneError(f"{name}: expected a list of {expected} numbers, got {shown(value)}")
    items = list(value)  # type: ignore[arg-type]
    if len(items) not in lengths:
        raise SceneError(f"{name}: expected {expected} numbers, got {len(items)}: {shown(value)}")
    numbers = []
    for item in items:
        if isinstance(item, bool) or not isinstance(item, (int, float, np.integer, np.floating)):
            raise SceneError(f"{name}: expected numbers, got {shown(item)} in {shown(value)}")
        try:
            number = float(item)
        except OverflowError:  # an integer beyond float64
            number = math.inf
        if not math.isfinite(number):
            raise SceneError(f"{name}: expected finite numbers, got {shown(item)} in {shown(value)}")
        numbers.append(number)
    return tuple(numbers)


def color(value: object, name: str = "color") -> Color:
    """RGBA from RGB or RGBA; components >= 0, alpha <= 1."""
    numbers = finite_numbers(value, name, (3, 4))
    if len(numbers) == 3:
        numbers = numbers + (1.0,)
    if min(numbers) < 0.0:
        raise SceneError(f"{name}: color components must be >= 0, got {list(numbers)}")
    if max(numbers[:3]) > MAX_COLOR:
        raise SceneError(f"{name}: color components must be at most {MAX_COLOR:g}, got {list(numbers)}")
    if numbers[3] > 1.0:
        raise SceneError(f"{name}: alpha must be between 0 and 1, got {numbers[3]}")
    return numbers  # type: ignore[return-value]


def vec3(value: object, name: str) -> Vec3:
    numbers = finite_numbers(value, name, (3,))
    if max(abs(n) for n in numbers) > MAX_COORDINATE:
        raise SceneError(f"{name}: coordinates must be within ±{MAX_COORDINATE:g}, got {list(numbers)}")
    return numbers  # type: ignore[return-value]


def direction(value: object, name: str) -> Vec3:
    numbers = vec3(value, name)
    if math.hypot(*numbers) == 0.0:
        raise SceneError(f"{name}: a direction must not be the zero vector")
    if math.hypot(*numbers) < MIN_DIRECTION_LENGTH:
        raise SceneError(f"{name}: a direction must be at least {MIN_DIRECTION_LENGTH:g} long, got {list(numbers)}")
    return numbers


def number(value: object, name: str, low: float, high: float, *, low_open: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise SceneError(f"{name}: expected a number, got {shown(value)}")
    try:
        result = float(value)
    except OverflowError:
        result = math.inf
    too_low = result <= low if low_open else result < low
    if not math.isfinite(result) or too_low or result > high:
        bracket = "(" if low_open else "["
        raise SceneError(f"{name}: expected a number in {bracket}{low:g}, {high:g}], got {shown(value)}")
    return result


def boolean(value: object, name: str) -> bool:
    """true or false, nothing else (not 0/1, not "yes"): a typo must not pass as truthy."""
    if not isinstance(value, (bool, np.bool_)):
        raise SceneError(f"{name}: expected true or false, got {shown(value)}")
    return bool(value)


def choice(value: object, name: str, options: Sequence[str]) -> str:
    if not isinstance(value, str) or value not in options:
        raise SceneError(f"{name}: expected one of {', '.join(map(repr, options))}, got {shown(value)}")
    return str(value)


def set_fields(instance: object, **values: object) -> None:
    """Assign normalized values on a frozen dataclass during __post_init__."""
    for key, value in values.items():
        object.__setattr__(instance, key, value)



def image_size(value: object, name: str = "output.size") -> tuple[int, int]:
    numbers = finite_numbers(value, name, (2,))
    if any(n != int(n) for n in numbers):
        raise SceneError(f"{name}: expected whole numbers of pixels, got {list(numbers)}")
    width, height = int(numbers[0]), int(numbers[1])
    if not (1 <= width <= MAX_IMAGE_SIDE and 1 <= height <= MAX_IMAGE_SIDE):
        raise SceneError(f"{name}: width and height must be between 1 and {MAX_IMAGE_SIDE}, got {width}×{height}")
    return width, height


