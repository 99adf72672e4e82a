"""Light sources (docs/conventions.md#the-lighting-equation): directional, positional and spot lights, OpenGL style."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Union

from ..errors import SceneError
from .values import MAX_COORDINATE, MAX_EXPONENT, Color, Vec3, boolean, finite_numbers, set_fields, color, direction, number, vec3


def _common_fields(light: object, prefix: str) -> dict[str, object]:
    """The fields every kind of light has: its three colours and whether it casts shadows."""
    colors = {key: color(getattr(light, key), f"{prefix}.{key}") for key in ("ambient", "diffuse", "specular")}
    return colors | {"shadows": boolean(getattr(light, "shadows"), f"{prefix}.shadows")}


def _attenuation(value: object, name: str) -> Vec3:
    coefficients = finite_numbers(value, name, (3,))
    if min(coefficients) < 0.0:
        raise SceneError(f"{name}: coefficients must be >= 0, got {list(coefficients)}")
    if max(coefficients) > MAX_COORDINATE:
        raise SceneError(f"{name}: coefficients must be at most {MAX_COORDINATE:g}, got {list(coefficients)}")
    if max(coefficients) == 0.0:
        raise SceneError(
            f"{name}: (0, 0, 0) divides by zero everywhere; use (1, 0, 0) for no attenuation"
        )
    return coefficients  # type: ignore[return-value]


@dataclass(frozen=True)
class DirectionalLight:
    """A light at infinity (sunlight): `direction` is the way the light travels, in world space."""

    direction: Vec3 = (0.0, 0.0, -1.0)
    ambient: Color = (0.0, 0.0, 0.0, 1.0)
    diffuse: Color = (1.0, 1.0, 1.0, 1.0)
    specular: Color = (1.0, 1.0, 1.0, 1.0)
    shadows: bool = False  # objects between a point and the light shade it (docs/shadows.md)

    kind = "directional"

    def __post_init__(self) -> None:
        set_fields(self, direction=direction(self.direction, "light.direction"), **_common_fields(self, "light"))


@dataclass(frozen=True)
class PositionalLight:
    """A point light at `position` (world space) with OpenGL attenuation 1/(kc + kl d + kq d²).

    `range` > 0 (glTF KHR_lights_punctual's) also fades the light to zero at that distance
    with the extension's window clamp(1 − (d/range)⁴, 0, 1)²; 0 (the default) never cuts off."""

    position: Vec3 = (5.0, 2.0, 2.0)
    ambient: Color = (0.0, 0.0, 0.0, 1.0)
    diffuse: Color = (1.0, 1.0, 1.0, 1.0)
    specular: Color = (1.0, 1.0, 1.0, 1.0)
    attenuation: Vec3 = (1.0, 0.0, 0.0)  # constant, linear, quadratic
    range: float = 0.0  # distance where the light fades out (0: never)
    shadows: bool = False  # as DirectionalLight.shadows

    kind = "positional"

    def __post_init__(self) -> None:
        set_fields(
            self,
            position=vec3(self.position, "light.position"),
            attenuation=_attenuation(self.attenuation, "light.attenuation"),
            range=number(self.range, "light.range", 0.0, MAX_COORDINATE),
            **_common_fields(self, "light"),
        )


@dataclass(frozen=True)
class SpotLight:
    """A positional light limited to a cone around `direction` (the way the light travels).

    Inside the cone the intensity is cos(φ)^exponent, φ the angle off the axis; outside
    (φ >= cutoff) it is zero. The cone is open: cutoff 0 gives no light at all.
    """

    position: Vec3 = (5.0, 2.0, -3.0)
    direction: Vec3 = (0.0, 0.0, -1.0)
    cutoff: float = 20.0  # degrees, 0..90
    exponent: float = 10.0
    ambient: Color = (0.0, 0.0, 0.0, 1.0)
    diffuse: Color = (1.0, 1.0, 1.0, 1.0)
    specular: Color = (1.0, 1.0, 1.0, 1.0)
    attenuation: Vec3 = (1.0, 0.0, 0.0)
    range: float = 0.0  # as PositionalLight.range
    shadows: bool = False  # as DirectionalLight.shadows

    kind = "spot"

    def __post_init__(self) -> None:
        set_fields(
            self,
            position=vec3(self.position, "light.position"),
            direction=direction(self.direction, "light.direction"),
            cutoff=number(self.cutoff, "light.cutoff", 0.0, 90.0),
            exponent=number(self.exponent, "light.exponent", 0.0, MAX_EXPONENT),
            attenuation=_attenuation(self.attenuation, "light.attenuation"),
            range=number(self.range, "light.range", 0.0, MAX_COORDINATE),
            **_common_fields(self, "light"),
        )


Light = Union[DirectionalLight, PositionalLight, SpotLight]
LIGHT_TYPES: dict[str, type] = {
    "directional": DirectionalLight,
    "positional": PositionalLight,
    "spot": SpotLight,
}

