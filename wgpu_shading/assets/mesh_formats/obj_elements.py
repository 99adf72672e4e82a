"""OBJ's line and point elements: `l` polylines and `p` points (the OBJ specification's
"line" and "point" elements), and a file of bare `v` lines read as a point cloud.

Each record's indices refer to `v` lines (a `v/vt` pair's texture index is ignored: lines
and points are drawn in their colour); negative ones count back from the vertices declared
so far, as in faces (obj.py). A record's material is the `usemtl` in force on its line.
Lines and points get vertices of their own, copied from the `v` lines they use, so the
faces' vertices (split by uv and normal) are not touched.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ...errors import MeshError
from ...scene.material import Material
from .number_text import parse_numbers


@dataclass
class ObjElements:
    """The lines (indices (k, 2) segments) or points (indices None: every vertex a point)
    of an OBJ, on vertices of their own, in parts by material."""

    positions: np.ndarray  # (n, 3) float64
    colors: np.ndarray | None  # (n, 3) float64 from `v x y z r g b`
    indices: np.ndarray | None
    parts: list[tuple[int, int, Material | None, str]]


def _record_indices(line: str, line_number: int, declared: int, path: str) -> np.ndarray:
    """The record's vertices, 0-based (int32). Read in C (a `v/vt` token's tail dropped);
    a record that is not all in-range numbers that way is read token by token, which says
    which token is wrong. A Python list of every token was ~140 bytes a vertex: a 48 MB
    `l` line of 24M vertices took 3.3 GB to load."""
    text = line[1:]  # after the `l` or `p`
    if "/" in text:
        text = _SLASH_TAILS.sub("", text)
    raw = parse_numbers(text, np.int64)
    if raw is not None:
        if not ((raw == 0) | (raw > declared) | (raw < -declared)).any():
            return np.where(raw > 0, raw - 1, declared + raw).astype(np.int32)  # (declared ≤ MAX_VERTICES)
    resolved = []
    for match in _TOKENS.finditer(line, len(line) - len(line.lstrip()) + 1):  # (lazily: the first bad one ends it)
        try:
            value = int(match.group().split("/")[0])
        except ValueError:
            raise MeshError(f"{path}:{line_number}: cannot read {line.strip()!r} (expected vertex indices)") from None
        index = value - 1 if value > 0 else declared + value
        if value == 0 or not 0 <= index < declared:
            raise MeshError(f"{path}:{line_number}: {line.strip()!r} refers to a vertex that does not exist ({declared} v declared before it)")
        resolved.append(index)
    return np.array(resolved, np.int32)


_SLASH_TAILS = re.compile(r"/\S*")  # `7/3` → `7`
_TOKENS = re.compile(r"\S+")


def obj_elements(records: dict[int, tuple[str, int, str | None]], v: np.ndarray, materials: dict, path: str,
                 kind: str) -> ObjElements | None:
    """The `l` (kind "lines") or `p` (kind "points") records: 0-based line number → (the
    line, how many `v` lines precede it, the material in force there), in file order
    (obj_blocks.py collects them)."""
    if not records:
        return None
    by_material: dict[str, list[np.ndarray]] = {}
    for index, (line, declared, material) in records.items():
        vertices = _record_indices(line, index + 1, declared, path)
        if kind == "lines":
            if len(vertices) < 2:
                raise MeshError(f"{path}:{index + 1}: a line needs at least 2 vertices, got {line.strip()!r}")
            elements = np.stack([vertices[:-1], vertices[1:]], axis=1)
        else:
            elements = vertices
        by_material.setdefault(material or "", []).append(elements)
    return _on_own_vertices(by_material, v, materials, kind)


def bare_points(v: np.ndarray) -> ObjElements:
    """A file of `v` lines and nothing to join them: every vertex a point (trimesh's
    obj_points.obj, written by Blender)."""
    return ObjElements(v[:, :3], v[:, 3:6] if v.shape[1] == 6 else None, None, [(0, len(v), None, "")])


def _on_own_vertices(by_material: dict, v: np.ndarray, materials: dict, kind: str) -> ObjElements:
    groups = [(name, np.concatenate(chunks)) for name, chunks in by_material.items()]
    if kind == "points":  # each listed point its own vertex, in part order
        used = np.concatenate([elements for _, elements in groups])
        indices = None
    else:
        # np.unique's vertices and inverse, from a mask over the `v` lines: its sort of every
        # corner took ~80 bytes a segment (a 48 MB `l` line of 24M vertices: 3.3 GB).
        is_used = np.zeros(len(v), bool)
        for _, elements in groups:
            is_used[elements.reshape(-1)] = True
        used = np.flatnonzero(is_used)
        place = np.cumsum(is_used, dtype=np.int32) - 1  # each used vertex's place among them
        indices = np.concatenate([place[elements] for _, elements in groups])
    parts, start = [], 0
    for name, elements in groups:
        parts.append((start, len(elements), materials.get(name) if name else None, name))
        start += len(elements)
    return ObjElements(v[used, :3], v[used, 3:6] if v.shape[1] == 6 else None, indices, parts)
