"""PLY files: which reader reads each, once the header's declared counts are checked
against the file's size (ply_header.py), and binary point clouds read with numpy.

A binary PLY whose only non-empty element is `vertex` with scalar properties (what
scanners, Open3D, MeshLab and point-cloud-utils write) is read here in blocks of rows
straight into the arrays a Mesh keeps: trimesh reads the whole file into memory, then makes
float64 copies of it (a 10M-point cloud peaked at 2.5 GB; docs/primitives.md). A binary
mesh of faces of one size (triangles, quads, ...) is read the same way by ply_triangles.py,
an ASCII triangle mesh a block of lines at a time by ply_ascii_triangles.py; any other PLY
by trimesh (trimesh_reader.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import MeshError
from ..mesh_pieces import MeshFile, point_piece
from .ply_ascii_triangles import read_ascii_triangles
from .ply_edges import renamed_edge_file
from .ply_face_uvs import read_face_uvs
from .ply_header import PLY_TYPES, PlyHeader, ply_declared_counts, read_ply_header
from .ply_polygons import read_polygons
from .ply_triangles import read_triangles, triangle_layout
from .trimesh_reader import read_with_trimesh

_BLOCK_ROWS = 1 << 20


def is_binary_point_cloud(header: PlyHeader) -> bool:
    """Binary, every element but `vertex` empty, the vertex's properties scalars of known types with x, y, z."""
    if not header.binary or header.format not in ("binary_little_endian", "binary_big_endian"):
        return False
    vertex = [element for element in header.elements if element.name == "vertex"]
    if len(vertex) != 1 or any(element.count for element in header.elements if element.name != "vertex"):
        return False
    names = [name for name, _, _ in vertex[0].properties]
    return (all(kind in PLY_TYPES and count is None for _, kind, count in vertex[0].properties)
            and {"x", "y", "z"} <= set(names) and len(set(names)) == len(names))


@dataclass
class PlyPoints:
    positions: np.ndarray  # (n, 3) float32, or float64 where the file stores doubles
    normals: np.ndarray | None  # (n, 3) float32 (nx ny nz)
    colors: np.ndarray | None  # (n, 3 or 4) uint8 (uchar red green blue [alpha]) or float32


def read_binary_point_cloud(path: Path, header: PlyHeader, where: str) -> PlyPoints:
    """The vertex element of a binary point cloud (is_binary_point_cloud), a block of rows at a time."""
    (vertex,) = [element for element in header.elements if element.name == "vertex"]
    order = "<" if header.format == "binary_little_endian" else ">"
    record = np.dtype([(name, order + PLY_TYPES[kind]) for name, kind, _ in vertex.properties])
    fields = record.fields
    count = vertex.count
    position_type = np.float64 if any(fields[axis][0].itemsize == 8 for axis in "xyz") else np.float32
    positions = np.empty((count, 3), position_type)
    normals = np.empty((count, 3), np.float32) if {"nx", "ny", "nz"} <= set(fields) else None
    channels = [name for name in ("red", "green", "blue", "alpha") if name in fields]
    colors = None
    if channels[:3] == ["red", "green", "blue"]:
        integer = all(fields[name][0].kind == "u" and fields[name][0].itemsize == 1 for name in channels)
        colors = np.empty((count, len(channels)), np.uint8 if integer else np.float32)
    try:
        with open(path, "rb") as file:
            file.seek(header.header_bytes)
            for start in range(0, count, _BLOCK_ROWS):
                rows = min(_BLOCK_ROWS, count - start)
                block = np.fromfile(file, record, rows)
                if len(block) < rows:
                    raise MeshError(f"{where}: truncated: the header declares {count} vertices, the file holds {start + len(block)}")
                for column, axis in enumerate("xyz"):
                    positions[start : start + rows, column] = block[axis]
                if normals is not None:
                    for column, axis in enumerate(("nx", "ny", "nz")):
                        normals[start : start + rows, column] = block[axis]
                if colors is not None:
                    for column, channel in enumerate(channels):
                        colors[start : start + rows, column] = block[channel]
    except OSError as error:
        raise MeshError(f"{where}: cannot be read ({error.strerror or error})") from None
    except MemoryError:
        raise MeshError(f"{where}: not enough memory to read {count} points") from None
    return PlyPoints(positions, normals, colors)


def read_ply(path: Path, file_size: int) -> MeshFile:
    """A PLY file (assets/meshes.py's reader for .ply): a binary point cloud read here, a
    binary mesh of faces of one size by ply_triangles.py (of several by ply_polygons.py,
    with texcoord lists by ply_face_uvs.py), any other PLY through trimesh
    (trimesh_reader.py); the header's counts are checked against the file's size first."""
    where = f"mesh file {str(path)!r}"
    header = read_ply_header(path, where)
    declared = ply_declared_counts(path, where, file_size, header)
    if not is_binary_point_cloud(header):
        layout = triangle_layout(header, file_size)
        triangles = read_triangles(path, layout, where) if layout is not None else read_ascii_triangles(path, header, where)
        if triangles is None:  # a binary mesh of faces of several sizes (trimesh reads only one size)
            triangles = read_polygons(path, header, file_size, where)
        if triangles is None:  # a binary mesh whose faces carry their corners' texture coordinates
            triangles = read_face_uvs(path, header, file_size, where)
        if triangles is not None:
            return MeshFile([triangles], self_contained=True)  # (a TextureFile comment is not read)
        edges = renamed_edge_file(path, header.header_bytes) if header.count("edge") else None
        return read_with_trimesh(path, file_size, declared, edges)
    points = read_binary_point_cloud(path, header, where)
    return MeshFile([point_piece(points.positions, points.normals, points.colors, name=path.name)], self_contained=True)
