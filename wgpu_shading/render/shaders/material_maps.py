"""How the textures of a draw's material maps (scene/maps.py) are stored; the binding plan
(bindings.py) lists which are bound.

Colour maps (emissive, specular) and the base colour texture are stored in an
rgba8unorm-srgb texture when the draw is in linear colour space and the image is
sRGB-encoded: the GPU decodes each texel to linear light before filtering. Data maps
(normal, bump, shininess, occlusion, alpha) are always read as stored. A bump (height)
map is bound as the tangent-space normal map it implies (`scene.maps.height_to_normal`),
made once per (image, bump scale) and kept while the image lives.
"""

from __future__ import annotations

import weakref

from ...scene import Material, Texture
from ...scene.maps import height_to_normal
from ..features import FeatureSet

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
