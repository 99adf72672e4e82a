"""PLY meshes whose faces carry their corners' texture coordinates: after each
face's vertex indices, a `texcoord` list of two floats a corner, as MeshLab and Agisoft
Metashape export a textured mesh (with `comment TextureFile NAME`). trimesh reads such a
file whole, as every PLY it reads: 13.4x the mesh's arrays at 2M triangles
(`python benchmarks/scripts/load_peak.py 2000000 /tmp/uvs.ply --face-uvs --render 512`).

Read here a block of faces at a time (binary; or ASCII, a block of lines at a time: 59x and
21 s at 2M triangles through trimesh), every face a triangle with its 6 floats, and its
vertices x y z and properties trimesh skips (MeshLab's flags and quality), their normals and
RGB(A) colours (trimesh drops those once it splits vertices: here each split vertex keeps its
file vertex's, as VTK's PLY reader, f3d's, keeps them), and scalar face properties after
the texcoords (Metashape's `texnumber`, MeshLab's flags), read past; a binary face's uchar
colour (VCGLIB's) makes every corner its own vertex with its face's colour, as trimesh does
(even where the vertices have colours too: trimesh then draws the faces').
Each vertex is split by the distinct texture coordinates of its corners,
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
from ..mesh_pieces import MeshPiece, with_face_colors
from .corner_join import CornerJoin
from .line_sections import ascii_texts, vertex_and_face_lines
from .obj_vertices import CornerTriples
from .ply_ascii_triangles import line_values, vertex_values
from .ply_header import PlyHeader
from .ply_triangles import BLOCK_ROWS, face_color_fields, file_rows, mesh_arrays, mesh_rows, read_face_colors, read_vertices, skipped_scalars


def read_face_uvs(path: Path, header: PlyHeader, file_size: int, where: str) -> MeshPiece | None:
    """The mesh of a PLY in this module's layout, binary or ASCII, or None for any other
    (trimesh reads it)."""
    binary = header.format in ("binary_little_endian", "binary_big_endian")
    rows = mesh_rows(header, ">" if header.format == "binary_big_endian" else "<", face_texture=True, face_scalars=True)
    if rows is None:
        return None
    vertex_row, face_row = rows
    color_fields = face_color_fields(face_row)
    if color_fields and not binary:
        return None  # (face colours in ASCII: trimesh)
    vertex_count, face_count = header.count("vertex"), header.count("face")
    if face_count > MAX_TRIANGLES:
        raise MeshError(f"{where}: {face_count} faces; at most {MAX_TRIANGLES} triangles are supported")
    split = _UvSplit(vertex_count, face_row.fields["uv"][0].base, face_count if color_fields else 0, color_fields)
    try:
        vertices = mesh_arrays(vertex_row, face_row, vertex_count, 0)[:3]  # positions, normals, colours
        if header.format == "ascii":
            read = _read_ascii(path, header, vertex_row, face_row, vertices, split, where)
        elif binary:
            if header.header_bytes + vertex_count * vertex_row.itemsize + face_count * face_row.itemsize != file_size:
                return None  # faces of other sizes, or truncated: trimesh reads or names it
            read = _read_binary(path, header, vertex_row, face_row, vertices, split, where)
        else:
            return None
    except OSError as error:
        raise MeshError(f"{where}: cannot be read ({error.strerror or error})") from None
    except MemoryError:
        raise MeshError(f"{where}: not enough memory to read {vertex_count} vertices and {face_count} faces") from None
    return split.piece(vertices, path.name) if read else None


class _UvSplit:
    """The faces' corners and uvs, a block at a time; then the vertices split by their uvs."""

    def __init__(self, vertex_count: int, uv_type: np.dtype, colored_faces: int = 0, color_fields: list[str] = ()):
        self.vertex_count = vertex_count
        # Each face's colour (VCGLIB's), drawn instead of the vertices' where both are given, as
        # trimesh draws them once it has split the vertices at their seams.
        self.color_fields = list(color_fields) if colored_faces else []
        self.face_colors = np.empty((colored_faces, len(self.color_fields)), np.uint8) if colored_faces else None
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

    def piece(self, vertices: tuple, name: str) -> MeshPiece:
        """The mesh: each (vertex, uv) pair a vertex, with that vertex's position, normal
        and colour (`vertices`: the file's, mesh_arrays'; the module docstring)."""
        positions, vertex_normals, vertex_colors = vertices
        combos, faces = self.triples.distinct(self.runs, [0, 1], self.vertex_count)
        self.runs = []
        rank = np.arange(self.uv_ids, dtype=np.uint32)  # each uv's id (in the order met), renumbered to its sorted row
        uv_values = self.join.finish(rank)[rank, :2]
        source = combos[:, 0]
        normals = None if vertex_normals is None else vertex_normals[source]
        colors = None if vertex_colors is None else vertex_colors[source]
        piece = MeshPiece(positions[source], faces, normals, uv_values[combos[:, 1]], parts=[(0, len(faces), None, name)],
                          colors=colors)
        del combos, uv_values, rank, source
        if self.face_colors is not None:  # every corner its own vertex, as trimesh gives them
            piece = with_face_colors(piece, self.face_colors)
        return_freed_memory()  # the blocks' and the pairs' arrays, before the crease analysis's
        return piece


def _read_binary(path: Path, header: PlyHeader, vertex_row, face_row, vertices: tuple, split: _UvSplit, where: str) -> bool:
    """Whether the file is of this module's layout; its vertices read into `vertices`, its faces into `split`."""
    face_count = header.count("face")
    with open(path, "rb") as file:
        file.seek(header.header_bytes)
        read_vertices(file, vertex_row, *vertices, where)
        for start in range(0, face_count, BLOCK_ROWS):
            block = file_rows(file, face_row, min(BLOCK_ROWS, face_count - start), where)
            if (block["count"] != 3).any() or (block["uv_count"] != 6).any():
                return False
            if not split.add(block["corners"].reshape(-1).astype(np.int64), block["uv"].reshape(-1, 2)):
                return False
            if split.face_colors is not None:
                read_face_colors(block, split.color_fields, split.face_colors[start : start + len(block)])
    return True


def _read_ascii(path: Path, header: PlyHeader, vertex_row, face_row, vertices: tuple, split: _UvSplit, where: str) -> bool:
    """The ASCII file's vertex lines and its face lines (`3 a b c 6 u v u v u v`), a block of
    lines at a time, each value given its property's type as trimesh gives it (as
    ply_ascii_triangles.py reads them). Whether the file is of this module's layout."""
    names = list(vertex_row.names)
    scalars = skipped_scalars(face_row)  # after each face's lists (MeshLab's flags)
    read = 0  # vertices
    sections = vertex_and_face_lines(ascii_texts(text_line_blocks(path, where, MeshError), skip=header.header_bytes),
                                     split.vertex_count, header.count("face"))
    for section in sections:
        if section is None:
            return False
        values = line_values(section[0], len(names)) if section[0] else np.empty((0, len(names)))
        width = 11 + scalars  # 3 a b c 6 u v u v u v, then the face's scalars
        faces = line_values(section[1], width) if section[1] else np.empty((0, width))
        if values is None or faces is None:
            return False
        if not vertex_values(values, vertex_row, slice(read, read + len(values)), *vertices):
            return False  # (trimesh reads or names it)
        read += len(values)
        corners = faces[:, 1:4]
        if (faces[:, 0] != 3).any() or (faces[:, 4] != 6).any() or (corners != np.floor(corners)).any():
            return False
        if len(faces) and not split.add(corners.reshape(-1).astype(np.int64), faces[:, 5:11].astype(split.join.dtype).reshape(-1, 2)):
            return False
    return True
