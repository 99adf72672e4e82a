"""A PLY file's header (Paul Bourke's PLY format description): its format, and its
elements, each a count and its properties; and the counts it declares, checked against the
file's size before anything is allocated (checks.py). The readers: ply.py (point clouds,
and which reader a file goes to), ply_triangles.py, trimesh (trimesh_reader.py)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ...errors import MeshError
from ...scene.geometry.mesh import MAX_TRIANGLES
from .checks import check_declared_counts

PLY_TYPES = {
    "char": "i1", "uchar": "u1", "int8": "i1", "uint8": "u1", "short": "i2", "ushort": "u2", "int16": "i2", "uint16": "u2",
    "int": "i4", "uint": "u4", "int32": "i4", "uint32": "u4", "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}
PLY_SIZES = {name: int(code[1]) for name, code in PLY_TYPES.items()}


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
                per_item = (PLY_SIZES.get(count_kind, 1) + items * PLY_SIZES.get(kind, 1)) if header.binary else 2 * (1 + items)
            else:
                per_item = PLY_SIZES.get(kind, 1) if header.binary else 2  # a digit and a separator
            minimum += element.count * per_item
    vertices, faces = header.count("vertex"), header.count("face")
    if header.count("edge") > MAX_TRIANGLES:  # segments cost what triangles cost
        raise MeshError(f"{where}: declares {header.count('edge')} edges; at most {MAX_TRIANGLES} are supported")
    check_declared_counts(where, vertices, faces, minimum, file_size - header.header_bytes)
    return vertices, faces
