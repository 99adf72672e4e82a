"""ASCII PLY meshes read a block of lines at a time (files.text_line_blocks), in the layout
ply_triangles.py reads in binary: a vertex a line, then a face a line, every face of one size
(`3 a b c`, `4 a b c d`, ...), cut into triangles as trimesh cuts them.

trimesh reads an ASCII PLY as a Python string per line and a numpy array per line: a
2M-triangle ASCII PLY peaked at 28x its mesh's arrays and took 7 s. Here each block's
numbers are read in C (number_text.py), exactly as strtod reads them, then given each
property's type, as trimesh gives them (every value through float64, then the property's
type: `float` coordinates are float32), so the Mesh is the same (tests/test_ply_triangles.py).
Anything else in the data (a blank line, a row of another length, a colour outside
0..255, faces of several sizes, rows after the faces) sends the file to trimesh, which reads
it as before.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.freed_memory import return_freed_memory
from ...scene.geometry.mesh import MAX_TRIANGLES
from ..files import TEXT_BLOCK_BYTES, text_line_blocks
from ..mesh_pieces import MeshPiece
from .checks import MAX_FACE_CORNERS
from .line_sections import ascii_texts, vertex_and_face_lines
from .number_text import LEADING_COUNT, parse_floats, parse_numbers
from .ply_header import PlyHeader
from .ply_triangles import COLOR_NAMES, cut_polygons, fan_count, mesh_arrays, mesh_rows


def read_ascii_triangles(path: Path, header: PlyHeader, where: str) -> MeshPiece | None:
    """The mesh of an ASCII PLY in the layout of ply_triangles.py, or None for any other."""
    rows = mesh_rows(header, "<") if header.format == "ascii" else None
    if rows is None:
        return None
    vertex_row, face_row = rows
    vertex_count, face_count = header.count("vertex"), header.count("face")
    positions, normals, colors, faces = mesh_arrays(vertex_row, face_row, vertex_count, 0)  # (faces: once their size is read)
    corners = None
    names = list(vertex_row.names)
    columns = {name: names.index(name) for name in names}
    channels = [name for name in COLOR_NAMES if name in columns]
    vertices_read = faces_read = 0
    texts = ascii_texts(text_line_blocks(path, where, MeshError), skip=header.header_bytes)
    for section in vertex_and_face_lines(texts, vertex_count, face_count):
        if section is None:
            return None
        vertex_lines, face_lines = section
        if vertex_lines:
            values = parse_floats("\n".join(vertex_lines))
            if values is None or values.size != len(names) * len(vertex_lines):
                return None
            values = values.reshape(len(vertex_lines), len(names))
            rows_read = slice(vertices_read, vertices_read + len(vertex_lines))
            for column, axis in enumerate("xyz"):  # each value given its property's type first, as trimesh gives it
                positions[rows_read, column] = values[:, columns[axis]].astype(vertex_row.fields[axis][0])
            if normals is not None:
                for column, axis in enumerate(("nx", "ny", "nz")):
                    normals[rows_read, column] = values[:, columns[axis]].astype(vertex_row.fields[axis][0])
            for column, channel in enumerate(channels):
                channel_values = values[:, columns[channel]]
                if channel_values.min() < 0 or channel_values.max() > 255 or (channel_values % 1).any():
                    return None
                colors[rows_read, column] = channel_values
            vertices_read += len(vertex_lines)
        if not face_lines:
            continue
        first = LEADING_COUNT.match(face_lines[0]) if corners is None else None
        if first is not None and int(first.group(1)) > MAX_FACE_CORNERS:  # before its numbers are read (trimesh: 1.7 GB for 12M)
            raise MeshError(f"{where}: a face of {int(first.group(1))} corners; at most {MAX_FACE_CORNERS} are supported")
        numbers = parse_numbers("\n".join(face_lines), np.int64)
        if numbers is None or not numbers.size:
            return None
        if corners is None:  # every face the first one's size, or trimesh reads the file
            corners = int(numbers[0])
            if not 3 <= corners <= MAX_FACE_CORNERS or fan_count(corners, face_count) > MAX_TRIANGLES:
                return None
            faces = np.empty((fan_count(corners, face_count), 3), faces.dtype)
        if numbers.size != (corners + 1) * len(face_lines):
            return None
        polygons = numbers.reshape(len(face_lines), corners + 1)
        info = np.iinfo(faces.dtype)
        if (polygons[:, 0] != corners).any() or polygons[:, 1:].min() < info.min or polygons[:, 1:].max() > info.max:
            return None
        cut_polygons(polygons[:, 1:], faces_read, face_count, faces)
        faces_read += len(face_lines)
    if path.stat().st_size > TEXT_BLOCK_BYTES:  # several blocks: their temporaries given back
        return_freed_memory()
    return MeshPiece(positions, faces, normals, colors=colors, parts=[(0, len(faces), None, path.name)])
