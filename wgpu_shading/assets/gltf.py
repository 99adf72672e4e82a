"""glTF 2.0 (.gltf/.glb) through trimesh, plus what trimesh drops, read from the file's JSON.

trimesh builds one geometry per primitive (meshes, then primitives, in file order; modes
other than points/lines/triangles/strips skipped) and keeps that order in scene.geometry,
so the JSON's primitive table pairs with it one to one. From the JSON come: whether a
primitive has NORMAL (without it glTF says flat shading), COLOR_0, alphaMode/alphaCutoff,
KHR_materials_unlit, KHR_materials_specular, sampler filters and Draco compression.
Instances come from the scene graph, each with its node's world transform.

Materials: gltf_material.py (linear colours, metallic-roughness with maps, the default material).
KHR_texture_transform on the base color texture is applied to the uvs (texCoord ignored).
"""

from __future__ import annotations

import copy
import json
import struct
from pathlib import Path

import numpy as np

from ..errors import MeshError
from .gltf_material import SPECULAR_GLOSSINESS as _SPECULAR_GLOSSINESS
from .gltf_material import gltf_material  # noqa: F401 (the loader's entry point for materials)

_KEPT_MODES = {0, 1, 4, 5}


def read_gltf_json(path: Path) -> dict:
    raw = path.read_bytes()
    try:
        if raw[:4] == b"glTF":
            length, _ = struct.unpack_from("<II", raw, 12)
            document = json.loads(raw[20 : 20 + length])
        else:
            document = json.loads(raw)
    except (ValueError, struct.error) as error:
        raise MeshError(f"mesh file {str(path)!r}: not a valid glTF file ({error})") from None
    except RecursionError:
        raise MeshError(f"mesh file {str(path)!r}: not a valid glTF file (its JSON is nested too deeply)") from None
    if not isinstance(document, dict):  # every later step reads it as an object
        raise MeshError(f"mesh file {str(path)!r}: not a valid glTF file (expected a JSON object, got {type(document).__name__})")
    return document


def check_extensions(document: dict, path: Path) -> None:
    """Draco needs DracoPy (the `draco` extra); without it trimesh returns all-zero
    geometry, which renders as a black image: an error instead."""
    used = set(document.get("extensionsUsed", [])) | set(document.get("extensionsRequired", []))
    if "KHR_draco_mesh_compression" in used:
        try:
            import DracoPy  # noqa: F401
        except ImportError:
            from ..errors import install_hint

            raise MeshError(
                f"mesh file {str(path)!r} uses Draco mesh compression (KHR_draco_mesh_compression); "
                f"to decode it, {install_hint('draco')}"
            ) from None
    unsupported = set(document.get("extensionsRequired", [])) - {
        "KHR_draco_mesh_compression", "KHR_materials_unlit", "KHR_texture_transform", "KHR_mesh_quantization",
    }
    if unsupported:
        raise MeshError(f"mesh file {str(path)!r} requires glTF extension(s) this renderer cannot decode: {', '.join(sorted(unsupported))}")


def without_specular_glossiness(path: Path, document: dict) -> bytes | None:
    """The file's bytes with each specular-glossiness material's diffuse factor and texture
    put where trimesh reads a base color; None when no material uses the extension.

    trimesh converts the extension to metallic-roughness itself (trimesh.visual.gloss),
    baking the specular color into a new base color texture: a grey, washed-out box where
    f3d and the extension's viewers show the diffuse texture. gltf_material maps the
    extension directly (from the untouched document); trimesh only decodes the image."""
    if not any(_SPECULAR_GLOSSINESS in m.get("extensions", {}) for m in document.get("materials", [])):
        return None
    rewritten = copy.deepcopy(document)
    for material in rewritten["materials"]:
        extension = material.get("extensions", {}).pop(_SPECULAR_GLOSSINESS, None)
        if extension is None:
            continue
        pbr = {"baseColorFactor": extension.get("diffuseFactor", [1.0, 1.0, 1.0, 1.0]), "metallicFactor": 0.0}
        if "diffuseTexture" in extension:
            pbr["baseColorTexture"] = extension["diffuseTexture"]
        material["pbrMetallicRoughness"] = pbr
    text = json.dumps(rewritten).encode()
    raw = path.read_bytes()
    if raw[:4] != b"glTF":
        return text
    old_length, _ = struct.unpack_from("<II", raw, 12)
    text += b" " * (-len(text) % 4)  # GLB chunks are 4-byte aligned; JSON pads with spaces
    rest = raw[20 + old_length :]
    return b"glTF" + struct.pack("<II", 2, 20 + len(text) + len(rest)) + struct.pack("<I", len(text)) + b"JSON" + text + rest


def transform_uvs(uvs: np.ndarray, material: dict | None) -> np.ndarray:
    """trimesh's uvs with the base color texture's KHR_texture_transform applied (trimesh
    ignores it: the extension's test file showed its own "not supported" tiles).
    uv' = T · R · S · uv in glTF's uv space, whose v trimesh has flipped (v = 1 − v_glTF)."""
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


def primitive_table(document: dict) -> list[dict]:
    """One row per primitive trimesh turns into a geometry, in trimesh's order."""
    rows = []
    materials = document.get("materials", [])
    for mesh in document.get("meshes", []):
        for primitive in mesh.get("primitives", []):
            if primitive.get("mode", 4) not in _KEPT_MODES:
                continue
            attributes = primitive.get("attributes", {})
            index = primitive.get("material")
            rows.append(
                {
                    "has_normal": "NORMAL" in attributes,
                    "has_color": "COLOR_0" in attributes,
                    "material": materials[index] if index is not None and index < len(materials) else None,
                }
            )
    return rows
