"""Validation of user values: every scene dataclass normalizes its fields through these.

Each function returns the normalized value or raises SceneError with a message that
names the key (`name`) and the value, so the same text reaches the CLI and the library.
"""

from __future__ import annotations

import math
from typing import Literal, Sequence

import numpy as np

from ..errors import SceneError

Color = tuple[float, float, float, float]
Vec3 = tuple[float, float, float]

Frequency = Literal["flat", "gouraud", "phong"]
Reflection = Literal["phong", "blinn-phong"]
TextureMode = Literal["modulate", "modulate_all", "blend"]

FREQUENCIES: tuple[str, ...] = ("flat", "gouraud", "phong")
REFLECTIONS: tuple[str, ...] = ("phong", "blinn-phong")
TEXTURE_MODES: tuple[str, ...] = ("modulate", "modulate_all", "blend")

MAX_COORDINATE = 1e15
MAX_EXPONENT = 1e6
MAX_IMAGE_SIDE = 16384


# --------------------------------------------------------------------------- validation


def _numbers(value: object, name: str, lengths: Sequence[int]) -> tuple[float, ...]:
    """A tuple of finite floats of one of the allowed lengths, or a SceneError naming `name`."""
    expected = " or ".join(str(n) for n in lengths)
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
        raise SceneError(f"{name}: expected a list of {expected} numbers, got {value!r}")
    items = list(value)  # type: ignore[arg-type]
    if len(items) not in lengths:
        raise SceneError(f"{name}: expected {expected} numbers, got {len(items)}: {value!r}")
    numbers = []
    for item in items:
        if isinstance(item, bool) or not isinstance(item, (int, float, np.integer, np.floating)):
            raise SceneError(f"{name}: expected numbers, got {item!r} in {value!r}")
        number = float(item)
        if not math.isfinite(number):
            raise SceneError(f"{name}: expected finite numbers, got {number} in {value!r}")
        numbers.append(number)
    return tuple(numbers)


def color(value: object, name: str = "color") -> Color:
    """RGBA from RGB or RGBA; components >= 0, alpha <= 1."""
    numbers = _numbers(value, name, (3, 4))
    if len(numbers) == 3:
        numbers = numbers + (1.0,)
    if min(numbers) < 0.0:
        raise SceneError(f"{name}: color components must be >= 0, got {list(numbers)}")
    if numbers[3] > 1.0:
        raise SceneError(f"{name}: alpha must be between 0 and 1, got {numbers[3]}")
    return numbers  # type: ignore[return-value]


def vec3(value: object, name: str) -> Vec3:
    numbers = _numbers(value, name, (3,))
    if max(abs(n) for n in numbers) > MAX_COORDINATE:
        raise SceneError(f"{name}: coordinates must be within ±{MAX_COORDINATE:g}, got {list(numbers)}")
    return numbers  # type: ignore[return-value]


def direction(value: object, name: str) -> Vec3:
    numbers = vec3(value, name)
    if math.hypot(*numbers) == 0.0:
        raise SceneError(f"{name}: a direction must not be the zero vector")
    return numbers


def number(value: object, name: str, low: float, high: float, *, low_open: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise SceneError(f"{name}: expected a number, got {value!r}")
    result = float(value)
    too_low = result <= low if low_open else result < low
    if not math.isfinite(result) or too_low or result > high:
        bracket = "(" if low_open else "["
        raise SceneError(f"{name}: expected a number in {bracket}{low:g}, {high:g}], got {value!r}")
    return result


def choice(value: object, name: str, options: Sequence[str]) -> str:
    if value not in options:
        raise SceneError(f"{name}: expected one of {', '.join(map(repr, options))}, got {value!r}")
    return str(value)


def _set(instance: object, **values: object) -> None:
    """Assign normalized values on a frozen dataclass during __post_init__."""
    for key, value in values.items():
        object.__setattr__(instance, key, value)



def image_size(value: object, name: str = "output.size") -> tuple[int, int]:
    numbers = _numbers(value, name, (2,))
    if any(n != int(n) for n in numbers):
        raise SceneError(f"{name}: expected whole numbers of pixels, got {list(numbers)}")
    width, height = int(numbers[0]), int(numbers[1])
    if not (1 <= width <= MAX_IMAGE_SIDE and 1 <= height <= MAX_IMAGE_SIDE):
        raise SceneError(f"{name}: width and height must be between 1 and {MAX_IMAGE_SIDE}, got {width}×{height}")
    return width, height


