"""glTF materials → classic Materials with maps (docs/real-world-files.md, "glTF materials").

Colours follow the file: glTF's factors and COLOR_0 are linear, its base colour and
emissive textures sRGB-encoded (glTF 2.0 §3.9.2), so every glTF material is drawn in
linear colour space (`Material.color_space = "linear"`: lit in linear light, output
sRGB-encoded, as glTF viewers show it).

Metallic-roughness onto the classic model (glTF 2.0 spec, appendix B, plus a rule for
rough metals). With base = baseColorFactor, m = metallic, r = roughness:

    s         = m · (1 − r²)             the share of the base colour reflected as a highlight
    ambient   = base
    diffuse   = base · (1 − s)           dielectrics: base; rough metals: base as well
    specular  = f0 · (1 − m) + base · s  f0 = 0.04 (ior 1.5), or min(0.04 · specularColorFactor, 1)
                                         · specularFactor (KHR_materials_specular)
    shininess = clamp((2/α² − 2) / 4, 1, 512), α = r²

Without an environment a metal's reflection of its surroundings is missing; viewers light
a rough metal with their environment's blurred, even light, which looks like a diffuse
surface of the base colour. `s` moves a metal's reflectance from the highlight to the
diffuse term as it gets rough: `pbrMetallicRoughness: {}` (metallic 1, roughness 1, the
glTF default material) is an even grey instead of black with a white hot spot; a polished
metal (r → 0) keeps all of it in the highlight.

The metallic-roughness texture (metalness in blue, roughness in green) is applied per
texel: a specular map (the highlight's colour above, texel by texel, relative to the
material's specular colour, the largest over the texture), a shininess map (the exponent
above, relative to the largest), and the diffuse factor (1 − s) multiplied into the base
colour texture (made from it when the material has none; resampled to the base colour
texture's size, in linear light), which the `modulate` combine applies to the ambient
and diffuse terms (and to a factor-only emission: that one is dimmed on metal texels). Other maps: normalTexture (× scale), emissiveTexture
(× emissiveFactor × KHR_materials_emissive_strength), occlusionTexture (× strength).
KHR_materials_specular's specularTexture (alpha) and specularColorTexture (sRGB) make f0
per texel.
KHR_materials_pbrSpecularGlossiness (archived, but in many older exports) is the classic
model already: diffuse = ambient = diffuseFactor (× diffuseTexture), specular =
specularFactor, roughness = 1 − glossinessFactor (specularGlossinessTexture ignored).
"""

from __future__ import annotations

import numpy as np

from ...scene.maps import srgb_decode, srgb_encode
from ...scene.material import Material, Texture

SPECULAR_GLOSSINESS = "KHR_materials_pbrSpecularGlossiness"
_NEAREST = 9728  # GL_NEAREST (and 9984/9986 NEAREST_MIPMAP_* count as nearest too)
# glTF wrapS/wrapT (OpenGL enums) → Texture.wrap; anything else is the spec's default, REPEAT.
_WRAP_MODES = {10497: "repeat", 33071: "clamp", 33648: "mirror"}
# The glTF default material (§3.9.1: a primitive without one): white, metallic 1, roughness 1.
DEFAULT_MATERIAL: dict = {"name": "glTF default"}


def _sampler(document: dict, texture_info: dict | None) -> dict:
    """The glTF sampler of a texture reference ({} when none: linear, repeat)."""
    if not texture_info:
        return {}
    textures = document.get("textures", [])
    texture = textures[texture_info.get("index", 0)] if texture_info.get("index", 0) < len(textures) else {}
    samplers = document.get("samplers", [])
    return samplers[texture["sampler"]] if "sampler" in texture and texture["sampler"] < len(samplers) else {}


def _texture(document: dict, image, info: dict | None, name: str, encoding: str = "srgb", pixels=None) -> Texture:
    sampler = _sampler(document, info)
    return Texture(
        np.asarray(image.convert("RGBA")) if pixels is None else pixels, name=name,
        nearest=sampler.get("magFilter") == _NEAREST, encoding=encoding,
        wrap=(_WRAP_MODES.get(sampler.get("wrapS"), "repeat"), _WRAP_MODES.get(sampler.get("wrapT"), "repeat")),
    )


def shininess_of(roughness):
    """The Phong exponent of a roughness (module docstring)."""
    alpha = np.maximum(roughness, 0.03) ** 2
    return np.clip((2.0 / alpha**2 - 2.0) / 4.0, 1.0, 512.0)


# Per-texel maps are computed this many texel rows at a time: their float64 temporaries
# are a block's, not a whole image's (a 2048² metallic-roughness texture took ~0.8 GB;
# docs/reliability.md#peak-memory-of-a-textured-gltf), and the bytes are the same.
_BLOCK_ROWS = 128


def _row_blocks(height: int) -> list[slice]:
    return [slice(start, min(start + _BLOCK_ROWS, height)) for start in range(0, height, _BLOCK_ROWS)]


def _metallic_roughness(document, info, image, base, metallic, roughness, dielectric, name) -> dict:
    """Material fields for the metallic-roughness model; per-texel maps from `image`."""
    if image is None and np.ndim(dielectric) == 1:
        share = metallic * (1.0 - roughness**2)
        return dict(diffuse=base * (1.0 - share), specular=dielectric * (1.0 - metallic) + base * share,
                    shininess=float(shininess_of(roughness)))
    rgba = None if image is None else np.asarray(image.convert("RGBA"))  # blue: metallic, green: roughness
    shape = dielectric.shape[:2] if rgba is None else rgba.shape[:2]
    if rgba is not None and np.ndim(dielectric) == 3:  # KHR_materials_specular textures, on the same texels
        dielectric = _resized(dielectric, shape)

    def texels(rows: slice) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """share (how much of the base colour is specular), specular and shininess of some rows."""
        if rgba is None:  # f0 from KHR_materials_specular textures, metallic and roughness from factors
            count = len(range(*rows.indices(shape[0])))
            texel_metallic, texel_roughness = np.full((count, shape[1]), metallic), np.full((count, shape[1]), roughness)
        else:
            texel_metallic, texel_roughness = metallic * (rgba[rows, :, 2] / 255.0), roughness * (rgba[rows, :, 1] / 255.0)
        f0 = dielectric[rows] if np.ndim(dielectric) == 3 else dielectric
        share = texel_metallic * (1.0 - texel_roughness**2)
        return share, f0 * (1.0 - texel_metallic)[:, :, None] + base * share[:, :, None], shininess_of(texel_roughness)

    # the maps store each texel over the largest value (then in the material): found first
    top_specular, top_shininess = np.full(3, 1e-6), 0.0
    for rows in _row_blocks(shape[0]):
        _, specular, shininess = texels(rows)
        top_specular = np.maximum(top_specular, specular.reshape(-1, 3).max(axis=0))
        top_shininess = max(top_shininess, float(shininess.max()))
    diffuse_factor = np.empty(shape)
    specular_map, shininess_map = (np.full(shape + (4,), 255, np.uint8) for _ in range(2))
    for rows in _row_blocks(shape[0]):
        share, specular, shininess = texels(rows)
        diffuse_factor[rows] = 1.0 - share
        specular_map[rows, :, :3] = _bytes(specular / top_specular)
        shininess_map[rows, :, :3] = _bytes(shininess / top_shininess)[:, :, None]
    return dict(
        diffuse=base, specular=top_specular, shininess=top_shininess, diffuse_factor=diffuse_factor,
        specular_map=_texture(document, image, info, f"{name} (specular from metallic-roughness)", "linear", specular_map),
        shininess_map=_texture(document, image, info, f"{name} (shininess from roughness)", "linear", shininess_map),
    )


def _bytes(values: np.ndarray) -> np.ndarray:
    """Values in [0, 1] (clipped) as 8-bit texel values."""
    return np.round(np.clip(values, 0.0, 1.0) * 255.0).astype(np.uint8)


def _resized(values: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """An (H, W) or (H, W, C) float array resampled bilinearly to `shape`[:2]."""
    from PIL import Image

    if values.shape[:2] == tuple(shape[:2]):
        return values
    size = (shape[1], shape[0])
    channels = [values] if values.ndim == 2 else [values[:, :, k] for k in range(values.shape[2])]
    resized = [np.asarray(Image.fromarray(c.astype(np.float32), mode="F").resize(size, Image.BILINEAR), np.float64) for c in channels]
    return resized[0] if values.ndim == 2 else np.stack(resized, axis=2)


def _specular_extension(extension: dict, images) -> np.ndarray:
    """KHR_materials_specular's dielectric f0 = min(0.04 · specularColorFactor (× the sRGB
    specularColorTexture), 1) · specularFactor (× specularTexture's alpha): (3,), or
    (H, W, 3) per texel when it has textures (decoded by primitives.material_images)."""
    color = np.array(extension.get("specularColorFactor", [1.0, 1.0, 1.0]), dtype=np.float64)
    factor = float(extension.get("specularFactor", 1.0))
    color_image = getattr(images, "specularColorTexture", None)
    factor_image = getattr(images, "specularTexture", None)
    if color_image is None and factor_image is None:
        return np.minimum(0.04 * color, 1.0) * factor
    shape = (color_image if color_image is not None else factor_image).size[::-1]
    texel_color = np.broadcast_to(color, shape + (3,))
    if color_image is not None:
        texel_color = color * srgb_decode(np.asarray(color_image.convert("RGB"), np.float64) / 255.0)
    texel_factor = np.full(shape, factor)
    if factor_image is not None:
        texel_factor = factor * _resized(np.asarray(factor_image.convert("RGBA"), np.float64)[:, :, 3] / 255.0, shape)
    return np.minimum(0.04 * texel_color, 1.0) * texel_factor[:, :, None]


def _with_diffuse_factor(texture: Texture | None, factor: np.ndarray, label: str) -> Texture:
    """The base colour texture × the metallic-roughness texture's diffuse factor, per texel
    (module docstring); the factor alone (linear) when there is no base colour texture."""
    if texture is None:
        grey = np.round(np.repeat(factor[:, :, None], 3, axis=2) * 255.0).astype(np.uint8)
        pixels = np.concatenate([grey, np.full(grey.shape[:2] + (1,), 255, np.uint8)], axis=2)
        return Texture(pixels, name=f"{label} (diffuse from metallic-roughness)", encoding="linear")
    from PIL import Image

    height, width = texture.pixels.shape[:2]
    if factor.shape != (height, width):
        factor = np.asarray(Image.fromarray(factor.astype(np.float32), mode="F").resize((width, height), Image.BILINEAR), np.float64)
    pixels = np.array(texture.pixels)  # alpha kept as it is
    for rows in _row_blocks(height):
        rgb, scale = texture.pixels[rows, :, :3] / 255.0, factor[rows, :, None]
        # sRGB: scaled in linear light, stored encoded again
        pixels[rows, :, :3] = _bytes(srgb_encode(srgb_decode(rgb) * scale) if texture.encoding == "srgb" else rgb * scale)
    return Texture(pixels, name=texture.name, nearest=texture.nearest, wrap=texture.wrap, encoding=texture.encoding)


def gltf_material(document: dict, row: dict, images, name: str, notes: list[str]) -> Material:
    """The classic material of one primitive (module docstring); `images` holds its decoded
    textures (primitives.material_images). A primitive without a material gets the glTF
    default material. What the user should be told (a texture that could not be read) is
    added to `notes`: said once the whole file is read (GltfData.notes)."""
    material = row["material"]
    if material is None:
        material, images = DEFAULT_MATERIAL, None
    label = f"{name}:{material.get('name', '')}"
    pbr = material.get("pbrMetallicRoughness", {})
    extensions = material.get("extensions", {})
    glossiness = extensions.get(SPECULAR_GLOSSINESS)
    image_of = lambda key: getattr(images, key, None)  # noqa: E731 (the reader's decoded PIL images, primitives.material_images)
    if glossiness is not None:  # the classic model already (module docstring)
        base = np.array(glossiness.get("diffuseFactor", [1.0, 1.0, 1.0, 1.0]), dtype=np.float64)
        roughness = 1.0 - float(np.clip(glossiness.get("glossinessFactor", 1.0), 0.0, 1.0))
        fields = dict(diffuse=base[:3], shininess=float(shininess_of(roughness)),
                      specular=np.clip(np.array(glossiness.get("specularFactor", [1.0, 1.0, 1.0]), dtype=np.float64), 0.0, 1.0))
        base_texture_info = glossiness.get("diffuseTexture")
    else:
        base = np.array(pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0]), dtype=np.float64)
        specular_extension = extensions.get("KHR_materials_specular")
        dielectric = np.full(3, 0.04) if specular_extension is None else _specular_extension(specular_extension, images)
        fields = _metallic_roughness(
            document, pbr.get("metallicRoughnessTexture"), image_of("metallicRoughnessTexture"), base[:3],
            float(pbr.get("metallicFactor", 1.0)), float(pbr.get("roughnessFactor", 1.0)), dielectric, label,
        )
        base_texture_info = pbr.get("baseColorTexture")
    emission = np.array(material.get("emissiveFactor", [0.0, 0.0, 0.0]), dtype=np.float64)
    if "KHR_materials_emissive_strength" in extensions:
        emission = emission * float(extensions["KHR_materials_emissive_strength"].get("emissiveStrength", 1.0))
    maps: dict = {}
    if image_of("emissiveTexture") is not None and emission.any():
        maps["emissive_map"] = _texture(document, image_of("emissiveTexture"), material.get("emissiveTexture"), f"{label} (emissive)")
    if image_of("normalTexture") is not None:
        info = material.get("normalTexture") or {}
        maps["normal_map"] = _texture(document, image_of("normalTexture"), info, f"{label} (normal)", "linear")
        maps["normal_scale"] = float(np.clip(info.get("scale", 1.0), -1e3, 1e3))
    if image_of("occlusionTexture") is not None:
        info = material.get("occlusionTexture") or {}
        maps["occlusion_map"] = _texture(document, image_of("occlusionTexture"), info, f"{label} (occlusion)", "linear")
        maps["occlusion_strength"] = float(np.clip(info.get("strength", 1.0), 0.0, 1.0))
    texture = None
    if image_of("baseColorTexture") is not None:
        texture = _texture(document, image_of("baseColorTexture"), base_texture_info, label)
    elif base_texture_info is not None:
        # The reader gives None for an image it cannot load (missing, a folder, a FIFO, not
        # an image); say so, as for an OBJ's missing map_Kd, instead of an untextured surprise.
        notes.append(f"{name}: material {material.get('name', '')!r}: its base colour texture could not be read; drawn untextured")
    unlit = "KHR_materials_unlit" in extensions or row.get("unlit", False)  # lines, points without normals (reader.py)
    if "diffuse_factor" in fields:
        factor = fields.pop("diffuse_factor")
        texture = texture if unlit else _with_diffuse_factor(texture, factor, label)
    alpha_mode = str(material.get("alphaMode", "OPAQUE")).lower()
    opacity = float(np.clip(base[3], 0.0, 1.0))
    return Material(
        ambient=tuple(base[:3]) + (opacity,),
        diffuse=tuple(base[:3] if unlit else fields.pop("diffuse")) + (opacity,),
        specular=tuple(fields.pop("specular")) + (opacity,),
        emission=tuple(np.clip(emission, 0.0, None)) + (1.0,),
        shininess=fields.pop("shininess"),
        texture=texture,
        name=str(material.get("name", "")),
        alpha_mode=alpha_mode if alpha_mode in ("opaque", "mask", "blend") else "opaque",
        alpha_cutoff=float(np.clip(material.get("alphaCutoff", 0.5), 0.0, 1.0)),
        unlit=unlit,
        double_sided=material.get("doubleSided", False) is True,
        color_space="linear",
        **(fields if not unlit else {}),
        **(maps if not unlit else {}),
    )
