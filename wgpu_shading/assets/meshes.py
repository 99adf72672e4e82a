"""Mesh files (OBJ/MTL, PLY, STL, OFF, glTF/GLB) into one Mesh with one part per material.

OBJ is read by mesh_formats/obj.py (trimesh's OBJ reader mis-resolves relative indices and drops
smoothing groups); OFF by mesh_formats/off.py (a token stream: trimesh wanted one face per line);
PLY and STL by trimesh; glTF by our own accessor reader (gltf/).
Every format ends as "pieces" (vertex arrays with their parts), whose normals follow
docs/real-world-files.md: the file's normals win; glTF primitives without NORMAL are flat; otherwise
vertices are welded by position and split at the crease angle (scene/normals.py).
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..errors import MeshError, SceneError
from ..scene.builtins import BUILTIN_PREFIX, builtin
from ..scene.material import Material
from ..scene.mesh import Mesh, MeshPart, face_normals
from ..scene.normals import crease_normals
from .examples import resolve_example
from .files import check_regular_file
from .mesh_formats.checks import describe_load_error, file_size_or_error, ply_declared_counts, text_source

MESH_SUFFIXES = (".obj", ".ply", ".stl", ".off", ".glb", ".gltf")
DEFAULT_CREASE_ANGLE = 60.0  # degrees (docs/real-world-files.md)


@dataclass
class _Piece:
    """One vertex set of a file: an OBJ, a glTF primitive instance, a PLY."""

    positions: np.ndarray
    faces: np.ndarray
    normals: np.ndarray | None = None
    uvs: np.ndarray | None = None
    colors: np.ndarray | None = None  # (n, 4) float in [0, 1]
    flat: np.ndarray | None = None  # (f,) bool: faces that are always flat
    all_flat: bool = False
    parts: list = field(default_factory=list)  # (first face, count, material, name)
    tangents: np.ndarray | None = None  # (n, 4) glTF TANGENT, only with the file's normals


def load_mesh(source: str | os.PathLike[str], *, crease_angle: float = DEFAULT_CREASE_ANGLE) -> Mesh:
    """A built-in (`builtin:torus`), a shipped sample (`example:knot.obj`) or a mesh file
    (OBJ, PLY, STL, OFF, GLB/glTF).

    crease_angle (degrees, 0..180): where the file has no normals, edges sharper than this
    are creases (docs/real-world-files.md); 180 is the plain average of the welded faces, 0 is flat."""
    text = resolve_example(str(source))
    if text.startswith(BUILTIN_PREFIX):
        return builtin(text)
    if not (isinstance(crease_angle, (int, float)) and 0.0 <= crease_angle <= 180.0):
        raise MeshError(f"crease_angle: expected a number of degrees between 0 and 180, got {crease_angle!r}")
    if "\x00" in text:
        raise MeshError(f"mesh file {text!r}: a path cannot contain a NUL character")
    path = Path(text)
    if not path.exists():
        raise MeshError(f"mesh file {text!r} not found")
    check_regular_file(path, f"mesh file {text!r}", MeshError)  # a folder, FIFO or device: refused unread
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise MeshError(f"mesh file {text!r}: unsupported format {path.suffix!r}; expected one of {', '.join(MESH_SUFFIXES)}")
    file_size = file_size_or_error(path, f"mesh file {text!r}")  # size limit, before anything is read
    with np.errstate(all="ignore"):  # bad values become MeshErrors, not warnings on stderr
        if suffix == ".obj":
            from .mesh_formats.obj import read_obj

            data = read_obj(path)
            pieces = [_Piece(data.positions, data.faces, data.normals, data.uvs, data.colors, data.flat, parts=data.parts)]
        elif suffix in (".glb", ".gltf"):
            pieces = _gltf_pieces(path)
        elif suffix == ".stl" and (binary := _binary_stl(path, file_size)) is not None:
            pieces = [binary]
        elif suffix == ".off":
            from .mesh_formats.off import read_off

            off = read_off(path, file_size)
            piece = _Piece(off.positions, off.faces, off.normals, off.uvs, off.colors, parts=[(0, len(off.faces), None, path.name)])
            pieces = [piece if off.face_colors is None else _with_face_colors(piece, off.face_colors)]
        else:
            pieces = [_trimesh_piece(path, file_size)]
        pieces = [p for p in pieces if len(p.faces)]
        if not pieces:
            raise MeshError(f"mesh file {text!r} contains no triangles")
        return _assemble(pieces, path.name, float(crease_angle))


# --------------------------------------------------------------------------- trimesh formats


def _load_trimesh(path: Path, file_size: int | None = None, content: bytes | None = None, **options):
    """trimesh's reading of `path` (or of `content`, the file rewritten, resolving its
    other files next to `path`), its exceptions turned into one-line MeshErrors."""
    import io

    import trimesh  # lazy: trimesh costs ~0.3 s to import

    where = f"mesh file {str(path)!r}"
    try:
        # Text formats are decoded here (UTF-8, else Latin-1): trimesh's own fallback needs
        # the optional charset_normalizer.
        source = text_source(path, where, file_size) if file_size is not None else None
        if content is not None:
            source = io.BytesIO(content)
        if source is None:
            return trimesh.load(str(path), process=False, **options)
        resolver = trimesh.resolvers.FilePathResolver(str(path))
        return trimesh.load(source, file_type=path.suffix.lower().lstrip("."), process=False, resolver=resolver, **options)
    except MeshError:
        raise
    except IndexError as error:  # trimesh indexes vertices with the file's face indices
        raise MeshError(f"{where}: a face refers to a vertex that does not exist ({error})") from None
    except (Exception, RecursionError) as error:  # trimesh raises many exception types for malformed files
        raise MeshError(f"{where}: {describe_load_error(error, path)}") from None


def _file_normals(geometry) -> np.ndarray | None:
    """Normals the file gave (trimesh caches them only then); never trimesh's computed ones,
    which take minutes on big meshes without scipy."""
    normals = geometry._cache.cache.get("vertex_normals")
    if normals is not None and np.shape(normals) == np.shape(geometry.vertices):
        return np.asarray(normals, dtype=np.float64)
    return None


def _binary_stl(path: Path, file_size: int) -> _Piece | None:
    """A binary STL read with numpy (mesh_formats/stl.py); None for ASCII STL (read by trimesh)."""
    from .mesh_formats.stl import binary_stl_count, read_binary_stl

    where = f"mesh file {str(path)!r}"
    try:
        count = binary_stl_count(path, where, file_size)
        if count is None:
            return None
        positions, faces = read_binary_stl(path, count)
    except OSError as error:
        raise MeshError(f"{where}: cannot be read ({error.strerror or error})") from None
    except MemoryError:
        raise MeshError(f"{where}: not enough memory to read {file_size} bytes of STL") from None
    return _Piece(positions, faces, parts=[(0, len(faces), None, path.name)])


def _trimesh_piece(path: Path, file_size: int) -> _Piece:
    import trimesh

    # A PLY header's counts are checked against the file size before trimesh allocates them.
    declared = ply_declared_counts(path, f"mesh file {str(path)!r}", file_size) if path.suffix.lower() == ".ply" else None
    loaded = _load_trimesh(path, file_size)
    if isinstance(loaded, trimesh.Scene):
        geometries = [g for g in loaded.dump() if isinstance(g, trimesh.Trimesh)]
        if not geometries:
            raise MeshError(f"mesh file {str(path)!r}: contains no triangles (no mesh in the file)")
        # Several bodies (an ASCII STL with several `solid`s, as CAD tools export
        # assemblies): one mesh, as f3d and every slicer show them; STL/OFF/PLY carry no
        # materials that could tell the bodies apart.
        loaded = geometries[0] if len(geometries) == 1 else trimesh.util.concatenate(geometries)
    if isinstance(loaded, trimesh.PointCloud):
        raw = loaded.metadata.get("_ply_raw", {}) if isinstance(loaded.metadata, dict) else {}
        if "tristrips" in raw:
            raise MeshError(f"mesh file {str(path)!r}: the PLY has triangle strips (element 'tristrips'), not faces; only 'face' elements are supported")
        raise MeshError(f"mesh file {str(path)!r}: a point cloud ({len(loaded.vertices)} vertices, no faces); nothing to shade")
    if not isinstance(loaded, trimesh.Trimesh):
        raise MeshError(f"mesh file {str(path)!r}: contains no triangles (found {type(loaded).__name__})")
    positions = np.asarray(loaded.vertices, dtype=np.float64)
    faces = np.asarray(loaded.faces, dtype=np.int64)
    visual = loaded.visual
    uvs = getattr(visual, "uv", None)
    uvs = np.asarray(uvs, dtype=np.float64) if uvs is not None and len(uvs) == len(positions) else None
    colors, face_colors = None, None
    kind = getattr(visual, "kind", None)
    if isinstance(visual, trimesh.visual.ColorVisuals):
        if kind == "vertex":
            colors = np.asarray(visual.vertex_colors)
        elif kind == "face":
            face_colors = np.asarray(visual.face_colors)  # no scipy: expanded below, never averaged
    else:  # TextureVisuals keep PLY colors as attributes
        vertex_attribute = getattr(visual, "vertex_attributes", {}).get("color")
        face_attribute = loaded.face_attributes.get("color") if hasattr(loaded, "face_attributes") else None
        if vertex_attribute is not None and len(vertex_attribute) == len(positions):
            colors = np.asarray(vertex_attribute)
        elif face_attribute is not None and len(face_attribute) == len(faces):
            face_colors = np.asarray(face_attribute)
    if declared is not None and (len(positions) < declared[0] or len(faces) < declared[1]):
        # Polygons become one or more triangles each, so a whole file has at least as many.
        raise MeshError(
            f"mesh file {str(path)!r}: truncated: the header declares {declared[0]} vertices and {declared[1]} faces, "
            f"the file holds {len(positions)} vertices and {len(faces)} triangles"
        )
    normals = _file_normals(loaded)
    piece = _Piece(positions, faces, normals, uvs, None if colors is None else _unit_colors(colors), parts=[(0, len(faces), None, path.name)])
    return piece if face_colors is None else _with_face_colors(piece, _unit_colors(face_colors))


def _with_face_colors(piece: _Piece, face_colors: np.ndarray) -> _Piece:
    """One colour per face, unblended: every corner its own vertex (MeshLab; averaging
    into vertices would blur the faces' colours)."""
    corners = piece.faces.reshape(-1)
    return replace(
        piece,
        positions=piece.positions[corners],
        faces=np.arange(len(corners)).reshape(-1, 3),
        normals=None if piece.normals is None else piece.normals[corners],
        uvs=None if piece.uvs is None else piece.uvs[corners],
        colors=np.repeat(face_colors, 3, axis=0),
    )


def _unit_colors(colors: np.ndarray) -> np.ndarray:
    colors = np.asarray(colors)
    scale = 255.0 if colors.dtype.kind in "iu" else 1.0
    colors = colors.astype(np.float64) / scale
    if colors.shape[1] == 3:
        colors = np.concatenate([colors, np.ones((len(colors), 1))], axis=1)
    return colors[:, :4]


# --------------------------------------------------------------------------- glTF


def _gltf_pieces(path: Path) -> list[_Piece]:
    from .gltf.extensions import check_extensions, gltf_material, transform_uvs
    from .gltf.document import GltfData
    from .gltf.primitives import gltf_pieces, material_images

    data = GltfData(path)
    check_extensions(data.document, path)
    materials: dict[tuple[int, int], Material | None] = {}
    pieces = []
    for piece in gltf_pieces(data):
        attributes = piece.primitive["attributes"]
        index = piece.primitive.get("material")
        document_material = None if index is None else data.item("materials", index, f"meshes[{piece.key[0]}].primitives[{piece.key[1]}].material")
        row = {"has_normal": "NORMAL" in attributes, "has_color": "COLOR_0" in attributes, "material": document_material}
        if piece.key not in materials:
            try:
                images = material_images(data, document_material, path.name) if document_material is not None else None
                materials[piece.key] = gltf_material(data.document, row, images, path.name)
            except (SceneError, AttributeError, TypeError, ValueError, KeyError, IndexError) as error:
                if isinstance(error, MeshError):
                    raise
                # A hostile document's material (a list where an object belongs, a string
                # factor, a colour beyond the limits): one line naming the file.
                detail = str(error) if isinstance(error, SceneError) else f"{type(error).__name__}: {error}"
                raise MeshError(f"mesh file {str(path)!r}: material of {piece.name!r}: {detail}") from None
        uvs = piece.uvs
        if uvs is not None:
            try:
                uvs = transform_uvs(uvs, document_material)
            except (AttributeError, TypeError, ValueError, KeyError, IndexError) as error:
                raise MeshError(f"mesh file {str(path)!r}: KHR_texture_transform of {piece.name!r}: {type(error).__name__}: {error}") from None
            if not np.isfinite(uvs).all():
                raise MeshError(f"mesh file {str(path)!r}: KHR_texture_transform of {piece.name!r}: the texture coordinates become non-finite")
        normals = piece.normals if row["has_normal"] else None
        material = materials[piece.key]
        if uvs is None and material is not None and material.maps:  # maps need texture coordinates
            material = replace(material, **{key: None for key in material.maps})
        # TANGENT is used with the file's normals (never welded) for a normal map.
        tangents = piece.tangents if normals is not None and material is not None and material.normal_map is not None else None
        pieces.append(
            _Piece(piece.positions, piece.faces, normals, uvs, piece.colors, all_flat=not row["has_normal"],
                   parts=[(0, len(piece.faces), material, piece.name)], tangents=tangents)
        )
    return pieces


# --------------------------------------------------------------------------- assembly


def _piece_normals(piece: _Piece, crease_angle: float) -> _Piece:
    """The piece with normals: the file's, flat, or welded and creased."""
    if piece.normals is not None:
        return piece
    if piece.all_flat:  # every corner its own vertex, with its face's normal
        corners = piece.faces.reshape(-1)
        unit, _ = face_normals(piece.positions, piece.faces)
        return replace(
            piece,
            positions=piece.positions[corners],
            faces=np.arange(len(corners)).reshape(-1, 3),
            normals=np.repeat(unit, 3, axis=0),
            uvs=None if piece.uvs is None else piece.uvs[corners],
            colors=None if piece.colors is None else piece.colors[corners],
        )
    source, faces, normals = crease_normals(piece.positions, piece.faces, crease_angle, piece.flat)
    if source is None:
        return replace(piece, normals=normals)
    return replace(
        piece,
        positions=piece.positions[source],
        faces=faces,
        normals=normals,
        uvs=None if piece.uvs is None else piece.uvs[source],
        colors=None if piece.colors is None else piece.colors[source],
    )


def _check_piece(piece: _Piece, name: str) -> None:
    """What normals and welding index with must be valid first (trimesh reads PLY, STL and
    OFF faces without checking them, process=False): finite positions, indices in range."""
    if piece.faces.ndim != 2 or piece.faces.shape[1] != 3:
        raise MeshError(f"{name}: faces must be triangles, got an array of shape {piece.faces.shape}")
    if not np.isfinite(piece.positions).all():
        bad = int(np.flatnonzero(~np.isfinite(piece.positions).all(axis=1))[0])
        raise MeshError(f"{name}: vertex {bad} has a NaN or infinite coordinate: {piece.positions[bad].tolist()}")
    low, high = int(piece.faces.min()), int(piece.faces.max())
    if low < 0 or high >= len(piece.positions):
        culprit = low if low < 0 else high
        raise MeshError(
            f"{name}: a face refers to vertex {culprit}, but the file has {len(piece.positions)} vertices "
            f"(valid: 0..{len(piece.positions) - 1})"
        )


def _assemble(pieces: list[_Piece], name: str, crease_angle: float) -> Mesh:
    for piece in pieces:
        _check_piece(piece, name)
    pieces = [_piece_normals(piece, crease_angle) for piece in pieces]
    any_uvs = any(p.uvs is not None for p in pieces)
    any_colors = any(p.colors is not None for p in pieces)
    any_tangents = any(p.tangents is not None for p in pieces)
    positions, faces, normals, uvs, colors, tangents, parts = [], [], [], [], [], [], []
    vertex_offset = face_offset = 0
    for piece in pieces:
        count = len(piece.positions)
        positions.append(piece.positions)
        faces.append(piece.faces + vertex_offset if vertex_offset else piece.faces)  # one piece: no copy
        normals.append(piece.normals)
        if any_uvs:
            uvs.append(piece.uvs if piece.uvs is not None else np.zeros((count, 2)))
        if any_colors:
            colors.append(piece.colors if piece.colors is not None else np.ones((count, 4)))
        if any_tangents:  # zeros: no tangent, the derivative frame
            tangents.append(piece.tangents if piece.tangents is not None else np.zeros((count, 4)))
        for first, length, material, part_name in piece.parts:
            if material is not None and material.texture is not None and piece.uvs is None:
                warnings.warn(f"{name}: part {part_name!r} has a texture but no texture coordinates; drawn untextured", stacklevel=3)
                material = replace(material, texture=None)
            parts.append(MeshPart(face_offset + first, length, material, part_name))
        vertex_offset += count
        face_offset += len(piece.faces)
    def joined(arrays: list) -> np.ndarray:  # one piece (a PLY, an STL): no copy
        return arrays[0] if len(arrays) == 1 else np.concatenate(arrays)

    return Mesh.from_arrays(
        joined(positions),
        joined(faces),
        normals=joined(normals),
        uvs=joined(uvs) if any_uvs else None,
        colors=joined(colors) if any_colors else None,
        tangents=joined(tangents) if any_tangents else None,
        parts=tuple(parts),
        name=name,
    )
