"""glTF 2.0 (.gltf/.glb) materials and extensions; the geometry is read by document.py
(buffers, accessors), nodes.py (node graph, skins) and primitives.py (primitives).

Materials: materials.py (linear colours, metallic-roughness with maps, the default material).
KHR_texture_transform on the base color texture is applied to the uvs (texCoord ignored).
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
            from ...errors import install_hint

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
