"""ASCII PLY meshes read a block of lines at a time (files.text_line_blocks), in the layout
ply_triangles.py reads in binary: a vertex a line, then a face a line (`3 a b c`, `4 a b c d`,
...), cut into triangles as trimesh cuts them.

trimesh reads an ASCII PLY as a Python string per line and a numpy array per line: a
2M-triangle ASCII PLY peaked at 28x its mesh's arrays and took 7 s. Here each block's
numbers are read in C (number_text.py), exactly as strtod reads them, then given each
property's type, as trimesh gives them (every value through float64, then the property's
type: `float` coordinates are float32), so the Mesh is the same (tests/test_ply_triangles.py).
Faces of several sizes are counted by kind in a first pass (each line's numbers must be its
count and that many indices), then read again and cut as ply_polygons.py cuts a binary
file's, as trimesh cuts this one. Faces followed by scalar properties (MeshLab's flags and
quality: `3 a b c 0 0.5`) are read when all are of one size, the scalars read past. Anything else in the data (a blank line, a row of another
length, a colour outside 0..255, rows after the faces) sends the file to trimesh, which
reads it as before.
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
from .number_text import LEADING_COUNT, leading_counts, parse_floats, parse_numbers
from .ply_polygons import MixedCut, kind_counts
from .ply_header import PlyHeader
from .ply_triangles import COLOR_NAMES, cut_polygons, face_color_fields, fan_count, mesh_arrays, mesh_rows, skipped_scalars


def read_ascii_triangles(path: Path, header: PlyHeader, where: str) -> MeshPiece | None:
    """The mesh of an ASCII PLY in the layout of ply_triangles.py, or None for any other."""
    rows = mesh_rows(header, "<", face_scalars=True) if header.format == "ascii" else None
    if rows is None:
        return None
    vertex_row, face_row = rows
    if face_color_fields(face_row):
        return None  # (face colours in ASCII: trimesh)
    scalars = skipped_scalars(face_row)  # after each face's lists (MeshLab's flags)
    vertex_count, face_count = header.count("vertex"), header.count("face")
    positions, normals, colors, faces = mesh_arrays(vertex_row, face_row, vertex_count, 0)  # (faces: once their size is read)
    corners = mixed = None  # every face's size; or, once faces of several sizes are met, their kind_counts
    names = list(vertex_row.names)
    vertices_read = faces_read = 0
    texts = ascii_texts(text_line_blocks(path, where, MeshError), skip=header.header_bytes)
    for section in vertex_and_face_lines(texts, vertex_count, face_count):
        if section is None:
            return None
        vertex_lines, face_lines = section
        if vertex_lines:
            values = line_values(vertex_lines, len(names))
            if values is None:
                return None
            if not vertex_values(values, vertex_row, slice(vertices_read, vertices_read + len(vertex_lines)), positions, normals, colors):
                return None
            vertices_read += len(vertex_lines)
        if not face_lines:
            continue
        first = LEADING_COUNT.match(face_lines[0]) if corners is None else None
        if first is not None and int(first.group(1)) > MAX_FACE_CORNERS:  # before its numbers are read (trimesh: 1.7 GB for 12M)
            raise MeshError(f"{where}: a face of {int(first.group(1))} corners; at most {MAX_FACE_CORNERS} are supported")
        if scalars:  # faces of one size only, their scalars read past
            if corners is None:
                corners = int(first.group(1)) if first is not None else -1
                if not 3 <= corners <= MAX_FACE_CORNERS:
                    return None
                if fan_count(corners, face_count) > MAX_TRIANGLES:  # (before the array is made; trimesh would hold the text)
                    raise MeshError(f"{where}: {face_count} faces of {corners} corners make {fan_count(corners, face_count)} "
                                    f"triangles; at most {MAX_TRIANGLES} are supported")
                faces = np.empty((fan_count(corners, face_count), 3), faces.dtype)
            polygons = _polygons_before_scalars(face_lines, corners, scalars, faces.dtype)
            if polygons is None:
                return None
            cut_polygons(polygons, faces_read, face_count, faces)
            faces_read += len(face_lines)
            continue
        numbers = parse_numbers("\n".join(face_lines), np.int64)
        if numbers is None or not numbers.size:
            return None
        info = np.iinfo(faces.dtype)
        if numbers.min() < info.min or numbers.max() > info.max:
            return None
        if mixed is None and corners is None:  # every face the first one's size, or faces of several sizes
            corners = int(numbers[0])
            if 3 <= corners <= MAX_FACE_CORNERS and fan_count(corners, face_count) <= MAX_TRIANGLES:
                faces = np.empty((fan_count(corners, face_count), 3), faces.dtype)
            else:
                corners = -1  # (no face of that size: the faces' own counts decide, below)
        if mixed is None and numbers.size == (corners + 1) * len(face_lines):
            polygons = numbers.reshape(len(face_lines), corners + 1)
            if (polygons[:, 0] == corners).all():
                cut_polygons(polygons[:, 1:], faces_read, face_count, faces)
                faces_read += len(face_lines)
                continue
        records = leading_counts(face_lines, numbers)  # faces of several sizes: counted now, cut in a second pass
        if records is None:
            return None
        if mixed is None:  # the blocks before were all faces of `corners` corners
            faces = np.empty((0, 3), faces.dtype)
            mixed = tuple(faces_read * kind for kind in kind_counts(np.array([corners])))
        counts, _ = records
        if counts.max() > MAX_FACE_CORNERS:
            raise MeshError(f"{where}: face {faces_read + int(np.argmax(counts > MAX_FACE_CORNERS))} has "
                            f"{int(counts.max())} corners; at most {MAX_FACE_CORNERS} are supported")
        mixed = tuple(total + more for total, more in zip(mixed, kind_counts(counts)))
        faces_read += len(face_lines)
    if mixed is not None:
        faces = _mixed_faces(path, header, where, mixed, faces.dtype)
    if path.stat().st_size > TEXT_BLOCK_BYTES:  # several blocks: their temporaries given back
        return_freed_memory()
    return MeshPiece(positions, faces, normals, colors=colors, parts=[(0, len(faces), None, path.name)])


def vertex_values(values: np.ndarray, vertex_row: np.dtype, rows: slice, positions, normals, colors) -> bool:
    """A block of vertex lines' values (line_values) into rows `rows` of the arrays made by
    mesh_arrays, each value given its property's type first, as trimesh gives it; False
    where a colour is not a whole number in 0..255 (trimesh then reads the file)."""
    names = list(vertex_row.names)
    for array, axes in ((positions, "xyz"), (normals, ("nx", "ny", "nz"))):
        for column, axis in enumerate(axes if array is not None else ()):
            array[rows, column] = values[:, names.index(axis)].astype(vertex_row.fields[axis][0])
    for column, channel in enumerate(name for name in COLOR_NAMES if name in names):
        channel_values = values[:, names.index(channel)]
        if channel_values.min(initial=0) < 0 or channel_values.max(initial=0) > 255 or (channel_values % 1).any():
            return False
        colors[rows, column] = channel_values
    return True


def _polygons_before_scalars(face_lines: list[str], corners: int, scalars: int, index_type) -> np.ndarray | None:
    """The indices of face lines `n i1 .. in s1 .. sk` (n = corners, k = scalars), or None
    when a line is of another form (trimesh then reads the file, or names what is wrong)."""
    values = line_values(face_lines, 1 + corners + scalars)
    if values is None or (values[:, 0] != corners).any():
        return None
    polygons = values[:, 1 : corners + 1]
    info = np.iinfo(index_type)
    if (polygons != np.floor(polygons)).any() or polygons.min() < info.min or polygons.max() > info.max:
        return None
    return polygons.astype(index_type)


def line_values(lines: list[str], width: int) -> np.ndarray | None:
    """A block of lines' numbers, (lines, width) float64, read in C; None when they are not
    `width` numbers a line (trimesh then reads the file)."""
    values = parse_floats("\n".join(lines))
    if values is None or values.size != width * len(lines):
        return None
    return values.reshape(len(lines), width)


def _mixed_faces(path: Path, header: PlyHeader, where: str, sizes: tuple[int, int, int], index_type) -> np.ndarray:
    """The second pass over an ASCII PLY of faces of several sizes: its face lines read
    again, a block at a time, and cut as ply_polygons.py cuts a binary file's (as trimesh
    cuts this one)."""
    triangles = sizes[0] + 2 * sizes[1] + sizes[2]
    if triangles > MAX_TRIANGLES:
        raise MeshError(f"{where}: its {header.count('face')} faces make {triangles} triangles; at most {MAX_TRIANGLES} are supported")
    faces = np.empty((triangles, 3), index_type)
    placed = MixedCut(faces, sizes)
    texts = ascii_texts(text_line_blocks(path, where, MeshError), skip=header.header_bytes)
    for section in vertex_and_face_lines(texts, header.count("vertex"), header.count("face")):
        if section is None:  # (the first pass read it: the file changed since)
            raise MeshError(f"{where}: changed while it was read")
        face_lines = section[1]
        if not face_lines:
            continue
        numbers = parse_numbers("\n".join(face_lines), np.int64)
        records = None if numbers is None else leading_counts(face_lines, numbers)
        if records is None:
            raise MeshError(f"{where}: changed while it was read")
        counts, first = records
        placed.add(counts, lambda chosen, size, numbers=numbers, first=first: numbers[first[chosen][:, None] + 1 + np.arange(size)])
    return faces
