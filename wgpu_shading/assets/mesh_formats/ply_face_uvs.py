"""PLY meshes whose faces carry their corners' texture coordinates: after each
face's vertex indices, a `texcoord` list of two floats a corner, as MeshLab and Agisoft
Metashape export a textured mesh (with `comment TextureFile NAME`). trimesh reads such a
file whole, as every PLY it reads: 13.4x the mesh's arrays at 2M triangles
(`python benchmarks/scripts/load_peak.py 2000000 /tmp/uvs.ply --face-uvs --render 512`).

Read here a block of faces at a time (binary; or ASCII, a block of lines at a time: 59x and
21 s at 2M triangles through trimesh), every face a triangle with its 6 floats, and its
vertices x y z and properties trimesh skips (MeshLab's flags and quality); normals or colours beside the texcoords go to trimesh, which drops them once it
splits vertices. Each vertex is split by the distinct texture coordinates of its corners,
as trimesh splits it (trimesh.visual.texture.unmerge_faces): a vertex per distinct (vertex,
uv), vertices no face uses left out. The texture coordinates are joined by their bits a
block at a time (corner_join.py, as an STL's corners), and the (vertex, uv) pairs made
distinct as an OBJ's (v, vt) are (obj_vertices.CornerTriples: each vertex's first uv its
own, only the others kept a corner), so no array of every corner's uvs or pairs is held.

The same triangles as trimesh's, corner by corner (position and uv), and as many vertices;
where a vertex has several uvs their vertices may come in another order (trimesh orders
them by an unstable sort), and uvs that trimesh merges by rounding them to 8 decimals are
kept apart.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.freed_memory import return_freed_memory
from ...scene.geometry.mesh import MAX_TRIANGLES
from ..files import text_line_blocks
from ..mesh_pieces import MeshPiece
from .corner_join import CornerJoin
from .line_sections import ascii_texts, vertex_and_face_lines
from .obj_vertices import CornerTriples
from .ply_ascii_triangles import line_values
from .ply_header import PlyHeader
from .ply_triangles import BLOCK_ROWS, COLOR_NAMES, file_rows, float_type, mesh_rows, read_vertices


def read_face_uvs(path: Path, header: PlyHeader, file_size: int, where: str) -> MeshPiece | None:
    """The mesh of a PLY in this module's layout, binary or ASCII, or None for any other
    (trimesh reads it)."""
    rows = mesh_rows(header, ">" if header.format == "binary_big_endian" else "<", face_texture=True)
    if rows is None:
        return None
    vertex_row, face_row = rows
    if "nx" in vertex_row.fields or any(name in vertex_row.fields for name in COLOR_NAMES):
        return None
    vertex_count, face_count = header.count("vertex"), header.count("face")
    if face_count > MAX_TRIANGLES:
        raise MeshError(f"{where}: {face_count} faces; at most {MAX_TRIANGLES} triangles are supported")
    split = _UvSplit(vertex_count, face_row.fields["uv"][0].base)
    try:
        if header.format == "ascii":
            positions = _read_ascii(path, header, vertex_row, split, where)
        elif header.format in ("binary_little_endian", "binary_big_endian"):
            if header.header_bytes + vertex_count * vertex_row.itemsize + face_count * face_row.itemsize != file_size:
                return None  # faces of other sizes, or truncated: trimesh reads or names it
            positions = _read_binary(path, header, vertex_row, face_row, split, where)
        else:
            return None
    except OSError as error:
        raise MeshError(f"{where}: cannot be read ({error.strerror or error})") from None
    except MemoryError:
        raise MeshError(f"{where}: not enough memory to read {vertex_count} vertices and {face_count} faces") from None
    return None if positions is None else split.piece(positions, path.name)


class _UvSplit:
    """The faces' corners and uvs, a block at a time; then the vertices split by their uvs."""

    def __init__(self, vertex_count: int, uv_type: np.dtype):
        self.vertex_count = vertex_count
        self.join = CornerJoin(np.float32 if uv_type.itemsize == 4 else np.float64)  # (in this machine's byte order)
        self.triples = CornerTriples()
        self.runs: list = []
        self.uv_ids = 0

    def add(self, corners: np.ndarray, uvs: np.ndarray) -> bool:
        """A block's corners (k,) int64 and their uvs (k, 2); False where the file is not of
        this layout (trimesh then reads it, or names what is wrong)."""
        if not np.isfinite(uvs).all() or (len(corners) and (corners.min() < 0 or corners.max() >= self.vertex_count)):
            return False
        ids = self.join.add(np.column_stack([uvs, np.zeros(len(uvs), uvs.dtype)]))
        self.uv_ids = max(self.uv_ids, int(ids.max(initial=0)) + 1)
        pairs = np.stack([corners, ids.astype(np.int64), np.full(len(ids), -1)], axis=1)  # (v, uv, no vn)
        self.runs.append(self.triples.split(pairs.reshape(-1, 3, 3), self.vertex_count))
        return True

    def piece(self, positions: np.ndarray, name: str) -> MeshPiece:
        combos, faces = self.triples.distinct(self.runs, [0, 1], self.vertex_count)
        self.runs = []
        rank = np.arange(self.uv_ids, dtype=np.uint32)  # each uv's id (in the order met), renumbered to its sorted row
        uv_values = self.join.finish(rank)[rank, :2]
        piece = MeshPiece(positions[combos[:, 0]], faces, None, uv_values[combos[:, 1]], parts=[(0, len(faces), None, name)])
        del combos, uv_values, rank
        return_freed_memory()  # the blocks' and the pairs' arrays, before the crease analysis's
        return piece


def _read_binary(path: Path, header: PlyHeader, vertex_row, face_row, split: _UvSplit, where: str) -> np.ndarray | None:
    positions = np.empty((split.vertex_count, 3), float_type(vertex_row.fields, "xyz"))
    face_count = header.count("face")
    with open(path, "rb") as file:
        file.seek(header.header_bytes)
        read_vertices(file, vertex_row, positions, None, None, where)
        for start in range(0, face_count, BLOCK_ROWS):
            block = file_rows(file, face_row, min(BLOCK_ROWS, face_count - start), where)
            if (block["count"] != 3).any() or (block["uv_count"] != 6).any():
                return None
            if not split.add(block["corners"].reshape(-1).astype(np.int64), block["uv"].reshape(-1, 2)):
                return None
    return positions


def _read_ascii(path: Path, header: PlyHeader, vertex_row, split: _UvSplit, where: str) -> np.ndarray | None:
    """The ASCII file's vertex lines and its face lines (`3 a b c 6 u v u v u v`), a block of
    lines at a time, each value given its property's type as trimesh gives it (as
    ply_ascii_triangles.py reads them)."""
    names = list(vertex_row.names)
    positions = np.empty((split.vertex_count, 3), float_type(vertex_row.fields, "xyz"))
    read = 0  # vertices
    sections = vertex_and_face_lines(ascii_texts(text_line_blocks(path, where, MeshError), skip=header.header_bytes),
                                     split.vertex_count, header.count("face"))
    for section in sections:
        if section is None:
            return None
        vertices = line_values(section[0], len(names)) if section[0] else np.empty((0, len(names)))
        faces = line_values(section[1], 11) if section[1] else np.empty((0, 11))  # 3 a b c 6 u v u v u v
        if vertices is None or faces is None:
            return None
        for column, axis in enumerate("xyz"):
            positions[read : read + len(vertices), column] = vertices[:, names.index(axis)].astype(vertex_row.fields[axis][0])
        read += len(vertices)
        corners = faces[:, 1:4]
        if (faces[:, 0] != 3).any() or (faces[:, 4] != 6).any() or (corners != np.floor(corners)).any():
            return None
        if len(faces) and not split.add(corners.reshape(-1).astype(np.int64), faces[:, 5:].astype(split.join.dtype).reshape(-1, 2)):
            return None
    return positions
