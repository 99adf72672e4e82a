"""ASCII PLY triangle meshes read a block of lines at a time (files.text_line_blocks), in
the layout ply_triangles.py reads in binary: a vertex a line, then `3 a b c` a face a line.

trimesh reads an ASCII PLY as a Python string per line and a numpy array per line: a
2M-triangle ASCII PLY peaked at 28x its mesh's arrays and took 7 s. Here each block's
numbers are read in C (number_text.py), exactly as strtod reads them, then given each
property's type, as trimesh gives them (every value through float64, then the property's
type: `float` coordinates are float32), so the Mesh is the same (tests/test_ply_triangles.py).
Anything else in the data (a blank line, a row of another length, a colour outside
0..255, a polygon, rows after the faces) sends the file to trimesh, which reads it as before.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.freed_memory import return_freed_memory
from ..files import text_line_blocks
from ..mesh_pieces import MeshPiece
from .number_text import parse_floats, parse_numbers
from .ply_header import PlyHeader
from .ply_triangles import COLOR_NAMES, mesh_arrays, mesh_rows

BLOCK_BYTES = 4 << 20  # the blocks of lines read at a time (as an OBJ's)


def read_ascii_triangles(path: Path, header: PlyHeader, where: str) -> MeshPiece | None:
    """The mesh of an ASCII PLY in the layout of ply_triangles.py, or None for any other."""
    rows = mesh_rows(header, "<") if header.format == "ascii" else None
    if rows is None:
        return None
    vertex_row, face_row = rows
    vertex_count, face_count = header.count("vertex"), header.count("face")
    positions, normals, colors, faces = mesh_arrays(vertex_row, face_row, vertex_count, face_count)
    names = list(vertex_row.names)
    columns = {name: names.index(name) for name in names}
    channels = [name for name in COLOR_NAMES if name in columns]
    vertices_read = faces_read = 0
    for text in _texts(path, header.header_bytes, where):
        if text is None:
            return None
        lines = text.split("\n")
        if lines[-1] == "":
            lines.pop()
        wanted = min(len(lines), vertex_count - vertices_read)
        if wanted:
            values = parse_floats("\n".join(lines[:wanted]))
            if values is None or values.size != len(names) * wanted:
                return None
            values = values.reshape(wanted, len(names))
            rows_read = slice(vertices_read, vertices_read + wanted)
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
            vertices_read += wanted
        face_lines = lines[wanted:]
        while face_lines and faces_read + len(face_lines) > face_count and not face_lines[-1].strip():
            face_lines.pop()  # blank lines after the last face
        if not face_lines:
            continue
        if faces_read + len(face_lines) > face_count:
            return None
        numbers = parse_numbers("\n".join(face_lines), np.int64)
        if numbers is None or numbers.size != 4 * len(face_lines):
            return None
        triangles = numbers.reshape(len(face_lines), 4)
        info = np.iinfo(faces.dtype)
        if (triangles[:, 0] != 3).any() or triangles[:, 1:].min() < info.min or triangles[:, 1:].max() > info.max:
            return None
        faces[faces_read : faces_read + len(face_lines)] = triangles[:, 1:]
        faces_read += len(face_lines)
    if vertices_read != vertex_count or faces_read != face_count:
        return None
    if header.header_bytes + 4 * BLOCK_BYTES < path.stat().st_size:  # several blocks: their temporaries given back
        return_freed_memory()
    return MeshPiece(positions, faces, normals, colors=colors, parts=[(0, face_count, None, path.name)])


def _texts(path: Path, header_bytes: int, where: str):
    """The text of the data's blocks of lines, past the header; None for a block that is
    not ASCII (trimesh then reads the file)."""
    blocks = text_line_blocks(path, where, MeshError, BLOCK_BYTES)
    skipped = 0
    for block in blocks:
        if skipped < header_bytes:  # (the header is whole lines: a block ends at it or beyond)
            block, skipped = block[header_bytes - skipped :], skipped + len(block)
            if not block:
                continue
        try:
            yield block.decode("ascii")
        except UnicodeDecodeError:
            yield None
            return
