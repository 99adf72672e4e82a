"""Shadows in a scene (docs/shadows.md): which lights cast them, and how the GPU
approximates them.

What casts and what receives is said where it belongs (scene/objects.py has the functions
that ask a Scene): `shadows` on each light (default
false), `cast_shadows` and `receive_shadows` on each object (default true). How the GPU
approximates the exact visibility — the size of its shadow maps, how a map is filtered and
how far a receiver is biased towards the light — is the scene's `ShadowSettings`. Every
setting is deterministic (no random sampling), so a scene gives the same picture on every
run; "auto" lets the renderer pick the cheapest setting that meets the guarantees of
docs/shadows.md (`study/accuracy/shadow_choice.py` is the rule).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Union

from ..errors import SceneError, shown
from .values import choice, number, set_fields

AUTO = "auto"
# The filters, cheapest first. nearest: one depth comparison with the nearest texel;
# bilinear: the hardware's 2×2 comparison sampler (sampler_comparison, linear filtering);
# pcf3 / pcf5: 3×3 / 5×5 grids of bilinear comparisons, equally weighted.
SHADOW_FILTERS: tuple[str, ...] = ("nearest", "bilinear", "pcf3", "pcf5")
# Shadow-map sides, in texels: WebGPU guarantees 2D and cube textures up to 8192 on every
# adapter (maxTextureDimension2D); below 16 a map cannot resolve anything.
MIN_SHADOW_MAP_SIZE, MAX_SHADOW_MAP_SIZE = 16, 8192
# Bias in shadow-map texels: 0 (none: acne wherever the receiver is the caster) to 64.
MAX_SHADOW_BIAS_TEXELS = 64.0

# What "auto" resolves to, field by field: the accuracy study's choice
# (docs/shadows.md#auto, study/accuracy/shadow_choice.py), measured on the GPU's shadows
# over every hard case (docs/accuracy.md#shadows; tests/test_shadow_study.py checks these
# against the stored points).
AUTO_MAP_SIZE, AUTO_FILTER, AUTO_BIAS = 256, "nearest", 4.0
# An "auto" map is AUTO_MAP_SIZE texels, doubled while its texels are wider than
# 1/AUTO_TEXELS_PER_PIXEL of a pixel of the image on a receiver it may shadow, up to
# AUTO_MAP_SIZE_LIMIT (render/passes/shadow_resolution.py; docs/shadows.md#auto): a caster
# thinner than a texel as the light sees it (a quad nearly edge-on) casts a shadow whose
# edges the map draws half a texel off, and 1/8 of a pixel still left specks (the hard case
# sliver_shadow, random scenes 290, 270, 229).
AUTO_TEXELS_PER_PIXEL, AUTO_MAP_SIZE_LIMIT = 16.0, 2048
AUTO_IS_MEASURED = True

ShadowFilter = Literal["auto", "nearest", "bilinear", "pcf3", "pcf5"]
MapSize = Union[int, Literal["auto"]]
Bias = Union[float, Literal["auto"]]


def shadow_map_size(value: object, name: str = "shadows.map_size") -> MapSize:
    """A whole number of texels in [16, 8192], or "auto"."""
    if value == AUTO:
        return AUTO
    whole = isinstance(value, int) or isinstance(value, float) and value.is_integer()
    if isinstance(value, bool) or not whole:
        raise SceneError(f"{name}: expected \"auto\" or a whole number of texels, got {shown(value)}")
    size = int(value)
    if not MIN_SHADOW_MAP_SIZE <= size <= MAX_SHADOW_MAP_SIZE:
        raise SceneError(f"{name}: expected \"auto\" or {MIN_SHADOW_MAP_SIZE}..{MAX_SHADOW_MAP_SIZE} texels, got {size}")
    return size


@dataclass(frozen=True)
class ShadowSettings:
    """How the GPU approximates the exact shadows of the lights that cast them.

    map_size: side of each shadow map (a cube map's face for a positional light), texels.
    filter:   how a map is read: one of SHADOW_FILTERS.
    bias:     how far each receiver is moved towards the light before it is compared with
              the map, in texels of that map (the renderer adds the slope term): texels,
              not world units or normalised depth, so that one value works at any scale.
    "auto" (each default) is the cheapest choice that meets docs/shadows.md's guarantees."""

    map_size: MapSize = AUTO
    filter: ShadowFilter = AUTO
    bias: Bias = AUTO

    def __post_init__(self) -> None:
        bias = self.bias if self.bias == AUTO else number(self.bias, "shadows.bias", 0.0, MAX_SHADOW_BIAS_TEXELS)
        set_fields(
            self,
            map_size=shadow_map_size(self.map_size),
            filter=choice(self.filter, "shadows.filter", (AUTO,) + SHADOW_FILTERS),
            bias=bias,
        )

    def resolved(self) -> "ShadowSettings":
        """Every "auto" replaced by the study's choice (docs/shadows.md#auto); explicit values kept."""
        return ShadowSettings(
            map_size=AUTO_MAP_SIZE if self.map_size == AUTO else self.map_size,
            filter=AUTO_FILTER if self.filter == AUTO else self.filter,
            bias=AUTO_BIAS if self.bias == AUTO else self.bias,
        )
