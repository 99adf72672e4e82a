"""glTF 2.0 (.gltf/.glb) materials and extensions; the geometry is read by document.py
(buffers, accessors), nodes.py (node graph, skins) and primitives.py (primitives).

Materials: materials.py (linear colours, metallic-roughness with maps, the default material).
Every texture reads its own texture coordinates: its TEXCOORD set (`texCoord`, and
KHR_texture_transform's `texCoord` override) with its own transform (reader.py).
"""

from __future__ import annotations

import reprlib
from pathlib import Path

import numpy as np

from ...errors import MeshError
from .materials import SPECULAR_GLOSSINESS as _SPECULAR_GLOSSINESS


# Every extension some part of the reader implements: a file may list these in
# extensionsRequired (glTF 2.0 §3.12); any other required one is refused by name.
IMPLEMENTED_EXTENSIONS = frozenset({
    "KHR_draco_mesh_compression", "KHR_lights_punctual", "KHR_materials_emissive_strength",
    "KHR_materials_pbrSpecularGlossiness", "KHR_materials_specular", "KHR_materials_unlit",
    "KHR_mesh_quantization", "KHR_texture_transform", "EXT_texture_webp", "EXT_meshopt_compression",
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
            from ...errors import install_hint

            raise MeshError(
                f"mesh file {str(path)!r} uses Draco mesh compression (KHR_draco_mesh_compression); "
                f"to decode it, {install_hint('draco')}"
            ) from None


# The glTF textures of a material and the Material fields each one feeds (materials.py).
TEXTURE_FIELDS = {
    "baseColorTexture": ("texture",),
    "metallicRoughnessTexture": ("specular_map", "shininess_map"),
    "normalTexture": ("normal_map",),
    "occlusionTexture": ("occlusion_map",),
    "emissiveTexture": ("emissive_map",),
    "specularColorTexture": ("specular_map",),
    "specularTexture": ("specular_map",),
}
UvChannel = tuple  # (TEXCOORD set, offset u, offset v, rotation, scale u, scale v)
_IDENTITY = (0.0, 0.0, 0.0, 1.0, 1.0)


def texture_infos(material: dict | None) -> dict[str, dict]:
    """The material's textureInfo objects by TEXTURE_FIELDS name (specular-glossiness's
    diffuseTexture is the base colour texture)."""
    if not material:
        return {}
    pbr = material.get("pbrMetallicRoughness") or {}
    extensions = material.get("extensions") or {}
    gloss = extensions.get(_SPECULAR_GLOSSINESS)
    specular = extensions.get("KHR_materials_specular") or {}
    infos = {
        "baseColorTexture": (gloss or {}).get("diffuseTexture") if gloss is not None else pbr.get("baseColorTexture"),
        "metallicRoughnessTexture": None if gloss is not None else pbr.get("metallicRoughnessTexture"),
        "normalTexture": material.get("normalTexture"),
        "occlusionTexture": material.get("occlusionTexture"),
        "emissiveTexture": material.get("emissiveTexture"),
        "specularColorTexture": specular.get("specularColorTexture"),
        "specularTexture": specular.get("specularTexture"),
    }
    return {name: info for name, info in infos.items() if isinstance(info, dict)}


def uv_channel(info: dict, name: str = "textureInfo") -> UvChannel:
    """Which texture coordinates a textureInfo reads: its TEXCOORD set (`texCoord`, which
    KHR_texture_transform's own `texCoord` overrides) and its transform. `name` (the
    texture's, baseColorTexture ...) is in the errors."""
    extensions = info.get("extensions") or {}
    transform = extensions.get("KHR_texture_transform") or {} if isinstance(extensions, dict) else extensions
    if not isinstance(transform, dict):  # a string or a list where the objects belong (assimp's badExtension.gltf)
        where = f"{name}.extensions" + (".KHR_texture_transform" if isinstance(extensions, dict) else "")
        raise ValueError(f"{where}: expected an object, got {reprlib.repr(transform)}")
    uv_set = transform.get("texCoord", info.get("texCoord", 0))
    if isinstance(uv_set, bool) or not isinstance(uv_set, int) or uv_set < 0:
        field = f"{name}.extensions.KHR_texture_transform.texCoord" if "texCoord" in transform else f"{name}.texCoord"
        raise ValueError(f"{field} must be a non-negative integer, got {reprlib.repr(uv_set)}")
    offset = [float(v) for v in transform.get("offset", [0.0, 0.0])]
    scale = [float(v) for v in transform.get("scale", [1.0, 1.0])]
    if len(offset) != 2 or len(scale) != 2:
        raise ValueError("offset and scale must have two numbers each")
    return (uv_set, *offset, float(transform.get("rotation", 0.0)), *scale)


def channel_uvs(uv_sets: dict[int, np.ndarray], channel: UvChannel) -> np.ndarray | None:
    """The channel's texture coordinates: its TEXCOORD set (the reader's, v flipped) with
    KHR_texture_transform applied, uv' = T · R · S · uv in glTF's uv space; None when the
    primitive has no such set."""
    uvs = uv_sets.get(channel[0])
    if uvs is None or channel[1:] == _IDENTITY:
        return uvs
    offset_u, offset_v, rotation, scale_u, scale_v = channel[1:]
    cos, sin = np.cos(rotation), np.sin(rotation)
    linear = np.array([[cos, sin], [-sin, cos]]) @ np.diag([scale_u, scale_v])  # the extension's R · S
    gltf_uv = np.stack([uvs[:, 0], 1.0 - uvs[:, 1]], axis=1) @ linear.T + [offset_u, offset_v]
    return np.stack([gltf_uv[:, 0], 1.0 - gltf_uv[:, 1]], axis=1)
