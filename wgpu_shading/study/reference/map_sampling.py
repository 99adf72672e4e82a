"""Material maps and colour spaces in the float64 reference (docs/conventions.md, "Material
maps" and "Colour spaces"), written from the document: sampling with sRGB decoding, the
tangent-space normal in the per-fragment derivative frame, and the per-point factors the
lighting equation and the combine take."""

from __future__ import annotations

import numpy as np

from ...scene import Material, Scene, Texture
from ...scene.maps import height_to_normal
from .lighting import dot, safe_normalize, sample_texture_bilinear


def is_linear(scene: Scene, material: Material) -> bool:
    """Linear colour space: the scene's choice, or with "auto" the material's."""
    space = scene.shading.color_space
    return (material.color_space if space == "auto" else space) == "linear"


def sample(texture: Texture, uv: np.ndarray, decode_srgb: bool = False) -> np.ndarray:
    """Bilinear RGBA in [0, 1] at `uv`; with `decode_srgb` the texels' RGB are decoded to
    linear light first (what an *-srgb texture format does before filtering)."""
    pixels = np.asarray(texture.pixels, dtype=np.float64)
    if decode_srgb:
        encoded = pixels[:, :, :3] / 255.0
        pixels = pixels.copy()
        pixels[:, :, :3] = 255.0 * np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)
    return sample_texture_bilinear(pixels, uv)


def color_map(texture: Texture | None, uv: np.ndarray, linear: bool) -> np.ndarray | None:
    """A colour map's RGBA (sRGB-decoded in linear colour space unless the texture is linear)."""
    if texture is None:
        return None
    return sample(texture, uv, decode_srgb=linear and texture.encoding == "srgb")


def tangent_normal(material: Material, uv: np.ndarray) -> np.ndarray | None:
    """The maps' tangent-space normal at `uv` (None without a normal or bump map): texel·2 − 1,
    the normal map's x, y × normal_scale; a bump map is its height → normal conversion;
    with both, x and y add and z multiplies."""
    mapped = None
    if material.normal_map is not None:
        mapped = sample(material.normal_map, uv)[:, :3] * 2.0 - 1.0
        mapped[:, :2] *= material.normal_scale
    if material.bump_map is not None:
        bump_texture = Texture(height_to_normal(material.bump_map.pixels, material.bump_scale))
        bump = sample(bump_texture, uv)[:, :3] * 2.0 - 1.0
        if mapped is None:
            mapped = bump
        else:
            mapped = np.stack([mapped[:, 0] + bump[:, 0], mapped[:, 1] + bump[:, 1], mapped[:, 2] * bump[:, 2]], axis=1)
    return mapped


def perturb(normals, corners, corner_uvs, mapped, counter_clockwise, face_sign) -> np.ndarray:
    """Normals turned by `mapped` in each triangle's tangent frame (three.js' derivative
    frame, evaluated exactly): with edges e1 = p1 − p0, e2 = p2 − p0 and uv differences
    d1, d2, T = σ·(e2 × N·d1.u − e1 × N·d2.u), B likewise with v, σ = +1 for triangles
    counter-clockwise on screen (y up) and −1 otherwise, times `face_sign`; both scaled by
    1/max(|T|, |B|). All arrays have one row per point; corners (N, 3, 3), corner_uvs (N, 3, 2)."""
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    d1, d2 = corner_uvs[:, 1] - corner_uvs[:, 0], corner_uvs[:, 2] - corner_uvs[:, 0]
    across_e2, across_e1 = np.cross(e2, normals), np.cross(e1, normals)
    sign = (np.where(counter_clockwise, 1.0, -1.0) * face_sign)[:, None]
    tangent = sign * (across_e2 * d1[:, :1] - across_e1 * d2[:, :1])
    bitangent = sign * (across_e2 * d1[:, 1:] - across_e1 * d2[:, 1:])
    largest = np.maximum(dot(tangent, tangent), dot(bitangent, bitangent))
    scale = np.where(largest > 0.0, 1.0 / np.sqrt(np.where(largest > 0.0, largest, 1.0)), 0.0)[:, None]
    turned = tangent * scale * mapped[:, :1] + bitangent * scale * mapped[:, 1:2] + normals * mapped[:, 2:3]
    return safe_normalize(turned, normals)


def perturb_with_tangents(front_normals, tangents, mapped, face_sign, derivative) -> np.ndarray:
    """Normals turned by `mapped` in the file's tangent frame (glTF TANGENT; wgsl/chunks/maps/normal_map.wgsl
    vertex_tangent_normal): T = normalize(t − N(N·t)), B = (N × T)·sign(w), N the front
    face's unit normal, T and B times `face_sign`; `derivative` where t is zero or along N.
    tangents (N, 4): the interpolated eye-space tangent and w."""
    t = tangents[:, :3]
    projected = t - front_normals * dot(front_normals, t)[:, None]
    length_squared = dot(projected, projected)
    usable = length_squared > 1e-12 * np.maximum(dot(t, t), 1e-30)
    unit = projected / np.sqrt(np.where(usable, length_squared, 1.0))[:, None]
    bitangent = np.cross(front_normals, unit) * np.where(tangents[:, 3:] >= 0.0, 1.0, -1.0)
    normals = front_normals * face_sign[:, None]
    turned = (unit * mapped[:, :1] + bitangent * mapped[:, 1:2]) * face_sign[:, None] + normals * mapped[:, 2:3]
    return np.where(usable[:, None], safe_normalize(turned, normals), derivative)


def lighting_factors(material: Material, uv: np.ndarray | None) -> dict:
    """shade()'s per-point factors at `uv`: occlusion on the ambient, shininess scale."""
    factors: dict = {}
    if uv is None:
        return factors
    if material.occlusion_map is not None:
        red = sample(material.occlusion_map, uv)[:, 0]
        factors["ambient_scale"] = 1.0 + material.occlusion_strength * (red - 1.0)
    if material.shininess_map is not None:
        factors["shininess_scale"] = sample(material.shininess_map, uv)[:, 0]
    if material.emissive_map is not None:
        factors["with_emission"] = False
    return factors


def combine_factors(scene: Scene, material: Material, uv: np.ndarray | None) -> dict:
    """combine()'s per-point arguments at `uv`: specular and emissive maps, alpha map, output encoding."""
    linear = is_linear(scene, material)
    factors: dict = {"srgb_output": linear}
    if uv is None:
        return factors
    if material.specular_map is not None:
        factors["specular_scale"] = color_map(material.specular_map, uv, linear)[:, :3]
    if material.emissive_map is not None:
        factors["emitted"] = np.asarray(material.emission[:3]) * color_map(material.emissive_map, uv, linear)[:, :3]
    if material.alpha_map is not None:
        factors["alpha_scale"] = sample(material.alpha_map, uv)[:, 0]
    return factors
