"""PLY and ASCII STL, read through trimesh: its reading turned into one MeshFile, its
exceptions into one-line MeshErrors; a PLY without faces into points (docs/primitives.md),
its triangle strips into triangles (ply_strips.py).
A PLY header's counts are checked against the file's size before trimesh allocates them
(ply.py, which hands trimesh the PLYs it does not read itself)."""

from __future__ import annotations

import warnings
from dataclasses import replace
from pathlib import Path
from typing import BinaryIO

import numpy as np

from ...errors import MeshError
from ..mesh_pieces import MeshFile, MeshPiece, point_piece, with_face_colors
from .checks import describe_load_error, text_source
from .ply_edges import edge_piece
from .ply_strips import strip_triangles
from .ply_triangles import polygon_colors


def read_with_trimesh(path: Path, file_size: int, declared: tuple[int, int] | None = None,
                      renamed_edges: BinaryIO | None = None) -> MeshFile:
    """A PLY or an ASCII STL file (ply.py's reader for PLYs that are not binary point clouds,
    `declared` their header's vertex and face counts, already checked against the file's
    size; stl.py's for ASCII STL). renamed_edges: a PLY with an `edge` element, as
    ply_edges.renamed_edge_file reads it: its edges drawn as lines, over its faces or alone."""
    if renamed_edges is None:
        return MeshFile([_trimesh_piece(_load_trimesh(path, file_size), path, declared)])
    with renamed_edges:
        loaded = _load_trimesh(path, source=renamed_edges)
    raw = loaded.metadata.get("_ply_raw", {}) if isinstance(getattr(loaded, "metadata", None), dict) else {}
    lines = edge_piece(raw, path)
    if lines is not None and not len(raw.get("face", {}).get("data", ())):
        return MeshFile([lines])  # the vertices are the edges' ends, not points of their own
    surface = _trimesh_piece(loaded, path, declared)
    return MeshFile([surface] if lines is None else [surface, lines])


def _load_trimesh(path: Path, file_size: int | None = None, source: BinaryIO | None = None, **options):
    """trimesh's reading of `path` (or of `source`, the file as read through a filter,
    resolving its other files next to `path`), its exceptions turned into one-line MeshErrors."""
    import trimesh  # lazy: trimesh costs ~0.3 s to import

    where = f"mesh file {str(path)!r}"
    try:
        # Text formats are decoded here (UTF-8, else Latin-1): trimesh's own fallback needs
        # the optional charset_normalizer.
        if source is None and file_size is not None:
            source = text_source(path, where, file_size)
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


def _trimesh_piece(loaded, path: Path, declared: tuple[int, int] | None) -> MeshPiece:
    """What trimesh read from `path` as one piece (its header's counts were checked against
    the file size before trimesh allocated them)."""
    import trimesh

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
        points = _point_cloud_piece(loaded, path, declared)
        if "tristrips" not in raw:
            return points
        faces = strip_triangles(raw["tristrips"].get("data"), len(points.positions), path)
        if not len(faces):
            raise MeshError(f"mesh file {str(path)!r}: its triangle strips (element 'tristrips') hold no triangles")
        return replace(points, faces=faces, primitive="triangles", parts=[(0, len(faces), None, path.name)])
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
    if declared is not None and len(faces) < declared[1]:
        # Polygons become one or more triangles each, so a whole file has at least as many.
        # (Not its vertices: trimesh leaves out those no face uses when it splits vertices by
        # their faces' texcoords, and a file cut short among its vertices has no faces left.)
        raise MeshError(
            f"mesh file {str(path)!r}: truncated: the header declares {declared[0]} vertices and {declared[1]} faces, "
            f"the file holds {len(positions)} vertices and {len(faces)} triangles"
        )
    if face_colors is not None and len(face_colors) != len(faces):
        face_colors = _polygon_colors(loaded, face_colors, len(faces), path)
    normals = _file_normals(loaded)
    piece = MeshPiece(positions, faces, normals, uvs, None if colors is None else _unit_colors(colors), parts=[(0, len(faces), None, path.name)])
    return piece if face_colors is None else with_face_colors(piece, _unit_colors(face_colors))


def _polygon_colors(loaded, face_colors: np.ndarray, triangles: int, path: Path) -> np.ndarray | None:
    """A PLY's face colours, one a polygon as trimesh keeps them, given to each triangle it
    cut the polygon into (trimesh gives quads twice as many triangles as colours); None,
    with a warning, where the polygons cannot be told from its raw faces."""
    raw = loaded.metadata.get("_ply_raw", {}).get("face", {}).get("data") if isinstance(loaded.metadata, dict) else None
    indices = None
    if raw is not None and "vertex_indices" in _fields(raw):
        indices = raw["vertex_indices"]
    elif raw is not None and "vertex_index" in _fields(raw):
        indices = raw["vertex_index"]
    if indices is not None:
        indices = np.asarray(indices)
        if indices.dtype.names:  # a binary file's records: (count, indices)
            counts = np.asarray(indices[indices.dtype.names[0]], np.int64).reshape(-1)
        elif indices.ndim == 2:  # an ASCII file's faces of one size
            counts = np.full(len(indices), indices.shape[1])
        else:  # an ASCII file's faces of several sizes, an array each
            counts = np.array([len(face) for face in indices])
        if len(counts) == len(face_colors):
            colors = polygon_colors(counts, face_colors)
            if len(colors) == triangles:
                return colors
    warnings.warn(f"mesh file {str(path)!r}: its {len(face_colors)} face colours do not match its {triangles} triangles; "
                  "drawn without them", stacklevel=2)
    return None


def _point_cloud_piece(loaded, path: Path, declared: tuple[int, int] | None) -> MeshPiece:
    """A PLY without faces: its vertices as points, with their colours and normals (nx ny
    nz) when it has them (docs/primitives.md)."""
    positions = np.asarray(loaded.vertices)
    if declared is not None and len(positions) < declared[0]:
        raise MeshError(f"mesh file {str(path)!r}: truncated: the header declares {declared[0]} vertices, the file holds {len(positions)}")
    raw = loaded.metadata.get("_ply_raw", {}).get("vertex", {}).get("data") if isinstance(loaded.metadata, dict) else None
    normals = None
    if raw is not None and all(name in _fields(raw) for name in ("nx", "ny", "nz")):
        normals = np.stack([np.asarray(raw[name], dtype=np.float32).reshape(-1) for name in ("nx", "ny", "nz")], axis=1)
    colors = np.asarray(loaded.colors) if len(getattr(loaded, "colors", ())) == len(positions) else None
    return point_piece(positions, normals, None if colors is None else _unit_colors(colors), name=path.name)


def _fields(raw) -> tuple[str, ...]:
    """The property names of trimesh's raw PLY element: a structured array (binary) or a dict (ASCII)."""
    names = getattr(getattr(raw, "dtype", None), "names", None)
    return tuple(names) if names else tuple(raw) if isinstance(raw, dict) else ()


def _unit_colors(colors: np.ndarray) -> np.ndarray:
    colors = np.asarray(colors)
    scale = 255.0 if colors.dtype.kind in "iu" else 1.0
    colors = colors.astype(np.float64) / scale
    if colors.shape[1] == 3:
        colors = np.concatenate([colors, np.ones((len(colors), 1))], axis=1)
    return colors[:, :4]
