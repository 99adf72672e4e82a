"""PLY files: the header, its declared counts checked against the file's size before
anything is allocated, and binary point clouds read with numpy (meshes with faces go to
trimesh: trimesh_reader.py).

The header (Paul Bourke's PLY format description) lists elements, each a count and its
properties. A binary PLY whose only non-empty element is `vertex` with scalar
properties (what scanners, Open3D, MeshLab and point-cloud-utils write) is read here in
blocks of rows straight into the arrays a Mesh keeps: trimesh reads the whole file into
memory, then makes float64 copies of it (a 10M-point cloud peaked at 2.5 GB; docs/primitives.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.geometry.mesh import MAX_TRIANGLES
from ..mesh_pieces import MeshFile, point_piece
from .checks import check_declared_counts
from .ply_edges import renamed_edge_file
from .trimesh_reader import read_with_trimesh

PLY_TYPES = {
    "char": "i1", "uchar": "u1", "int8": "i1", "uint8": "u1", "short": "i2", "ushort": "u2", "int16": "i2", "uint16": "u2",
    "int": "i4", "uint": "u4", "int32": "i4", "uint32": "u4", "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}
_PLY_SIZES = {name: int(code[1]) for name, code in PLY_TYPES.items()}
_BLOCK_ROWS = 1 << 20


@dataclass
class PlyElement:
    name: str
    count: int
    properties: list[tuple[str, str, str | None]] = field(default_factory=list)  # (name, type, list count type or None)


@dataclass
class PlyHeader:
    format: str  # ascii | binary_little_endian | binary_big_endian
    elements: list[PlyElement]
    header_bytes: int

    @property
    def binary(self) -> bool:
        return self.format.startswith("binary")

    def count(self, name: str) -> int:
        return next((element.count for element in self.elements if element.name == name), 0)


def read_ply_header(path: Path, where: str) -> PlyHeader:
    with open(path, "rb") as file:
        head = file.read(65536)
    if not head.startswith(b"ply"):
        raise MeshError(f"{where}: not a PLY file (it does not start with 'ply')")
    end = head.find(b"end_header")
    if end < 0:
        raise MeshError(f"{where}: the PLY header has no 'end_header' within its first 64 KiB")
    header_end = head.find(b"\n", end)
    header_bytes = (header_end + 1) if header_end >= 0 else len(head)
    fmt, elements = "ascii", []
    for line in head[:end].decode("latin-1").splitlines():
        words = line.split()
        if words[:1] == ["format"] and len(words) >= 2:
            fmt = words[1]
        elif words[:1] == ["element"] and len(words) >= 3:
            try:
                count = int(words[2])
            except ValueError:
                raise MeshError(f"{where}: bad PLY element count {words[2][:20]!r}") from None
            if count < 0:
                raise MeshError(f"{where}: negative PLY element count {count}")
            elements.append(PlyElement(words[1], count))
        elif words[:1] == ["property"] and elements and len(words) >= 3:
            if words[1] == "list" and len(words) >= 5:
                elements[-1].properties.append((words[4], words[3], words[2]))
            else:
                elements[-1].properties.append((words[2], words[1], None))
    return PlyHeader(fmt, elements, header_bytes)


def ply_declared_counts(path: Path, where: str, file_size: int, header: PlyHeader | None = None) -> tuple[int, int]:
    """The vertex and face counts a PLY header declares, checked against the file size."""
    header = header or read_ply_header(path, where)
    minimum = 0
    for element in header.elements:
        for _, kind, count_kind in element.properties:
            if count_kind is not None:
                # at least the length field and, for faces, three indices
                items = 3 if element.name == "face" else 0
                per_item = (_PLY_SIZES.get(count_kind, 1) + items * _PLY_SIZES.get(kind, 1)) if header.binary else 2 * (1 + items)
            else:
                per_item = _PLY_SIZES.get(kind, 1) if header.binary else 2  # a digit and a separator
            minimum += element.count * per_item
    vertices, faces = header.count("vertex"), header.count("face")
    if header.count("edge") > MAX_TRIANGLES:  # segments cost what triangles cost
        raise MeshError(f"{where}: declares {header.count('edge')} edges; at most {MAX_TRIANGLES} are supported")
    check_declared_counts(where, vertices, faces, minimum, file_size - header.header_bytes)
    return vertices, faces


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
    """A PLY file (assets/meshes.py's reader for .ply): a binary point cloud read here, any
    other PLY through trimesh (trimesh_reader.py); the header's counts are checked against
    the file's size first (checks.py)."""
    where = f"mesh file {str(path)!r}"
    header = read_ply_header(path, where)
    declared = ply_declared_counts(path, where, file_size, header)
    if not is_binary_point_cloud(header):
        edges = renamed_edge_file(path, header.header_bytes) if header.count("edge") else None
        return read_with_trimesh(path, file_size, declared, edges)
    points = read_binary_point_cloud(path, header, where)
    return MeshFile([point_piece(points.positions, points.normals, points.colors, name=path.name)])
