"""Binary PLY meshes whose faces carry their corners' texture coordinates: after each
face's vertex indices, a `texcoord` list of two floats a corner, as MeshLab and Agisoft
Metashape export a textured mesh (with `comment TextureFile NAME`). trimesh reads such a
file whole, as every PLY it reads: 13.4x the mesh's arrays at 2M triangles
(`python benchmarks/scripts/load_peak.py 2000000 /tmp/uvs.ply --face-uvs --render 512`).

Read here a block of faces at a time when the file is binary, every face a triangle with
its 6 floats, and its vertices x y z and properties trimesh skips (MeshLab's flags and
quality); normals or colours beside the texcoords go to trimesh, which drops them once it
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
from ..mesh_pieces import MeshPiece
from .corner_join import CornerJoin
from .obj_vertices import CornerTriples
from .ply_header import PlyHeader
from .ply_triangles import BLOCK_ROWS, COLOR_NAMES, file_rows, float_type, mesh_rows, read_vertices


def read_face_uvs(path: Path, header: PlyHeader, file_size: int, where: str) -> MeshPiece | None:
    """The mesh of a PLY in this module's layout, or None for any other (trimesh reads it)."""
    if header.format not in ("binary_little_endian", "binary_big_endian"):
        return None
    rows = mesh_rows(header, "<" if header.format == "binary_little_endian" else ">", face_texture=True)
    if rows is None:
        return None
    vertex_row, face_row = rows
    if "nx" in vertex_row.fields or any(name in vertex_row.fields for name in COLOR_NAMES):
        return None
    vertex_count, face_count = header.count("vertex"), header.count("face")
    if header.header_bytes + vertex_count * vertex_row.itemsize + face_count * face_row.itemsize != file_size:
        return None  # faces of other sizes, or truncated: trimesh reads or names it
    if face_count > MAX_TRIANGLES:
        raise MeshError(f"{where}: {face_count} faces; at most {MAX_TRIANGLES} triangles are supported")
    positions = np.empty((vertex_count, 3), float_type(vertex_row.fields, "xyz"))
    uv_join = CornerJoin(np.float32 if face_row.fields["uv"][0].base.itemsize == 4 else np.float64)  # (in this machine's byte order)
    triples = CornerTriples()
    runs, uv_ids = [], 0
    try:
        with open(path, "rb") as file:
            file.seek(header.header_bytes)
            read_vertices(file, vertex_row, positions, None, None, where)
            for start in range(0, face_count, BLOCK_ROWS):
                block = file_rows(file, face_row, min(BLOCK_ROWS, face_count - start), where)
                corners, uvs = block["corners"].reshape(-1).astype(np.int64), block["uv"].reshape(-1, 2)
                if (block["count"] != 3).any() or (block["uv_count"] != 6).any() or not np.isfinite(uvs).all():
                    return None
                if len(corners) and (corners.min() < 0 or corners.max() >= vertex_count):
                    return None  # trimesh names the face
                ids = uv_join.add(np.column_stack([uvs, np.zeros(len(uvs), uvs.dtype)]))
                uv_ids = max(uv_ids, int(ids.max(initial=0)) + 1)
                pairs = np.stack([corners, ids.astype(np.int64), np.full(len(ids), -1)], axis=1)  # (v, uv, no vn)
                runs.append(triples.split(pairs.reshape(-1, 3, 3), vertex_count))
    except OSError as error:
        raise MeshError(f"{where}: cannot be read ({error.strerror or error})") from None
    except MemoryError:
        raise MeshError(f"{where}: not enough memory to read {vertex_count} vertices and {face_count} faces") from None
    combos, faces = triples.distinct(runs, [0, 1], vertex_count)
    del runs
    rank = np.arange(uv_ids, dtype=np.uint32)  # each uv's id (in the order met), renumbered to its sorted row
    uv_values = uv_join.finish(rank)[rank, :2]
    piece = MeshPiece(positions[combos[:, 0]], faces, None, uv_values[combos[:, 1]], parts=[(0, len(faces), None, path.name)])
    del positions, combos, uv_values, rank
    return_freed_memory()  # the blocks' and the pairs' arrays, before the crease analysis's
    return piece
