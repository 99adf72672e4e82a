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
from pathlib import Path

import numpy as np

from ..errors import MeshError
from ..scene.builtins import BUILTIN_PREFIX, builtin
from ..scene.mesh import Mesh
from ..scene.view.reading import MAX_SECONDS
from .examples import resolve_example
from .files import check_regular_file
from .mesh_pieces import MeshPiece, assemble, with_face_colors
from .mesh_formats.checks import describe_load_error, file_size_or_error, ply_declared_counts, text_source

MESH_SUFFIXES = (".obj", ".ply", ".stl", ".off", ".glb", ".gltf")
DEFAULT_CREASE_ANGLE = 60.0  # degrees (docs/real-world-files.md)


def load_mesh(source: str | os.PathLike[str], *, crease_angle: float = DEFAULT_CREASE_ANGLE,
              animation_time: float | None = None, animation_index: int | str | None = None) -> Mesh:
    """A built-in (`builtin:torus`), a shipped sample (`example:knot.obj`) or a mesh file
    (OBJ, PLY, STL, OFF, GLB/glTF).

    crease_angle (degrees, 0..180): where the file has no normals, edges sharper than this
    are creases (docs/real-world-files.md); 180 is the plain average of the welded faces, 0 is flat.
    animation_time (seconds): a glTF file as its animation `animation_index` (0 unless given;
    1, 2, ... or "all") poses it then (docs/animation.md); None: as the file's nodes say,
    unanimated, unless an animation_index is given (then its start, time 0)."""
    if animation_index is not None and animation_time is None:
        animation_time = 0.0
    text = resolve_example(str(source))
    if text.startswith(BUILTIN_PREFIX):
        return builtin(text)
    if not (isinstance(crease_angle, (int, float)) and 0.0 <= crease_angle <= 180.0):
        raise MeshError(f"crease_angle: expected a number of degrees between 0 and 180, got {crease_angle!r}")
    if animation_time is not None and not (isinstance(animation_time, (int, float)) and not isinstance(animation_time, bool)
                                           and abs(animation_time) <= MAX_SECONDS):  # NaN fails too
        raise MeshError(f"animation_time: expected a number of seconds (at most {MAX_SECONDS:g} in size), got {animation_time!r}")
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
    notes: list[str] = []  # what the user should be told once the file is read (glTF)
    with np.errstate(all="ignore"):  # bad values become MeshErrors, not warnings on stderr
        if suffix == ".obj":
            from .mesh_formats.obj import read_obj

            data = read_obj(path)
            pieces = [MeshPiece(data.positions, data.faces, data.normals, data.uvs, data.colors, data.flat, parts=data.parts)]
        elif suffix in (".glb", ".gltf"):
            from .gltf.reader import gltf_mesh_pieces

            pieces, notes = gltf_mesh_pieces(path, animation_time, 0 if animation_index is None else animation_index)
        elif suffix == ".stl" and (binary := _binary_stl(path, file_size)) is not None:
            pieces = [binary]
        elif suffix == ".off":
            from .mesh_formats.off import read_off

            off = read_off(path, file_size)
            piece = MeshPiece(off.positions, off.faces, off.normals, off.uvs, off.colors, parts=[(0, len(off.faces), None, path.name)])
            pieces = [piece if off.face_colors is None else with_face_colors(piece, off.face_colors)]
        else:
            pieces = [_trimesh_piece(path, file_size)]
        if animation_time is not None and suffix not in (".glb", ".gltf"):
            notes.append(f"{path.name}: only glTF files hold animations; the animation time {animation_time:g} s is ignored")
        pieces = [p for p in pieces if len(p.faces)]
        mesh = assemble(pieces, path.name, float(crease_angle)) if pieces else None
    for note in dict.fromkeys(notes):  # once each, once the file was read without error (or to say why nothing is left)
        warnings.warn(note, stacklevel=2)
    if mesh is None:
        raise MeshError(f"mesh file {text!r} contains no triangles")
    return mesh


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


def _binary_stl(path: Path, file_size: int) -> MeshPiece | None:
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
    return MeshPiece(positions, faces, parts=[(0, len(faces), None, path.name)])


def _trimesh_piece(path: Path, file_size: int) -> MeshPiece:
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
    piece = MeshPiece(positions, faces, normals, uvs, None if colors is None else _unit_colors(colors), parts=[(0, len(faces), None, path.name)])
    return piece if face_colors is None else with_face_colors(piece, _unit_colors(face_colors))


def _unit_colors(colors: np.ndarray) -> np.ndarray:
    colors = np.asarray(colors)
    scale = 255.0 if colors.dtype.kind in "iu" else 1.0
    colors = colors.astype(np.float64) / scale
    if colors.shape[1] == 3:
        colors = np.concatenate([colors, np.ones((len(colors), 1))], axis=1)
    return colors[:, :4]


