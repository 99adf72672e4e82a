"""Wavefront OBJ reading, our own: trimesh's reader loses what docs/real-world-files.md needs.

What trimesh 5.2 gets wrong, and why this module exists:
- Negative (relative) indices are resolved against the end of the whole file instead of
  the vertices declared so far, so multi-object OBJs with relative indices (the classic
  Cornell box) collapse silently. Reported upstream as trimesh issue #2364 ("Loading OBJ
  with multiple objects with negative face indices"), open; the fix PR #2556 was closed.
  Here each face resolves them against the running counts of v / vt / vn.
- Face index 0 (invalid in OBJ) is silently mapped to a vertex; here it is an error
  naming the line, as in tinyobjloader.
- `s off` / `s 0` smoothing groups are dropped; here those faces are flat.
- Vertex colors (`v x y z r g b`) make it drop the `usemtl` materials.
The text is read a block of lines at a time by obj_blocks.py (never the whole file's lines at
once), materials come from mtl.py, face lines are read by obj_faces.py, `l` and `p` by
obj_elements.py.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.freed_memory import return_freed_memory
from ...scene.geometry.mesh import MAX_TRIANGLES, MAX_VERTICES
from ..files import text_line_blocks
from ..mesh_pieces import MeshFile, MeshPiece
from .line_sections import joined
from .mtl import read_mtl_files
from .obj_blocks import ObjContent
from .obj_elements import bare_points, obj_elements
from .obj_faces import ear_clip_concave, has_concave, kept_fans_note


def _without_byte_order_mark(data: bytes) -> bytes:
    """UTF-8 bytes without a byte order mark. Windows tools start files with one; left in,
    it hides the first line's keyword (a first `v` line was lost, shifting every index)."""
    if data.startswith(b"\xef\xbb\xbf"):
        return data[3:]
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):  # UTF-16 (assimp's box_UTF16BE.obj)
        return data.decode("utf-16").encode("utf-8")
    return data


def _with_newlines(data: bytes) -> bytes:
    """Classic Mac OS files end lines with CR alone: the whole file read as one line, an
    error saying it had no faces. (CR LF needs nothing: a trailing CR is blank space.) Only
    the first block needs a look: blocks end at newlines, so a file without any is one block."""
    if b"\r" in data and b"\n" not in data:
        return data.replace(b"\r", b"\n")
    return data


GATHER_ROWS = 1 << 20  # rows _rows_of gathers at a time


def _rows_of(source: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """source[rows], a block of rows at a time: numpy indexes with an int64 copy of an int32
    index array, made whole (40 MB at 5M vertices) at the peak of a Blender-style OBJ's load,
    when the file's v, vt and vn numbers are all still held."""
    gathered = np.empty((len(rows), source.shape[1]), source.dtype)
    for start in range(0, len(rows), GATHER_ROWS):
        # mode="clip": the rows are in range (distinct's), and mode="raise" buffers all of `out`
        np.take(source, rows[start : start + GATHER_ROWS], axis=0, out=gathered[start : start + GATHER_ROWS], mode="clip")
    return gathered


def read_obj(path: Path, file_size: int | None = None) -> MeshFile:
    """An OBJ file with its MTL materials, as one piece (file_size: the readers' signature;
    the text's own counts are checked instead). Read a block of lines at a time
    (obj_blocks.py), in memory a few times the arrays it gives, not the text's."""
    name = str(path)
    content = ObjContent(name, MAX_VERTICES, MAX_TRIANGLES)
    blocks = 0
    for blocks, block in enumerate(text_line_blocks(path, f"mesh file {name!r}", MeshError), 1):
        content.read_block(_with_newlines(_without_byte_order_mark(block)) if blocks == 1 else block)
    if blocks > 1:  # the blocks' text and temporaries, freed among the arrays kept: given back before the rest
        return_freed_memory()
    vertices, polygons = content.counts["v "], content.polygons
    if content.over_limit:  # (each block past the limit only counted)
        if content.triangles > MAX_TRIANGLES:  # few polygons of many corners: refused before the rest is cut into triangles
            raise MeshError(f"mesh file {name!r}: its faces cut into triangles make more than {MAX_TRIANGLES} (the limit is passed "
                            f"at line {content.triangle_line}); at most {MAX_TRIANGLES} triangles are supported")
        raise MeshError(f"mesh file {name!r}: {vertices} vertices and {polygons} faces; at most {MAX_VERTICES} of each are supported")
    if not vertices:
        raise MeshError(f"mesh file {name!r} contains no triangles, lines or points (no vertices)")
    if "v " in content.errors:
        raise content.errors["v "]
    v = content.vertex_numbers("v ")
    materials = read_mtl_files(content.libraries, path.parent, name) if content.libraries else {}
    # `l` and `p` records, each kind a piece of its own (obj_elements.py)
    segments = obj_elements(content.elements["lines"], v, materials, name, "lines")
    points = obj_elements(content.elements["points"], v, materials, name, "points")
    if not polygons and segments is None and points is None:
        points = bare_points(v)  # nothing joins the vertices: a point cloud
    others = [MeshPiece(e.positions, e.indices, colors=e.colors, parts=e.parts, primitive=kind)
              for kind, e in (("lines", segments), ("points", points)) if e is not None]
    if not polygons:
        return MeshFile(others, content.notes, self_contained=not content.libraries)
    for keyword in ("vt", "vn", "f"):
        if keyword in content.errors:
            raise content.errors[keyword]
    vt, vn = content.vertex_numbers("vt"), content.vertex_numbers("vn")
    kept_fans, triples = 0, content.triples
    for run in content.runs:  # concave polygons cut again (a degenerate one may give fewer triangles)
        if run.polygon is not None and has_concave(run.corners.vertices, run.polygon, v[:, :3]):
            corners, kept = ear_clip_concave(triples.whole(run.corners), run.polygon, v[:, :3])
            run.corners = triples.split(corners, len(v))
            kept_fans += kept
        run.polygon = None
    notes = content.notes
    if kept_fans:
        notes.append(kept_fans_note(name, kept_fans))
    runs = [run.corners for run in content.runs]
    run_triangles = [len(corners) for corners in runs]
    run_materials = [run.material or "" for run in content.runs]
    flat_faces = np.repeat([run.flat for run in content.runs], run_triangles).astype(bool)
    content.runs.clear()
    # Distinct (v, vt, vn) combinations become vertices.
    has_uv = bool(len(vt)) and all(corners.all_uv for corners in runs)
    has_normal = bool(len(vn)) and all(corners.all_normal for corners in runs)
    columns = [0] + ([1] if has_uv else []) + ([2] if has_normal else [])
    same = all((not has_uv or corners.same_uv) and (not has_normal or corners.same_normal) for corners in runs)
    # One index per corner for every attribute (exporters that write per-vertex uvs and
    # normals, and scans with neither): the vertices are the v lines, in order.
    if same and (not has_uv or len(vt) == len(v)) and (not has_normal or len(vn) == len(v)):
        vertex_blocks = [corners.vertices for corners in runs]
        del runs
        faces = joined(vertex_blocks, np.int32)  # (each let go once copied)
        positions = np.ascontiguousarray(v[:, :3])
        colors = np.ascontiguousarray(v[:, 3:6]) if v.shape[1] == 6 else None
        uvs = np.ascontiguousarray(vt[: len(v), :2]) if has_uv else None
        normals = np.ascontiguousarray(vn[: len(v)]) if has_normal else None
    else:  # a vertex per distinct (v, vt, vn): exporters number vt and vn on their own
        combos, faces = triples.distinct(runs, columns, len(v))
        del runs
        # each file's numbers let go once gathered: they and the vertices' are never all resident
        positions = _rows_of(v[:, :3], combos[:, 0])
        colors = _rows_of(v[:, 3:6], combos[:, 0]) if v.shape[1] == 6 else None
        del v
        uvs = _rows_of(vt[:, :2], combos[:, 1]) if has_uv else None
        del vt
        normals = _rows_of(vn, combos[:, -1]) if has_normal else None
        del vn, combos
    # Group faces by material (stable: file order within a material) so each part is one
    # range. A run's faces share its material, so the materials are listed per run (a list
    # of every face's material cost the bunny 8 of its 36 ms of reading).
    names = list(dict.fromkeys(m for m, count in zip(run_materials, run_triangles) if count))
    if len(names) > 1:
        index_of = {m: i for i, m in enumerate(names)}
        key = np.repeat(np.array([index_of.get(m, 0) for m in run_materials], np.int64), run_triangles)
        order = np.argsort(key, kind="stable")
        faces, flat_faces, key = faces[order], flat_faces[order], key[order]
        counts = np.bincount(key, minlength=len(names))
    else:
        counts = np.array([len(faces)])
    parts, start = [], 0
    named = [m for m in names if m]
    if named and not content.libraries:  # f3d and Blender draw these faces plain too, but say why
        notes.append(f"{name}: 'usemtl {named[0]}' but the file names no material library (mtllib); drawn without materials")
    for material_name, count in zip(names, counts):
        if material_name and materials and material_name not in materials:  # (a missing library warned already)
            notes.append(f"{name}: 'usemtl {material_name}' names no material of {', '.join(content.libraries)}; its faces drawn without it")
        parts.append((start, int(count), materials.get(material_name) if material_name else None, material_name))
        start += int(count)
    if len(faces) and int(faces.min()) >= 0:  # (always, once resolved: _check_piece names a stray one)
        # uint32 and read-only, owning its memory: what a Mesh keeps as its indices without
        # a copy (scene/geometry/mesh.py, owned), 120 MB less at the peak of a 10M-triangle load.
        faces = faces.astype(np.uint32, copy=False)
        faces.setflags(write=False)
    if blocks > 1:  # the blocks' text and temporaries, freed between the arrays kept: given back
        return_freed_memory()
    # one piece: a vertex per distinct (v, vt, vn) corner, faces sorted by material, flat under `s off`
    # Without a material library the Mesh follows from this file alone (mesh_cache.py).
    return MeshFile([MeshPiece(positions, faces, normals, uvs, colors, flat_faces, parts=parts)] + others, notes,
                    self_contained=not content.libraries)
