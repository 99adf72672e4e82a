"""Binary PLY meshes whose faces are polygons of several sizes: triangles and quads, or
n-gons, as Blender's PLY exporter writes a mesh (it keeps n-gons) and MeshLab or VTK a
quad-dominant one.

trimesh cannot read them: its binary reader takes every face to be the size of the first
("if you mixed triangles and quads this won't work at all", trimesh/exchange/ply.py) and
refused the file as "PLY is unexpected length!". Here the vertices are read as
ply_triangles.py reads them (the same layout: one list property of indices, then scalars,
as MeshLab writes its flags and quality, read past, or a uchar colour, which every
triangle of its face gets; and texture coordinates, which Blender writes as `s t`: one pair
per vertex, as the file gives them, in its order of vertices), and the faces in blocks of
bytes: a Python loop finds where each face's record starts (its count says how long it
is: ~0.1 µs a face), then numpy gathers the indices (and the scalars) of the block's faces
of each size. Two passes over the faces: the first counts the triangles (and refuses what
is too big before any array is made), the second fills them in.

They are cut as trimesh cuts an ASCII PLY of mixed faces (trimesh.geometry.triangulate_quads,
which tests/test_ply_polygons.py compares with): every triangle in file order, then every
quad's (a, b, c), then every quad's (c, d, a), then each larger polygon's fan from its
first corner, one polygon after the other; faces of fewer than 3 corners are left out, as
trimesh leaves them out.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np

from ...errors import MeshError
from ...scene.geometry.mesh import MAX_TRIANGLES
from ..mesh_pieces import MeshPiece, polygon_fans, with_face_colors
from .checks import MAX_FACE_CORNERS
from .ply_header import PlyHeader
from .ply_triangles import face_color_fields, float_type, mesh_arrays, mesh_rows, polygon_colors, read_vertices, texture_pair

BLOCK_BYTES = 8 << 20  # face bytes read at a time (a face of MAX_FACE_CORNERS 8-byte indices fits)


def read_polygons(path: Path, header: PlyHeader, file_size: int, where: str) -> MeshPiece | None:
    """The mesh of a binary PLY in ply_triangles.py's layout whose faces are of several sizes,
    or None for any other PLY (trimesh reads it, or says why not)."""
    if not header.binary:
        return None
    order = "<" if header.format == "binary_little_endian" else ">"
    rows = mesh_rows(header, order, texture=True, face_scalars=True)
    if rows is None:
        return None
    vertex_row, face_row = rows
    vertices, faces = header.count("vertex"), header.count("face")
    faces_at = header.header_bytes + vertices * vertex_row.itemsize
    count_type, index_type = face_row.fields["count"][0], face_row.fields["corners"][0].base
    # The scalars after each face's indices (MeshLab's flags and quality, a colour): a record's tail.
    tail = np.dtype([(name, face_row.fields[name][0]) for name in face_row.names if name not in ("count", "corners")])
    records = FaceRecords(count_type, index_type, faces, where, tail)
    with open(path, "rb") as file:
        file.seek(faces_at)
        sizes = records.sizes(file)  # (triangles, quads, larger polygons' triangles)
        triangles = sizes[0] + 2 * sizes[1] + sizes[2]
        if triangles > MAX_TRIANGLES:
            raise MeshError(f"{where}: its {faces} faces make {triangles} triangles; at most {MAX_TRIANGLES} are supported")
        try:
            positions, normals, colors, out = mesh_arrays(vertex_row, face_row, vertices, triangles)
            pair = texture_pair(vertex_row.names)
            uvs = None if pair is None else np.empty((vertices, 2), float_type(vertex_row.fields, pair))
        except MemoryError:
            raise MeshError(f"{where}: not enough memory to read {vertices} vertices and {faces} faces") from None
        file.seek(header.header_bytes)
        read_vertices(file, vertex_row, positions, normals, colors, where, uvs)
        color_fields = face_color_fields(face_row) if colors is None else []  # (vertex colours win, as in ply_triangles.py)
        face_colors = records.cut(file, out, sizes, color_fields)
    piece = MeshPiece(positions, out, normals, uvs, colors=colors, parts=[(0, len(out), None, path.name)])
    return piece if face_colors is None else with_face_colors(piece, face_colors)  # every triangle its polygon's colour


class FaceRecords:
    """The face records of a binary PLY: a count, then that many indices, then the scalars
    of `tail` (none by default), `faces` of them."""

    def __init__(self, count_type: np.dtype, index_type: np.dtype, faces: int, where: str, tail: np.dtype = np.dtype([])):
        self.count_type, self.index_type, self.faces, self.where, self.tail = count_type, index_type, faces, where, tail

    def _blocks(self, file):
        """(bytes, starts, counts) of each block of whole records, in order; a MeshError
        when the file ends inside a record or has bytes after the last one."""
        count_bytes, index_bytes = self.count_type.itemsize, self.index_type.itemsize
        carry, found = b"", 0
        while found < self.faces:
            chunk = file.read(BLOCK_BYTES)
            if not chunk:
                raise MeshError(f"{self.where}: the file ends inside its faces ({found} of {self.faces} read)")
            data = carry + chunk
            starts, counts, end = self._scan(data, found, count_bytes, index_bytes)
            found += len(starts)
            carry = data[end:]
            if len(starts):
                yield np.frombuffer(data, np.uint8), np.array(starts, np.int64), np.array(counts, np.int64)
        if carry or file.read(1):
            raise MeshError(f"{self.where}: bytes after its {self.faces} faces (a PLY of vertices and faces ends with its last face)")

    def _scan(self, data: bytes, found: int, count_bytes: int, index_bytes: int):
        """Where each whole record of `data` starts and its count (up to the file's last
        face: `found` are read before these), and where the first record not whole starts.
        A plain loop: each record's place depends on the count before it."""
        starts, counts = [], []
        place, length, wanted = 0, len(data), self.faces - found
        signed, big = self.count_type.kind == "i", self.count_type.byteorder == ">"
        while len(starts) < wanted and place + count_bytes <= length:
            if count_bytes == 1 and not signed:
                count = data[place]
            else:
                count = int.from_bytes(data[place : place + count_bytes], "big" if big else "little", signed=signed)
            if count < 0:
                raise MeshError(f"{self.where}: face {found + len(starts)} has a negative corner count ({count})")
            if count > MAX_FACE_CORNERS:  # (said from its count, as an OBJ's: trimesh took 2.4 GB to one of 12M)
                raise MeshError(f"{self.where}: face {found + len(starts)} has {count} corners; at most {MAX_FACE_CORNERS} are supported")
            end = place + count_bytes + count * index_bytes + self.tail.itemsize
            if end > length:
                break
            starts.append(place)
            counts.append(count)
            place = end
        return starts, counts, place

    def sizes(self, file) -> tuple[int, int, int]:
        """The first pass: (triangles, quads, the triangles of larger polygons)."""
        totals = (0, 0, 0)
        for _, _, counts in self._blocks(file):
            totals = tuple(total + more for total, more in zip(totals, kind_counts(counts)))
        return totals

    def cut(self, file, out: np.ndarray, sizes: tuple[int, int, int], color_fields: list[str] = ()) -> np.ndarray | None:
        """The second pass: every face cut into its rows of `out` (the module docstring).
        With `color_fields` (a face's colour among its scalars), each triangle's colour in
        the rows' order (polygon_colors), else None."""
        placed = MixedCut(out, sizes)
        counts_read, colors_read = [], []
        for data, starts, counts in self._blocks(file):
            placed.add(counts, lambda chosen, size, data=data, starts=starts: self._indices(data, starts[chosen], size))
            if color_fields:
                tails = self._tails(data, starts, counts)
                counts_read.append(counts.astype(np.min_scalar_type(MAX_FACE_CORNERS)))
                colors_read.append(np.stack([tails[field] for field in color_fields], axis=1))
        return polygon_colors(np.concatenate(counts_read), np.concatenate(colors_read)) if color_fields else None

    def _tails(self, data: np.ndarray, starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
        """The `tail` scalars of the records at `starts`, of these counts (a structured array)."""
        at = starts + self.count_type.itemsize + counts * self.index_type.itemsize
        windows = np.lib.stride_tricks.sliding_window_view(data, self.tail.itemsize)
        return np.ascontiguousarray(windows[at]).view(self.tail).reshape(len(starts))

    def _indices(self, data: np.ndarray, starts: np.ndarray, size: int) -> np.ndarray:
        """(len(starts), size) indices of the records at `starts`, each `size` corners."""
        count_bytes, index_bytes = self.count_type.itemsize, self.index_type.itemsize
        if not len(starts):
            return np.empty((0, size), self.index_type)
        width = size * index_bytes
        windows = np.lib.stride_tricks.sliding_window_view(data, width)
        return np.ascontiguousarray(windows[starts + count_bytes]).view(self.index_type).reshape(len(starts), size)


def kind_counts(counts: np.ndarray) -> tuple[int, int, int]:
    """(triangles, quads, the triangles of larger polygons) of faces of these corner counts."""
    larger = counts[counts > 4]
    return int(np.count_nonzero(counts == 3)), int(np.count_nonzero(counts == 4)), int((larger - 2).sum())


class MixedCut:
    """Faces of several sizes placed as trimesh cuts them (the module docstring), a block of
    faces at a time, into `out`, whose size the totals of kind_counts over every face give."""

    def __init__(self, out: np.ndarray, sizes: tuple[int, int, int]):
        self.out, (self.triangles, self.quads, _) = out, sizes
        self.done = {3: 0, 4: 0, "larger": self.triangles + 2 * self.quads}  # where each kind goes next

    def add(self, counts: np.ndarray, polygons_of: Callable[[np.ndarray, int], np.ndarray]) -> None:
        """The next faces, of these corner counts: polygons_of(chosen, size) gives the
        (n, size) indices of the chosen ones (a boolean mask over them), all of that size."""
        out, triangles, quads = self.out, self.triangles, self.quads
        for size in (3, 4):
            polygons, at = polygons_of(counts == size, size), self.done[size]
            if size == 3:
                out[at : at + len(polygons)] = polygons
            else:
                out[triangles + at : triangles + at + len(polygons)] = polygons[:, [0, 1, 2]]
                out[triangles + quads + at : triangles + quads + at + len(polygons)] = polygons[:, [2, 3, 0]]
            self.done[size] += len(polygons)
        larger = counts > 4
        if larger.any():  # fans in file order: each polygon's rows after the one before
            fan_rows = counts[larger] - 2
            first_row = self.done["larger"] + np.cumsum(fan_rows) - fan_rows
            chosen_larger = np.flatnonzero(larger)
            for size in np.unique(counts[larger]):
                mine = counts[larger] == size
                chosen = np.zeros(len(counts), bool)
                chosen[chosen_larger[mine]] = True
                fans = polygon_fans(polygons_of(chosen, int(size)))
                out[(first_row[mine][:, None] + np.arange(size - 2)).reshape(-1)] = fans
            self.done["larger"] += int(fan_rows.sum())
