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
Materials come from mtl.py, face lines are read by obj_faces.py, `l` and `p` by obj_elements.py.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.geometry.mesh import MAX_TRIANGLES, MAX_VERTICES
from ..files import read_text_bytes
from ..mesh_pieces import MeshFile, MeshPiece
from .obj_elements import obj_elements, bare_points
from .number_text import parse_floats, read_in_blocks
from .obj_faces import FaceRun, ear_clip_concave, run_corners
from .mtl import read_mtl_files


NUMBER_LINES_AT_ONCE = 1 << 16  # v/vt/vn lines read together: bounded temporaries (a few bytes a character)


def _numbers(lines: list[str], prefix: str) -> np.ndarray | None:
    """Every number of the lines (their `v`/`vt`/`vn` left out), NUMBER_LINES_AT_ONCE lines at
    a time: the reading's temporaries stay a few MB however big the file, and in cache."""
    keyword = prefix.strip()
    return read_in_blocks(lines, NUMBER_LINES_AT_ONCE, lambda block: parse_floats(" ".join(block).replace(keyword, " ")))


def _floats(lines: list[str], prefix: str, width: int, path: str, numbers: np.ndarray) -> np.ndarray:
    """The numbers of `v` / `vt` / `vn` lines as an (n, columns) float64 array; `numbers`
    are their 1-based line numbers (for errors)."""
    values = _numbers(lines, prefix)
    if values is not None and values.size == width * len(lines):
        array = values.reshape(-1, width)
    elif values is not None and prefix == "v " and values.size == 6 * len(lines):
        array = values.reshape(-1, 6)  # x y z r g b
    else:  # mixed widths (vt u v w, v x y z w) or a bad number: line by line
        rows = []
        for ordinal, line in enumerate(lines):
            text = line.strip()[len(prefix.strip()) :]
            try:
                row = [float(token) for token in text.split()]
            except ValueError:
                raise MeshError(f"{path}:{numbers[ordinal]}: cannot read {prefix.strip()!r} line {line.strip()!r} (expected numbers)") from None
            if len(row) < width:
                raise MeshError(f"{path}:{numbers[ordinal]}: {prefix.strip()!r} line has {len(row)} numbers, expected {width}")
            rows.append(row[:6] if prefix == "v " and len(row) >= 6 else row[:width])
        if prefix == "v " and any(len(r) == 6 for r in rows):
            rows = [r if len(r) == 6 else r[:3] + [1.0, 1.0, 1.0] for r in rows]
        array = np.array(rows, dtype=np.float64).reshape(len(rows), -1)
    bad = ~np.isfinite(array[:, :width]).all(axis=1)
    if bad.any():
        ordinal = int(np.flatnonzero(bad)[0])
        raise MeshError(f"{path}:{numbers[ordinal]}: {prefix.strip()!r} line has a NaN or infinite coordinate: {lines[ordinal].strip()[len(prefix.strip()):].strip()!r}")
    return array




def _slices(lines: list[str], indices: np.ndarray) -> list[str]:
    """lines[i] for each i, taken as list slices of consecutive runs (fast for blocks)."""
    if not len(indices):
        return []
    breaks = np.flatnonzero(np.diff(indices) != 1) + 1
    starts = np.concatenate([[0], breaks])
    ends = np.concatenate([breaks, [len(indices)]])
    out: list[str] = []
    for a, b in zip(starts.tolist(), ends.tolist()):
        out.extend(lines[indices[a] : indices[b - 1] + 1])
    return out


def _without_byte_order_mark(data: bytes) -> bytes:
    """UTF-8 bytes without a byte order mark. Windows tools start files with one; left in,
    it hides the first line's keyword (a first `v` line was lost, shifting every index)."""
    if data.startswith(b"\xef\xbb\xbf"):
        return data[3:]
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):  # UTF-16 (assimp's box_UTF16BE.obj)
        return data.decode("utf-16").encode("utf-8")
    return data


def _without_indentation(data: bytes) -> bytes:
    """Lines with their leading blanks removed: the OBJ spec allows them, and the
    classification in read_obj looks at a line's first two bytes."""
    return b"\n".join(line.lstrip(b" \t") for line in data.split(b"\n"))


def _line_starts(data: bytes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each line's first byte offset and its first two bytes (0 past the end), in numpy."""
    raw = np.frombuffer(data + b"\0\0", np.uint8)
    starts = np.concatenate([[0], np.flatnonzero(raw[: len(data)] == 10) + 1])
    return starts, raw[starts], raw[starts + 1]


def _with_newlines(data: bytes) -> bytes:
    """Classic Mac OS files end lines with CR alone: the whole file read as one line, an
    error saying it had no faces. (CR LF needs nothing: a trailing CR is blank space.)"""
    if b"\r" in data and b"\n" not in data:
        return data.replace(b"\r", b"\n")
    return data


def read_obj(path: Path, file_size: int | None = None) -> MeshFile:
    """An OBJ file with its MTL materials, as one piece (file_size: the readers' signature;
    the text's own counts are checked instead)."""
    data = _with_newlines(_without_byte_order_mark(read_text_bytes(path, f"mesh file {str(path)!r}", MeshError)))
    name = str(path)
    # Classify every line by its first two bytes, in numpy (a Python loop over millions of
    # lines would cost more than the rest of the reading). Indented lines are found from
    # the same first bytes (searching the text for "\n " cost 5 ms of a 2.3 MB file's 90).
    starts, first, second = _line_starts(data)
    if ((first == 32) | (first == 9)).any():
        data = _without_indentation(data)
        starts, first, second = _line_starts(data)
    blank = (second == 32) | (second == 9)
    is_v = (first == ord("v")) & blank
    is_vt = (first == ord("v")) & (second == ord("t"))
    is_vn = (first == ord("v")) & (second == ord("n"))
    is_f = (first == ord("f")) & blank
    is_l, is_p = (first == ord("l")) & blank, (first == ord("p")) & blank
    v_count, vt_count, vn_count = np.cumsum(is_v), np.cumsum(is_vt), np.cumsum(is_vn)
    # Counted before the text is split into lines (a Python string per line: ~60 bytes each).
    vertices, polygons = int(v_count[-1]) if len(v_count) else 0, int(is_f.sum())
    if vertices > MAX_VERTICES or polygons > MAX_TRIANGLES:
        raise MeshError(f"mesh file {name!r}: {vertices} vertices and {polygons} faces; at most {MAX_VERTICES} of each are supported")
    lines = data.decode("utf-8", errors="replace").split("\n")
    # The few state lines, in order: usemtl, s, mtllib.
    state_lines = np.flatnonzero((first == ord("u")) | (first == ord("s")) | (first == ord("m")))
    libraries: list[str] = []
    changes: list[tuple[int, str | None, bool]] = []  # (line index, material, flat) from there on
    material: str | None = None
    flat = False
    for index in state_lines.tolist():
        line = lines[index].strip()
        if line.startswith("usemtl"):
            material = line[6:].strip() or None
        elif line.startswith("s ") or line.startswith("s\t"):
            flat = line[2:].strip().lower() in ("off", "0")
        elif line.startswith("mtllib"):
            libraries.append(line[6:].strip())
            continue
        else:
            continue
        changes.append((index, material, flat))
    face_lines = np.flatnonzero(is_f)
    v_lines = np.flatnonzero(is_v)
    if not len(v_lines):
        raise MeshError(f"mesh file {name!r} contains no triangles, lines or points (no vertices)")
    v = _floats(_slices(lines, v_lines), "v ", 3, name, v_lines + 1)
    materials = read_mtl_files(libraries, path.parent, name) if libraries else {}
    change_at = np.array([c[0] for c in changes], np.int64)

    def material_at(index: int) -> str | None:
        state = int(np.searchsorted(change_at, index)) - 1
        return changes[state][1] if state >= 0 else None

    # `l` and `p` records, each kind a piece of its own (obj_elements.py)
    segments = obj_elements(lines, np.flatnonzero(is_l), v_count, material_at, v, materials, name, "lines")
    points = obj_elements(lines, np.flatnonzero(is_p), v_count, material_at, v, materials, name, "points")
    if not len(face_lines) and segments is None and points is None:
        points = bare_points(v)  # nothing joins the vertices: a point cloud
    others = [MeshPiece(e.positions, e.indices, colors=e.colors, parts=e.parts, primitive=kind)
              for kind, e in (("lines", segments), ("points", points)) if e is not None]
    if not len(face_lines):
        return MeshFile(others)
    # Runs: blocks of consecutive face lines (the counts and the state are fixed within one).
    breaks = np.flatnonzero(np.diff(face_lines) != 1) + 1
    runs = []
    for a, b in zip(np.concatenate([[0], breaks]).tolist(), np.concatenate([breaks, [len(face_lines)]]).tolist()):
        first_index = int(face_lines[a])
        state = int(np.searchsorted(change_at, first_index)) - 1
        run_material, run_flat = (changes[state][1], changes[state][2]) if state >= 0 else (None, False)
        runs.append(FaceRun(run_material, run_flat, int(v_count[first_index]), int(vt_count[first_index]),
                         int(vn_count[first_index]), first_index + 1, lines[first_index : int(face_lines[b - 1]) + 1]))
    vt_lines, vn_lines = np.flatnonzero(is_vt), np.flatnonzero(is_vn)
    vt = _floats(_slices(lines, vt_lines), "vt", 2, name, vt_lines + 1) if len(vt_lines) else np.zeros((0, 2))
    vn = _floats(_slices(lines, vn_lines), "vn", 3, name, vn_lines + 1) if len(vn_lines) else np.zeros((0, 3))
    corner_list, flat_list, run_materials, run_triangles = [], [], [], []
    for current in runs:
        corners, polygon = run_corners(current, name)
        corners = ear_clip_concave(corners, polygon, v[:, :3])
        corner_list.append(corners)
        flat_list.append(np.full(len(corners), current.flat))
        run_materials.append(current.material or "")
        run_triangles.append(len(corners))
    corners = np.concatenate(corner_list)
    flat_faces = np.concatenate(flat_list)
    # Distinct (v, vt, vn) combinations become vertices.
    has_uv = bool(len(vt)) and bool((corners[:, :, 1] >= 0).all())
    has_normal = bool(len(vn)) and bool((corners[:, :, 2] >= 0).all())
    columns = [corners[:, :, 0].reshape(-1)]
    if has_uv:
        columns.append(corners[:, :, 1].reshape(-1))
    if has_normal:
        columns.append(corners[:, :, 2].reshape(-1))
    same = all(np.array_equal(columns[0], column) for column in columns[1:])
    if same and len(v) >= max((len(vt) if has_uv else 0), (len(vn) if has_normal else 0)):
        # One index per corner for every attribute (exporters that write per-vertex uvs and
        # normals): the vertices are the v lines.
        faces = corners[:, :, 0]
        combos = np.repeat(np.arange(len(v))[:, None], len(columns), axis=1)
        if has_uv and len(vt) < len(v) or has_normal and len(vn) < len(v):
            combos = None
    else:
        combos = None
    if combos is None:
        stacked = np.stack(columns, axis=1)
        combos, inverse = np.unique(stacked, axis=0, return_inverse=True)
        faces = inverse.reshape(-1, 3)
    positions = v[combos[:, 0], :3]
    colors = v[combos[:, 0], 3:6] if v.shape[1] == 6 else None
    uvs = vt[combos[:, 1], :2] if has_uv else None
    normals = vn[combos[:, -1]] if has_normal else None
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
    if named and not libraries:  # f3d and Blender draw these faces plain too, but say why
        warnings.warn(f"{name}: 'usemtl {named[0]}' but the file names no material library (mtllib); drawn without materials", stacklevel=2)
    for material_name, count in zip(names, counts):
        if material_name and materials and material_name not in materials:  # (a missing library warned already)
            warnings.warn(f"{name}: 'usemtl {material_name}' names no material of {', '.join(libraries)}; its faces drawn without it", stacklevel=2)
        parts.append((start, int(count), materials.get(material_name) if material_name else None, material_name))
        start += int(count)
    # one piece: a vertex per distinct (v, vt, vn) corner, faces sorted by material, flat under `s off`
    return MeshFile([MeshPiece(positions, faces, normals, uvs, colors, flat_faces, parts=parts)] + others)
