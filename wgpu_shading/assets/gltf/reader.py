"""A glTF file read into a MeshFile (assets/mesh_pieces.py): every primitive instance of
its scene (primitives.py) with its classic material (materials.py) and the texture
coordinates each of its textures reads (extensions.py: a TEXCOORD set with a transform, a
"channel"; the base colour texture's is the mesh's uvs, others its extra_uvs), posed at an
animation time if one is asked for (animations.py; morph targets: morph_targets.py); its
own lights (punctual_lights.py) and cameras (cameras.py) read from the same parsed
document, on the same posed nodes, when the caller asks for them.

Materials are made once per (material, NORMAL present, COLOR_0 present, kind, sets), however many
primitives use them, so a texture is decoded once and a lost one is said once; what the
user should be told is collected in GltfData.notes and said by the loader only once the
file has been read whole (meshes.py), never before the file's own error."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ...errors import MeshError, SceneError
from ...scene.material import MAX_UV_SET, Material
from ..mesh_pieces import MeshFile, MeshPiece
from .animations import posed_nodes
from .cameras import gltf_camera
from .document import GltfData
from .extensions import TEXTURE_FIELDS, channel_uvs, check_extensions, texture_infos, uv_channel
from .materials import gltf_material
from .primitives import gltf_pieces, material_images
from .punctual_lights import gltf_lights


def read_gltf(path: Path, file_size: int | None = None, animation: tuple[float, int | str] | None = None) -> MeshFile:
    """A .gltf or .glb file (its size is checked by GltfData against what it declares);
    animation: (time in seconds, animation index or "all") to pose it at (animations.py)."""
    data = GltfData(path)
    posed = posed_gltf(data, animation)
    data.forget_binary_data()  # (the lights and cameras it keeps it for read only the document)
    return posed


def posed_gltf(data: GltfData, animation: tuple[float, int | str] | None = None) -> MeshFile:
    """A parsed glTF file as read_gltf reads it, posed at `animation` (an animation poses one
    parsed file for every frame: assets/animation_frames.py)."""
    nodes = None if animation is None else posed_nodes(data, *animation)
    pieces, notes = gltf_mesh_pieces(data, nodes)
    return MeshFile(pieces, notes, lights=lambda: gltf_lights(data, nodes), camera=lambda index: gltf_camera(data, index, nodes))


def gltf_mesh_pieces(data: GltfData, nodes: list | None = None) -> tuple[list[MeshPiece], list[str]]:
    """The file's pieces and the notes for the user; `nodes`: the nodes as an animation
    poses them (animations.posed_nodes), else the file's own."""
    path = data.path
    check_extensions(data.document, path)
    materials: dict[tuple, tuple[Material | None, list]] = data.materials  # made once per document
    pieces = []
    for piece in gltf_pieces(data, nodes):
        attributes = piece.primitive["attributes"]
        index = piece.primitive.get("material")
        document_material = None if index is None else data.item("materials", index, f"meshes[{piece.key[0]}].primitives[{piece.key[1]}].material")
        # Lines, and points without normals, are drawn in their colour: base colour × COLOR_0
        # (three.js' LineBasicMaterial and PointsMaterial), without textures (docs/primitives.md).
        unlit = piece.kind == "lines" or (piece.kind == "points" and "NORMAL" not in attributes)
        row = {"has_normal": "NORMAL" in attributes, "has_color": "COLOR_0" in attributes, "material": document_material, "unlit": unlit}
        key = (index, row["has_normal"], row["has_color"], unlit, piece.kind != "triangles", tuple(sorted(piece.uv_sets)))
        if key not in materials:
            materials[key] = _material(data, row, piece, document_material)
        material, channels = materials[key]
        try:
            uv_arrays = [channel_uvs(piece.uv_sets, channel) for channel in channels]
        except (TypeError, ValueError) as error:
            raise MeshError(f"mesh file {str(path)!r}: KHR_texture_transform of {piece.name!r}: {type(error).__name__}: {error}") from None
        if any(not np.isfinite(uvs).all() for uvs in uv_arrays):
            raise MeshError(f"mesh file {str(path)!r}: KHR_texture_transform of {piece.name!r}: the texture coordinates become non-finite")
        normals = piece.normals if row["has_normal"] else None
        # TANGENT is used with the file's normals (never welded) for a normal map.
        tangents = piece.tangents if normals is not None and material is not None and material.normal_map is not None else None
        pieces.append(
            MeshPiece(piece.positions, piece.faces, normals, uv_arrays[0] if uv_arrays else None, piece.colors,
                      all_flat=not row["has_normal"], parts=[(0, piece.element_count, material, piece.name)], tangents=tangents,
                      primitive=piece.kind, extra_uvs=np.stack(uv_arrays[1:], axis=1) if len(uv_arrays) > 1 else None)
        )
    return pieces, data.notes


def _channels(document_material: dict | None, images, uv_sets, path: Path, piece_name: str) -> tuple[list, dict[str, int | None]]:
    """The texture coordinate channels a material's textures read (extensions.uv_channel:
    a TEXCOORD set and a transform), the base colour texture's first, and each Material
    texture field's channel (None: its set is not in the primitive, the field is dropped)."""
    try:
        wanted = {name: uv_channel(info, name) for name, info in texture_infos(document_material).items()}
    except (AttributeError, TypeError, ValueError) as error:
        raise MeshError(f"mesh file {str(path)!r}: texture coordinates of {piece_name!r}: {error}") from None
    loaded = {name: channel for name, channel in wanted.items() if getattr(images, name, None) is not None}
    if "baseColorTexture" not in loaded and "metallicRoughnessTexture" in loaded:
        loaded["baseColorTexture"] = loaded["metallicRoughnessTexture"]  # the diffuse factor's own texture (materials.py)
    if "metallicRoughnessTexture" in loaded:  # specular textures are folded into its texels
        loaded.pop("specularColorTexture", None), loaded.pop("specularTexture", None)
    channels: list = []
    fields: dict[str, int | None] = {}
    for name, channel in loaded.items():
        if channel[0] not in uv_sets or (channel not in channels and len(channels) > MAX_UV_SET):
            number = None  # a set the primitive lacks, or beyond the sets a draw can read
        else:
            if channel not in channels:
                channels.append(channel)
            number = channels.index(channel)
        for field in TEXTURE_FIELDS[name]:
            fields[field] = number
    return channels, fields


def _with_channels(material: Material, fields: dict[str, int | None]) -> Material:
    """Each texture of `material` reading its channel (Texture.uv_set); a texture whose
    TEXCOORD set the primitive lacks is left out."""
    changes = {}
    for field in ("texture", *material.maps):
        texture = getattr(material, field)
        if texture is None:
            continue
        number = fields.get(field, 0)
        changes[field] = None if number is None else replace(texture, uv_set=number) if number else texture
    return replace(material, **changes) if changes else material


def _material(data: GltfData, row: dict, piece, document_material) -> tuple[Material | None, list]:
    """The primitive's classic material with its textures on their channels, and the channels."""
    try:
        images = material_images(data, row["material"], data.path.name) if row["material"] is not None else None
        material = gltf_material(data.document, row, images, data.path.name, data.notes)
    except (SceneError, AttributeError, TypeError, ValueError, KeyError, IndexError) as error:
        if isinstance(error, MeshError):
            raise
        # A hostile document's material (a list where an object belongs, a string factor, a
        # colour beyond the limits): one line naming the file.
        detail = str(error) if isinstance(error, SceneError) else f"{type(error).__name__}: {error}"
        raise MeshError(f"mesh file {str(data.path)!r}: material of {piece.name!r}: {detail}") from None
    if piece.kind != "triangles":  # lines and points are drawn in their colour, untextured
        return replace(material, texture=None, **{name: None for name in material.maps}), []
    channels, fields = _channels(document_material, images, piece.uv_sets, data.path, piece.name)
    for field in (field for field, number in fields.items() if number is None):
        data.notes.append(f"{data.path.name}: {piece.name!r}: its {field} reads a TEXCOORD set the primitive does not have "
                          f"(or a {MAX_UV_SET + 2}th set of texture coordinates and transform); drawn without it")
    return _with_channels(material, fields), channels
