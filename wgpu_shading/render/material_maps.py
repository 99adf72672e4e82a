"""Which textures a draw binds for its material's maps (scene/maps.py), and how each is stored.

Colour maps (emissive, specular) and the base colour texture are stored in an
rgba8unorm-srgb texture when the draw is in linear colour space and the image is
sRGB-encoded: the GPU decodes each texel to linear light before filtering. Data maps
(normal, bump, shininess, occlusion, alpha) are always read as stored. A bump (height)
map is bound as the tangent-space normal map it implies (`scene.maps.height_to_normal`),
made once per (image, bump scale) and kept while the image lives.
"""

from __future__ import annotations

import weakref

from ..scene import Material, Texture
from ..scene.maps import COLOR_MAPS, height_to_normal
from .features import FeatureSet
from .pipelines import MAP_BINDINGS

_bump_normals: "weakref.WeakKeyDictionary[Texture, dict[float, Texture]]" = weakref.WeakKeyDictionary()


def bump_normal_texture(height: Texture, scale: float) -> Texture:
    """The normal map of a height map at `scale`, made on first use."""
    made = _bump_normals.setdefault(height, {})
    if scale not in made:
        made[scale] = Texture(
            height_to_normal(height.pixels, scale), name=f"{height.name} (as a normal map)",
            nearest=height.nearest, wrap=height.wrap, encoding="linear",
        )
    return made[scale]


def decodes_srgb(texture: Texture, features: FeatureSet) -> bool:
    """Whether a colour texture is stored as *-srgb for this draw."""
    return features.srgb_output and texture.encoding == "srgb"


def map_textures(material: Material, features: FeatureSet) -> list[tuple[int, Texture, bool]]:
    """(binding, texture, stored as sRGB) for every map the draw's feature set uses."""
    bound = []
    for name in features.map_flags:
        texture = getattr(material, name)
        if name == "bump_map":
            texture = bump_normal_texture(texture, material.bump_scale)
        bound.append((MAP_BINDINGS[name], texture, name in COLOR_MAPS and decodes_srgb(texture, features)))
    return bound


def object_bindings(object_buffer, draw) -> tuple[tuple, tuple[int, ...]]:
    """The object bind group's resources and their binding numbers for a draw with maps:
    uniforms, the base colour texture and sampler if any, each map's texture and sampler."""
    resources: list = [(0, object_buffer)]
    if draw.texture is not None:
        resources += [(1, draw.texture.view), (2, draw.sampler)]
    for binding, gpu_map, sampler in draw.maps:
        resources += [(binding, gpu_map.view), (binding + 1, sampler)]
    return tuple(resource for _, resource in resources), tuple(binding for binding, _ in resources)
