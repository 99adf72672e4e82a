"""glTF 2.0 (.gltf/.glb) materials and extensions; the geometry is read by gltf_data.py
(buffers, accessors), gltf_nodes.py (node graph, skins) and gltf_mesh.py (primitives).

Material mapping (glTF 2.0 spec, appendix B, onto OpenGL's model; docs/real-world-files.md):
  base = baseColorFactor (× the texture, sampled per pixel)
  ambient  = base                      (docs/real-world-files.md: base color → diffuse and ambient)
  diffuse  = base · (1 − metallic)     (c_diff)
  specular = f0 = mix(f0_dielectric, base, metallic), f0_dielectric = 0.04 (ior 1.5),
             or min(0.04 · specularColorFactor, 1) · specularFactor (KHR_materials_specular)
  shininess = clamp((2/α² − 2) / 4, 1, 512), α = roughness²: the Blinn-Phong exponent of
             the same lobe width (Walter et al. 2007), /4 for Phong's R·V (VTK's rule)
Metallic and roughness textures count with their mean value (one material per part).
KHR_materials_pbrSpecularGlossiness (archived, but in many older exports) is the classic
model already: diffuse = ambient = diffuseFactor (× diffuseTexture), specular =
specularFactor, roughness = 1 − glossinessFactor (specularGlossinessTexture ignored).
KHR_texture_transform on the base color texture is applied to the uvs (texCoord ignored).
"""

from __future__ import annotations

import reprlib
import warnings
from pathlib import Path

import numpy as np

from ..errors import MeshError
from ..scene.material import Material, Texture

_NEAREST = 9728  # GL_NEAREST (and 9984/9986 NEAREST_MIPMAP_* count as nearest too)
_SPECULAR_GLOSSINESS = "KHR_materials_pbrSpecularGlossiness"


# Every extension some part of the reader implements: a file may list these in
# extensionsRequired (glTF 2.0 §3.12); any other required one is refused by name.
IMPLEMENTED_EXTENSIONS = frozenset({
    "KHR_draco_mesh_compression", "KHR_lights_punctual", "KHR_materials_emissive_strength",
    "KHR_materials_pbrSpecularGlossiness", "KHR_materials_specular", "KHR_materials_unlit",
    "KHR_mesh_quantization", "KHR_texture_transform",
})


def _extension_list(document: dict, key: str, path: Path) -> set[str]:
    names = document.get(key, [])
    if not isinstance(names, list) or not all(isinstance(name, str) for name in names):
        raise MeshError(f"mesh file {str(path)!r}: {key}: expected a list of extension names, got {reprlib.repr(names)}")
    return set(names)


def check_extensions(document: dict, path: Path) -> None:
    """Required extensions must be ones this reader implements (one line naming the
    others). Draco needs DracoPy (the `draco` extra)."""
    used = _extension_list(document, "extensionsUsed", path)
    required = _extension_list(document, "extensionsRequired", path)
    unsupported = required - IMPLEMENTED_EXTENSIONS
    if unsupported:
        raise MeshError(f"mesh file {str(path)!r} requires glTF extension(s) this renderer does not implement: {', '.join(sorted(unsupported))}")
    if "KHR_draco_mesh_compression" in used | required:
        try:
            import DracoPy  # noqa: F401
        except ImportError:
            from ..errors import install_hint

            raise MeshError(
                f"mesh file {str(path)!r} uses Draco mesh compression (KHR_draco_mesh_compression); "
                f"to decode it, {install_hint('draco')}"
            ) from None


def transform_uvs(uvs: np.ndarray, material: dict | None) -> np.ndarray:
    """The reader's uvs with the base color texture's KHR_texture_transform applied (the
    extension's test file showed its own "not supported" tiles without it).
    uv' = T · R · S · uv in glTF's uv space, whose v the reader has flipped (v = 1 − v_glTF)."""
    if not material:
        return uvs
    info = material.get("pbrMetallicRoughness", {}).get("baseColorTexture") or {}
    gloss = material.get("extensions", {}).get(_SPECULAR_GLOSSINESS)
    if gloss is not None:
        info = gloss.get("diffuseTexture") or {}
    transform = info.get("extensions", {}).get("KHR_texture_transform")
    if not transform:
        return uvs
    offset = np.array(transform.get("offset", [0.0, 0.0]), dtype=np.float64)
    rotation = float(transform.get("rotation", 0.0))
    scale = np.array(transform.get("scale", [1.0, 1.0]), dtype=np.float64)
    cos, sin = np.cos(rotation), np.sin(rotation)
    linear = np.array([[cos, sin], [-sin, cos]]) @ np.diag(scale)  # the extension's R · S
    gltf_uv = np.stack([uvs[:, 0], 1.0 - uvs[:, 1]], axis=1) @ linear.T + offset
    return np.stack([gltf_uv[:, 0], 1.0 - gltf_uv[:, 1]], axis=1)


def _sampler(document: dict, texture_info: dict | None) -> dict:
    """The glTF sampler of a texture reference ({} when none: linear, repeat)."""
    if not texture_info:
        return {}
    textures = document.get("textures", [])
    texture = textures[texture_info.get("index", 0)] if texture_info.get("index", 0) < len(textures) else {}
    samplers = document.get("samplers", [])
    return samplers[texture["sampler"]] if "sampler" in texture and texture["sampler"] < len(samplers) else {}


def _nearest(document: dict, texture_info: dict | None) -> bool:
    return _sampler(document, texture_info).get("magFilter") == _NEAREST


# glTF wrapS/wrapT (OpenGL enums) → Texture.wrap; anything else is the spec's default, REPEAT.
_WRAP_MODES = {10497: "repeat", 33071: "clamp", 33648: "mirror"}


def _wrap(document: dict, texture_info: dict | None) -> tuple[str, str]:
    sampler = _sampler(document, texture_info)
    return _WRAP_MODES.get(sampler.get("wrapS"), "repeat"), _WRAP_MODES.get(sampler.get("wrapT"), "repeat")


def _mean_channel(image, channel: int) -> float:
    if image is None:
        return 1.0
    pixels = np.asarray(image.convert("RGBA"), dtype=np.float64)
    return float(pixels[:, :, channel].mean() / 255.0)


def gltf_material(document: dict, row: dict, trimesh_material, name: str) -> Material | None:
    """The classic material of one primitive (see the module docstring); None when the
    primitive has no material (the object's or the command's default applies)."""
    material = row["material"]
    if material is None:
        return None
    pbr = material.get("pbrMetallicRoughness", {})
    extensions = material.get("extensions", {})
    glossiness = extensions.get(_SPECULAR_GLOSSINESS)
    if glossiness is not None:  # the classic model already (module docstring)
        base = np.array(glossiness.get("diffuseFactor", [1.0, 1.0, 1.0, 1.0]), dtype=np.float64)
        diffuse = base[:3]
        specular = np.clip(np.array(glossiness.get("specularFactor", [1.0, 1.0, 1.0]), dtype=np.float64), 0.0, 1.0)
        roughness = 1.0 - float(np.clip(glossiness.get("glossinessFactor", 1.0), 0.0, 1.0))
        base_texture_info = glossiness.get("diffuseTexture")
    else:
        base = np.array(pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0]), dtype=np.float64)
        metallic = float(pbr.get("metallicFactor", 1.0))
        roughness = float(pbr.get("roughnessFactor", 1.0))
        image = getattr(trimesh_material, "metallicRoughnessTexture", None)
        if image is not None:  # glTF: roughness in G, metalness in B
            metallic *= _mean_channel(image, 2)
            roughness *= _mean_channel(image, 1)
        specular_extension = extensions.get("KHR_materials_specular")
        if specular_extension is not None:
            color = np.array(specular_extension.get("specularColorFactor", [1.0, 1.0, 1.0]), dtype=np.float64)
            dielectric = np.minimum(0.04 * color, 1.0) * float(specular_extension.get("specularFactor", 1.0))
        else:
            dielectric = np.full(3, 0.04)
        diffuse = base[:3] * (1.0 - metallic)
        specular = dielectric * (1.0 - metallic) + base[:3] * metallic
        base_texture_info = pbr.get("baseColorTexture")
    alpha = max(roughness, 0.03) ** 2
    shininess = float(np.clip((2.0 / alpha**2 - 2.0) / 4.0, 1.0, 512.0))
    emission = np.array(material.get("emissiveFactor", [0.0, 0.0, 0.0]), dtype=np.float64)
    if "KHR_materials_emissive_strength" in extensions:
        emission = emission * float(extensions["KHR_materials_emissive_strength"].get("emissiveStrength", 1.0))
    emissive_image = getattr(trimesh_material, "emissiveTexture", None)
    if emissive_image is not None and emission.any():
        emission = emission * np.array([_mean_channel(emissive_image, k) for k in range(3)])
    texture = None
    image = getattr(trimesh_material, "baseColorTexture", None)
    if image is not None:
        nearest = _nearest(document, base_texture_info)
        texture = Texture(
            np.asarray(image.convert("RGBA")), name=f"{name}:{material.get('name', '')}", nearest=nearest,
            wrap=_wrap(document, base_texture_info),
        )
    elif base_texture_info is not None:
        # The reader gives None for an image it cannot load (missing, a folder, a FIFO, not
        # an image); say so, as for an OBJ's missing map_Kd, instead of an untextured surprise.
        warnings.warn(
            f"{name}: material {material.get('name', '')!r}: its base colour texture could not be read; drawn untextured",
            stacklevel=2,
        )
    alpha_mode = str(material.get("alphaMode", "OPAQUE")).lower()
    opacity = float(np.clip(base[3], 0.0, 1.0))
    unlit = "KHR_materials_unlit" in extensions
    return Material(
        ambient=tuple(base[:3]) + (opacity,),
        diffuse=tuple((base[:3] if unlit else diffuse)) + (opacity,),
        specular=tuple(specular) + (opacity,),
        emission=tuple(np.clip(emission, 0.0, None)) + (1.0,),
        shininess=shininess,
        texture=texture,
        name=str(material.get("name", "")),
        alpha_mode=alpha_mode if alpha_mode in ("opaque", "mask", "blend") else "opaque",
        alpha_cutoff=float(np.clip(material.get("alphaCutoff", 0.5), 0.0, 1.0)),
        unlit=unlit,
        double_sided=material.get("doubleSided", False) is True,
    )

