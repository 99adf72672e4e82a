"""Reading one view option's value, whether it comes as command-line text, a CSV cell, a
JSON value or a TOML value, and writing it back as command-line text that reads back to
the same value (floats through repr, so they round-trip exactly).

Every reader takes (value, where) and raises UsageError naming `where` (the flag, the
manifest line and column, ...) and what was expected. The options themselves are listed
in options.py.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

from ...errors import SceneError, UsageError
from ..lights import LIGHT_TYPES
from ..material_table import material as named_material
from ..objects import SAMPLE_COUNTS, up_axis
from ..shadows import AUTO, MAX_SHADOW_BIAS_TEXELS, shadow_map_size
from ..values import MAX_EXPONENT, Vec3, direction, image_size
from .bare_mesh import headlight

TRUE_WORDS = ("1", "true", "yes", "on")
FALSE_WORDS = ("0", "false", "no", "off")


def _numbers(value: Any, where: str, counts: tuple[int, ...], expected: str) -> tuple[float, ...]:
    """'1,2,3', '1 2 3' (a CSV cell) or a list of numbers → floats."""
    items = value.replace(",", " ").split() if isinstance(value, str) else value
    try:
        if isinstance(items, (bool, int, float)) or any(isinstance(item, bool) for item in items):
            raise TypeError
        numbers = tuple(float(item) for item in items)
    except (TypeError, ValueError):
        raise UsageError(f"{where}: expected {expected}, got {value!r}") from None
    if len(numbers) not in counts or not all(math.isfinite(n) for n in numbers):
        raise UsageError(f"{where}: expected {expected}, got {value!r}")
    return numbers


_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}


def parse_direction(value: str | Vec3, name: str = "direction") -> Vec3:
    """A direction as f3d spells it: an axis '+Y', '-Z', 'X', or a vector 'X,Y,Z' / (x, y, z)
    (not normalized; zero is an error). `name` is the flag or key for the message."""
    if isinstance(value, str):
        text = value.strip().upper()
        sign = -1.0 if text.startswith("-") else 1.0
        axis = text.lstrip("+-")
        if axis in _AXES and len(text) - len(axis) <= 1:
            return tuple(sign * c for c in _AXES[axis])
        try:
            value = tuple(float(part) for part in text.split(","))
        except ValueError:
            raise SceneError(f"{name}: expected +X, -X, +Y, -Y, +Z, -Z or a direction X,Y,Z, got {value!r}") from None
    return direction(value, name)


def read_size(value: Any, where: str) -> tuple[int, int]:
    """'512', '640x480', f3d's '640,480', 512 or [640, 480]."""
    if isinstance(value, str):
        parts = value.lower().replace("×", "x").replace(",", "x").split("x")
        try:
            numbers = [int(p) for p in parts]
        except ValueError:
            raise UsageError(f"{where}: expected WIDTHxHEIGHT or SIZE, got {value!r}") from None
        value = numbers * 2 if len(numbers) == 1 else numbers
        if len(value) != 2:
            raise UsageError(f"{where}: expected WIDTHxHEIGHT or SIZE, got {value!r}")
    elif isinstance(value, int) and not isinstance(value, bool):
        value = (value, value)
    try:
        return image_size(value, where)
    except SceneError as error:
        raise UsageError(str(error)) from None


def read_bool(value: Any, where: str) -> bool:
    if isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    if text in TRUE_WORDS:
        return True
    if text in FALSE_WORDS:
        return False
    raise UsageError(f"{where}: expected true or false, got {value!r}")


def read_float(value: Any, where: str, low: float = -math.inf, high: float = math.inf, *, low_open: bool = False) -> float:
    try:
        if isinstance(value, bool):  # JSON true is not 1 degree
            raise TypeError
        number = float(value)
    except (TypeError, ValueError):
        raise UsageError(f"{where}: expected a number, got {value!r}") from None
    too_low = number <= low if low_open else number < low
    if not math.isfinite(number) or too_low or number > high:
        bounds = f" {'above' if low_open else 'from'} {low:g}" if low > -math.inf else ""
        bounds += f" up to {high:g}" if high < math.inf else ""
        raise UsageError(f"{where}: expected a finite number{bounds}, got {value!r}")
    return number


def read_samples(value: Any, where: str) -> int:
    try:
        if isinstance(value, bool):
            raise ValueError
        count = int(value)
    except (TypeError, ValueError):
        count = None
    if count not in SAMPLE_COUNTS:
        raise UsageError(f"{where}: expected one of {', '.join(map(str, SAMPLE_COUNTS))}, got {value!r}")
    return count


MAX_FILE_INDEX = 1 << 20  # a file's N-th camera or animation: glTF lists hold at most this many (gltf/document.py)
MAX_SECONDS = 1e9  # an animation time: beyond any keyframe a file can hold, still exact in float64 steps of 1/fps
ALL = "all"


def read_index(value: Any, where: str) -> int:
    """A position in one of a file's lists, from 0: 2, "2" or 2.0."""
    try:
        if isinstance(value, bool):
            raise ValueError
        number = float(value)
        if not number.is_integer():
            raise ValueError
        index = int(number)
    except (TypeError, ValueError, OverflowError):
        raise UsageError(f"{where}: expected an index 0, 1, 2, ..., got {value!r}") from None
    if not 0 <= index <= MAX_FILE_INDEX:
        raise UsageError(f"{where}: expected an index from 0 to {MAX_FILE_INDEX}, got {value!r}")
    return index


def read_animation_index(value: Any, where: str) -> int | str:
    """An animation of the file, 0, 1, ..., or "all" of them at once (f3d 2's -1)."""
    if isinstance(value, str) and value.strip().lower() == ALL:
        return ALL
    try:
        return read_index(value, where)
    except UsageError:
        raise UsageError(f"{where}: expected an animation index 0, 1, 2, ... or all, got {value!r}") from None


def read_seconds(value: Any, where: str) -> float:
    return read_float(value, where, -MAX_SECONDS, MAX_SECONDS)


def read_color(value: Any, where: str) -> tuple[float, ...]:
    numbers = _numbers(value, where, (3, 4), "R,G,B or R,G,B,A (0..1)")
    if not all(0.0 <= n <= 1.0 for n in numbers):
        raise UsageError(f"{where}: expected components between 0 and 1, got {value!r}")
    return numbers


def read_vector(value: Any, where: str) -> tuple[float, float, float]:
    return _numbers(value, where, (3,), "3 numbers X,Y,Z")  # type: ignore[return-value]


def read_direction(value: Any, where: str) -> tuple[float, float, float]:
    """f3d's spelling: an axis (+Z, -x) or a vector X,Y,Z (a CSV cell may use blanks)."""
    if isinstance(value, str) and "," not in value and len(value.split()) == 3:
        value = ",".join(value.split())
    try:
        return parse_direction(value if isinstance(value, str) else read_vector(value, where), where)
    except SceneError as error:
        raise UsageError(str(error)) from None


def read_choice(options: tuple[str, ...]):
    def read(value: Any, where: str) -> str:
        if not isinstance(value, str) or value not in options:
            raise UsageError(f"{where}: expected one of {', '.join(options)}, got {value!r}")
        return value

    return read


def read_material(value: Any, where: str) -> str:
    if not isinstance(value, str):
        raise UsageError(f"{where}: expected a material name, got {value!r}")
    try:
        named_material(value)
    except SceneError as error:
        raise UsageError(f"{where}: {error}") from None
    return value


def read_up(value: Any, where: str) -> str:
    try:
        return up_axis(value, where)
    except SceneError as error:
        raise UsageError(str(error)) from None


def read_shininess(value: Any, where: str) -> float:
    return read_float(value, where, 0.0, MAX_EXPONENT)


def read_crease_angle(value: Any, where: str) -> float:
    try:
        return read_float(value, where, 0.0, 180.0)
    except UsageError:
        raise UsageError(f"{where}: expected degrees between 0 and 180, got {value!r}") from None


def read_shadow_map_size(value: Any, where: str) -> int | str:
    """"auto" or a whole number of texels (scene/shadows.py's range)."""
    if isinstance(value, str) and value.strip().lower() != AUTO:
        try:
            value = int(value)
        except ValueError:
            raise UsageError(f"{where}: expected auto or a whole number of texels, got {value!r}") from None
    try:
        return shadow_map_size(value.strip().lower() if isinstance(value, str) else value, where)
    except SceneError as error:
        raise UsageError(str(error)) from None


def read_shadow_bias(value: Any, where: str) -> float | str:
    """"auto" or texels of the shadow map (scene/shadows.py's range)."""
    if isinstance(value, str) and value.strip().lower() == AUTO:
        return AUTO
    return read_float(value, where, 0.0, MAX_SHADOW_BIAS_TEXELS)


def read_lights(value: Any, where: str) -> tuple[str, ...]:
    """Light SPECs (LIGHT_SYNTAX): a list, or one string with SPECs separated by ';'. Each
    is checked now (a headlight against a stand-in camera) so that a typo fails early."""
    specs = [part.strip() for part in value.split(";")] if isinstance(value, str) else value
    if not isinstance(specs, (list, tuple)) or not all(isinstance(spec, str) for spec in specs):
        raise UsageError(f"{where}: expected light SPECs ({LIGHT_SYNTAX}), got {value!r}")
    from ..camera import Camera

    for spec in specs:
        try:
            parse_light(spec, Camera())
        except SceneError as error:
            message = str(error)  # names the flag already when it came from --light
            raise UsageError(message if message.startswith(where) else f"{where}: {message}") from None
    return tuple(specs)


# --------------------------------------------------------------------------- lights

LIGHT_SYNTAX = (
    "TYPE[:KEY=VALUE]...: TYPE directional|positional|spot|headlight; keys dir=X,Y,Z (the way the light "
    "travels), pos=X,Y,Z, color=R,G,B (diffuse and specular), diffuse=, specular=, ambient=, "
    "attenuation=C,L,Q, cutoff=DEG, exponent=E; e.g. directional:dir=-1,-1,-1:color=1,1,1"
)
_LIGHT_KEYS = {"dir": "direction", "direction": "direction", "pos": "position", "position": "position",
               "diffuse": "diffuse", "specular": "specular", "ambient": "ambient", "attenuation": "attenuation",
               "cutoff": "cutoff", "exponent": "exponent"}


def parse_light(text: str, camera) -> object:
    """One light SPEC as a light (`headlight` is placed relative to `camera`)."""
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


# --------------------------------------------------------------------------- writing back


def spell(value: Any) -> str:
    """Command-line text that the readers above read back to exactly `value`."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, tuple) and len(value) == 2 and all(isinstance(v, int) for v in value):
        return f"{value[0]}x{value[1]}"  # a size
    if isinstance(value, tuple):
        return ",".join(repr(float(v)) for v in value)
    return str(value)
