"""A glTF file read into a MeshFile (assets/mesh_pieces.py): every primitive instance of
its scene (primitives.py) with its classic material (materials.py), its texture
coordinates transformed (extensions.py), posed at an animation time if one is asked for
(animations.py; morph targets: morph_targets.py); its own lights (punctual_lights.py) and
cameras (cameras.py) read from the same parsed document, on the same posed nodes, when the
caller asks for them.

Materials are made once per (material, NORMAL present, COLOR_0 present), however many
primitives use them, so a texture is decoded once and a lost one is said once; what the
user should be told is collected in GltfData.notes and said by the loader only once the
file has been read whole (meshes.py), never before the file's own error."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ...errors import MeshError, SceneError
from ...scene.material import Material
from ..mesh_pieces import MeshFile, MeshPiece
from .animations import posed_nodes
from .cameras import gltf_camera
from .document import GltfData
from .extensions import check_extensions, transform_uvs
from .materials import gltf_material
from .primitives import gltf_pieces, material_images
from .punctual_lights import gltf_lights


def read_gltf(path: Path, file_size: int | None = None, animation: tuple[float, int | str] | None = None) -> MeshFile:
    """A .gltf or .glb file (its size is checked by GltfData against what it declares);
    animation: (time in seconds, animation index or "all") to pose it at (animations.py)."""
    return posed_gltf(GltfData(path), animation)


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
    materials: dict[tuple, Material | None] = data.materials  # made once per document
    pieces = []
    for piece in gltf_pieces(data, nodes):
        attributes = piece.primitive["attributes"]
        index = piece.primitive.get("material")
        document_material = None if index is None else data.item("materials", index, f"meshes[{piece.key[0]}].primitives[{piece.key[1]}].material")
        row = {"has_normal": "NORMAL" in attributes, "has_color": "COLOR_0" in attributes, "material": document_material}
        key = (index, row["has_normal"], row["has_color"])
        if key not in materials:
            materials[key] = _material(data, row, piece.name)
        uvs = piece.uvs
        if uvs is not None:
            try:
                uvs = transform_uvs(uvs, document_material)
            except (AttributeError, TypeError, ValueError, KeyError, IndexError) as error:
                raise MeshError(f"mesh file {str(path)!r}: KHR_texture_transform of {piece.name!r}: {type(error).__name__}: {error}") from None
            if not np.isfinite(uvs).all():
                raise MeshError(f"mesh file {str(path)!r}: KHR_texture_transform of {piece.name!r}: the texture coordinates become non-finite")
        normals = piece.normals if row["has_normal"] else None
        material = materials[key]
        if uvs is None and material is not None and material.maps:  # maps need texture coordinates
            material = replace(material, **{name: None for name in material.maps})
        # TANGENT is used with the file's normals (never welded) for a normal map.
        tangents = piece.tangents if normals is not None and material is not None and material.normal_map is not None else None
        pieces.append(
            MeshPiece(piece.positions, piece.faces, normals, uvs, piece.colors, all_flat=not row["has_normal"],
                      parts=[(0, len(piece.faces), material, piece.name)], tangents=tangents)
        )
    return pieces, data.notes


def _material(data: GltfData, row: dict, piece_name: str) -> Material | None:
    try:
        images = material_images(data, row["material"], data.path.name) if row["material"] is not None else None
        return gltf_material(data.document, row, images, data.path.name, data.notes)
    except (SceneError, AttributeError, TypeError, ValueError, KeyError, IndexError) as error:
        if isinstance(error, MeshError):
            raise
        # A hostile document's material (a list where an object belongs, a string factor, a
        # colour beyond the limits): one line naming the file.
        detail = str(error) if isinstance(error, SceneError) else f"{type(error).__name__}: {error}"
        raise MeshError(f"mesh file {str(data.path)!r}: material of {piece_name!r}: {detail}") from None
