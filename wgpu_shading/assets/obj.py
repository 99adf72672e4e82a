"""Wavefront OBJ reading, our own: trimesh's reader loses what SPEC §12 needs.

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
Materials come from mtl.py.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import MeshError
from ..scene.material import Material
from .mtl import read_mtl_files


@dataclass
class _Run:
    """Consecutive face lines with the same state (material, smoothing, vertex counts)."""

    material: str | None
    flat: bool
    vertex_count: int
    uv_count: int
    normal_count: int
    first_line: int
    lines: list[str] = field(default_factory=list)


@dataclass
class ObjData:
    positions: np.ndarray  # (N, 3) float64, one per distinct (v, vt, vn) corner
    faces: np.ndarray  # (F, 3) int64, sorted by material
    uvs: np.ndarray | None
    normals: np.ndarray | None
    colors: np.ndarray | None
    flat: np.ndarray  # (F,) bool: under `s off` / `s 0`
    parts: list[tuple[int, int, Material | None, str]]  # first face, count, material, name


def _line_of(lines: list[str], prefix: str, ordinal: int) -> int:
    """1-based line number of the ordinal-th (0-based) line starting with prefix."""
    seen = -1
    for number, line in enumerate(lines, start=1):
        if line.startswith(prefix):
            seen += 1
            if seen == ordinal:
                return number
    return 0


def _floats(lines: list[str], prefix: str, width: int, path: str, all_lines: list[str]) -> np.ndarray:
    """The numbers of `v` / `vt` / `vn` lines as an (n, columns) float64 array."""
    body = [line[len(prefix) :] for line in lines]
    try:
        values = np.array(" ".join(body).split(), dtype=np.float64)
    except ValueError:
        values = None
    if values is not None and values.size == width * len(lines):
        array = values.reshape(-1, width)
    elif values is not None and prefix == "v " and values.size == 6 * len(lines):
        array = values.reshape(-1, 6)  # x y z r g b
    else:  # mixed widths (vt u v w, v x y z w) or a bad number: line by line
        rows = []
        for ordinal, text in enumerate(body):
            try:
                numbers = [float(token) for token in text.split()]
            except ValueError:
                number = _line_of(all_lines, prefix, ordinal)
                raise MeshError(f"{path}:{number}: cannot read {prefix.strip()!r} line {text.strip()!r} (expected numbers)") from None
            if len(numbers) < width:
                number = _line_of(all_lines, prefix, ordinal)
                raise MeshError(f"{path}:{number}: {prefix.strip()!r} line has {len(numbers)} numbers, expected {width}")
            rows.append(numbers[:6] if prefix == "v " and len(numbers) >= 6 else numbers[:width])
        if prefix == "v " and any(len(r) == 6 for r in rows):
            rows = [r if len(r) == 6 else r[:3] + [1.0, 1.0, 1.0] for r in rows]
        array = np.array(rows, dtype=np.float64).reshape(len(rows), -1)
    bad = ~np.isfinite(array[:, :width]).all(axis=1)
    if bad.any():
        ordinal = int(np.flatnonzero(bad)[0])
        number = _line_of(all_lines, prefix, ordinal)
        raise MeshError(f"{path}:{number}: {prefix.strip()!r} line has a NaN or infinite coordinate: {body[ordinal].strip()!r}")
    return array


_SLASHES = re.compile(r"/")


def _run_corners(run: _Run, path: str) -> tuple[np.ndarray, np.ndarray]:
    """Triangle corners of a run: (T, 3, 3) int64 zero-based (v, vt, vn) with −1 for absent,
    and the run-relative polygon index of each triangle."""
    lines = run.lines
    first_tokens = lines[0].split()
    corners = len(first_tokens)
    per_corner = first_tokens[0].count("/") + 1
    text = " ".join(lines)
    values = None
    if corners == 3 and "//" not in text:
        try:
            values = np.array(_SLASHES.sub(" ", text).split(), dtype=np.int64)
        except ValueError:
            values = None
        if values is not None and values.size != 3 * per_corner * len(lines):
            values = None
    if values is not None:
        raw = np.zeros((len(lines), 3, 3), np.int64)
        raw[:, :, :per_corner] = values.reshape(len(lines), 3, per_corner)
        polygon = np.arange(len(lines))
    else:  # polygons, `a//c`, or mixed formats: line by line, fan-triangulated
        triangles, polygon_of = [], []
        for ordinal, line in enumerate(lines):
            tokens = line.split()
            try:
                parsed = [[int(x) if x else 0 for x in (token.split("/") + ["", ""])[:3]] for token in tokens]
            except ValueError:
                raise MeshError(f"{path}:{_face_line(run, ordinal)}: cannot read face 'f {line.strip()}' (expected vertex indices)") from None
            if len(parsed) < 3:
                raise MeshError(f"{path}:{_face_line(run, ordinal)}: a face needs at least 3 vertices, got 'f {line.strip()}'")
            for k in range(1, len(parsed) - 1):
                triangles.append([parsed[0], parsed[k], parsed[k + 1]])
                polygon_of.append(ordinal)
        raw = np.array(triangles, np.int64).reshape(-1, 3, 3)
        polygon = np.array(polygon_of, np.int64)
    counts = np.array([run.vertex_count, run.uv_count, run.normal_count])
    zero = raw[:, :, 0] == 0
    if zero.any():
        ordinal = int(polygon[np.flatnonzero(zero.any(axis=1))[0]])
        raise MeshError(f"{path}:{_face_line(run, ordinal)}: face index 0 in 'f {lines[ordinal].strip()}' (OBJ indices start at 1)")
    # Positive indices count from 1; negative ones back from the last v/vt/vn declared so far.
    resolved = np.where(raw > 0, raw - 1, np.where(raw < 0, counts + raw, -1))
    out_of_range = ((raw != 0) & ((resolved < 0) | (resolved >= counts))).any(axis=(1, 2))
    if out_of_range.any():
        ordinal = int(polygon[np.flatnonzero(out_of_range)[0]])
        raise MeshError(
            f"{path}:{_face_line(run, ordinal)}: face 'f {lines[ordinal].strip()}' refers to a vertex that does not exist "
            f"({run.vertex_count} v, {run.uv_count} vt, {run.normal_count} vn declared before it)"
        )
    return resolved, polygon


def _face_line(run: _Run, ordinal: int) -> int:
    return run.first_line + ordinal  # runs hold consecutive face lines only


def read_obj(path: Path) -> ObjData:
    text = path.read_text(encoding="utf-8", errors="replace")
    all_lines = text.splitlines()
    name = str(path)
    v_lines: list[str] = []
    vt_lines: list[str] = []
    vn_lines: list[str] = []
    runs: list[_Run] = []
    run: _Run | None = None
    material: str | None = None
    flat = False
    libraries: list[str] = []
    for number, line in enumerate(all_lines, start=1):
        head = line[:2]
        if head == "f ":
            if run is None:
                run = _Run(material, flat, len(v_lines), len(vt_lines), len(vn_lines), number)
                runs.append(run)
            run.lines.append(line[2:])
            continue
        run = None  # any other line ends a run of faces
        if head == "v ":
            v_lines.append(line)
        elif head == "vt":
            vt_lines.append(line)
        elif head == "vn":
            vn_lines.append(line)
        elif line.startswith("usemtl"):
            material = line[6:].strip() or None
        elif head == "s ":
            flat = line[2:].strip().lower() in ("off", "0")
        elif line.startswith("mtllib"):
            libraries.append(line[6:].strip())
        elif line.startswith("f\t"):
            raise MeshError(f"{name}:{number}: faces separated by tabs are not supported; use spaces")
    if not runs or not v_lines:
        raise MeshError(f"mesh file {name!r} contains no triangles ({len(v_lines)} vertices, no faces)")
    v = _floats(v_lines, "v ", 3, name, all_lines)
    vt = _floats(vt_lines, "vt", 2, name, all_lines) if vt_lines else np.zeros((0, 2))
    vn = _floats(vn_lines, "vn", 3, name, all_lines) if vn_lines else np.zeros((0, 3))
    corner_list, flat_list, material_list = [], [], []
    for current in runs:
        corners, _ = _run_corners(current, name)
        corner_list.append(corners)
        flat_list.append(np.full(len(corners), current.flat))
        material_list.append([current.material] * len(corners))
    corners = np.concatenate(corner_list)
    flat_faces = np.concatenate(flat_list)
    face_material = np.array([m or "" for chunk in material_list for m in chunk], dtype=object)
    materials = read_mtl_files(libraries, path.parent, name) if libraries else {}
    # Distinct (v, vt, vn) combinations become vertices.
    has_uv = bool(len(vt)) and bool((corners[:, :, 1] >= 0).all())
    has_normal = bool(len(vn)) and bool((corners[:, :, 2] >= 0).all())
    columns = [corners[:, :, 0].reshape(-1)]
    if has_uv:
        columns.append(corners[:, :, 1].reshape(-1))
    if has_normal:
        columns.append(corners[:, :, 2].reshape(-1))
    if len(columns) == 1:
        vertex_ids, faces = np.arange(len(v)), corners[:, :, 0]
        combos = vertex_ids[:, None]
    else:
        stacked = np.stack(columns, axis=1)
        combos, inverse = np.unique(stacked, axis=0, return_inverse=True)
        faces = inverse.reshape(-1, 3)
    positions = v[combos[:, 0], :3]
    colors = v[combos[:, 0], 3:6] if v.shape[1] == 6 else None
    uvs = vt[combos[:, 1], :2] if has_uv else None
    normals = vn[combos[:, -1]] if has_normal else None
    # Group faces by material (stable: file order within a material) so each part is one range.
    names = list(dict.fromkeys(face_material.tolist()))
    if len(names) > 1:
        index_of = {m: i for i, m in enumerate(names)}
        key = np.fromiter((index_of[m] for m in face_material), np.int64, len(face_material))
        order = np.argsort(key, kind="stable")
        faces, flat_faces, key = faces[order], flat_faces[order], key[order]
        counts = np.bincount(key, minlength=len(names))
    else:
        counts = np.array([len(faces)])
    parts, start = [], 0
    for material_name, count in zip(names, counts):
        parts.append((start, int(count), materials.get(material_name) if material_name else None, material_name))
        start += int(count)
    return ObjData(positions, faces, uvs, normals, colors, flat_faces, parts)
