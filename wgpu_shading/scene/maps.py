"""The maps of a Phong material and the colour spaces (docs/conventions.md, "Material maps").

Each map is an optional Texture field of `Material`, sampled with the mesh's UVs:

    normal_map     tangent-space normal (RGB = (x, y, z)·0.5 + 0.5, +Y up the image), × normal_scale on x, y
    bump_map       height (red channel); turned into a tangent-space normal map on upload (`height_to_normal`)
    specular_map   RGB × the specular colour
    shininess_map  red × the shininess
    emissive_map   RGB × the emission colour, added after the texture combine
    occlusion_map  red: the ambient terms × (1 + occlusion_strength·(red − 1)) (glTF's rule)
    alpha_map      red × the alpha

`COLOR_MAPS` hold colours (sRGB-decoded in linear colour space when their Texture says
"srgb"); the others hold data and are always read as stored.
"""

from __future__ import annotations

import numpy as np

MAP_FIELDS: tuple[str, ...] = (
    "normal_map", "bump_map", "specular_map", "shininess_map", "emissive_map", "occlusion_map", "alpha_map",
)
COLOR_MAPS = frozenset({"emissive_map", "specular_map"})
TEXTURE_ENCODINGS = ("srgb", "linear")
# "display": colours are display values, lit and written as they are (OpenGL, the seeds, OBJ/MTL).
# "linear": colours are linear light; colour textures are sRGB-decoded and the output sRGB-encoded (glTF).
COLOR_SPACES = ("display", "linear")
# Scene-level choice: "auto" follows each material (glTF materials are linear, all others display).
SCENE_COLOR_SPACES = ("auto",) + COLOR_SPACES

# A full-range height step (0 → 1) is this fraction of the texture's width deep, × bump_scale.
BUMP_DEPTH = 1.0 / 32.0


def srgb_decode(encoded: np.ndarray) -> np.ndarray:
    """sRGB-encoded values in [0, 1] → linear (IEC 61966-2-1)."""
    encoded = np.asarray(encoded, dtype=np.float64)
    return np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    """Linear values in [0, 1] → sRGB-encoded (IEC 61966-2-1)."""
    linear = np.clip(np.asarray(linear, dtype=np.float64), 0.0, 1.0)
    return np.where(linear <= 0.0031308, linear * 12.92, 1.055 * linear ** (1.0 / 2.4) - 0.055)


def height_to_normal(pixels: np.ndarray, scale: float) -> np.ndarray:
    """A height map (red channel, rows top to bottom) → an RGBA8 tangent-space normal map.

    Central differences with wrap-around (textures repeat): the slope along u is
    Δheight per texel × width × BUMP_DEPTH × scale (so the depth does not change with the
    image's resolution); n = normalize(−∂h/∂u, −∂h/∂v, 1), v pointing up the image."""
    height = np.asarray(pixels, dtype=np.float64)[:, :, 0] / 255.0
    rows, columns = height.shape
    depth = BUMP_DEPTH * scale
    # Rows run top to bottom, v bottom to top: ∂h/∂v = (row above − row below) / 2.
    slope_u = (np.roll(height, -1, axis=1) - np.roll(height, 1, axis=1)) / 2.0 * columns * depth
    slope_v = (np.roll(height, 1, axis=0) - np.roll(height, -1, axis=0)) / 2.0 * columns * depth
    normal = np.stack([-slope_u, -slope_v, np.ones_like(height)], axis=-1)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    rgb = np.round((normal * 0.5 + 0.5) * 255.0).astype(np.uint8)
    return np.concatenate([rgb, np.full((rows, columns, 1), 255, np.uint8)], axis=-1)


def classify_bump_image(pixels: np.ndarray) -> str:
    """What an MTL `bump`/`map_Bump` image really is: "normal", "height" or "other".

    The MTL format defines a height map, but many exporters write tangent-space normal
    maps there. The rule (docs/real-world-files.md): a tangent-space normal map is bluish,
    its mean blue above 0.7 and at least 0.2 above the mean red and green, which lie
    within 0.15 of 0.5; a grey image (mean per-pixel channel spread below 12/255) is a
    height map; anything else (a colour photo) is "other" and is not used."""
    rgb = np.asarray(pixels, dtype=np.float64)[:, :, :3] / 255.0
    if rgb.shape[0] * rgb.shape[1] > 1 << 18:  # a sample is plenty for means
        step = int(np.ceil(np.sqrt(rgb.shape[0] * rgb.shape[1] / float(1 << 18))))
        rgb = rgb[::step, ::step]
    red, green, blue = (float(rgb[:, :, k].mean()) for k in range(3))
    if blue > 0.7 and blue - max(red, green) > 0.2 and abs(red - 0.5) < 0.15 and abs(green - 0.5) < 0.15:
        return "normal"
    if float((rgb.max(axis=2) - rgb.min(axis=2)).mean()) < 12.0 / 255.0:
        return "height"
    return "other"


def alpha_pixels(pixels: np.ndarray) -> np.ndarray:
    """The values an alpha map (MTL `map_d`, scene key `alpha_map`) stands for, in every
    channel: the image's alpha where it has transparency, else its luminance (Rec. 709)."""
    pixels = np.asarray(pixels)
    if pixels.shape[2] == 4 and int(pixels[:, :, 3].min()) < 255:
        value = pixels[:, :, 3].astype(np.float64)
    else:
        value = pixels[:, :, :3].astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])
    value = np.round(value).astype(np.uint8)
    return np.repeat(value[:, :, None], 4, axis=2)
