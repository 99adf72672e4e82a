"""What a mesh draws: its parts, each a range of one primitive kind with its material.

A mesh file holds triangles (surfaces), lines (OBJ `l`, glTF LINES / LINE_STRIP /
LINE_LOOP) and points (point clouds: PLY, OBJ and OFF files without faces, glTF POINTS).
A part is a range of one kind, drawn with its own material (docs/real-world-files.md):

- triangles: rows first .. first + count - 1 of `Mesh.indices`;
- lines: rows of `Mesh.line_indices`, each a segment between two vertices;
- points: vertices first .. first + count - 1 (a point is its vertex, so a 10-million-point
  cloud needs no index array).

`triangle_edges` gives the edges `--edges` draws over a surface (docs/primitives.md).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from ...errors import MeshError

if TYPE_CHECKING:  # pragma: no cover
    from ..material import Material

PRIMITIVES = ("triangles", "lines", "points")


@dataclass(frozen=True)
class MeshPart:
    """Elements first .. first + count - 1 of one primitive kind (module docstring), with
    the material the file gave them (None: the file said nothing; the object's or OpenGL's
    default material is used)."""

    first: int
    count: int
    material: "Material | None" = None
    name: str = ""
    primitive: str = "triangles"

    def __post_init__(self) -> None:
        if self.primitive not in PRIMITIVES:
            raise MeshError(f"mesh part {self.name!r}: primitive must be one of {', '.join(PRIMITIVES)}, got {self.primitive!r}")


def default_parts(triangles: int, lines: int, vertices: int, material: "Material | None", name: str) -> tuple[MeshPart, ...]:
    """One part per kind present, with `material`; a mesh with neither triangles nor lines
    is a point cloud: every vertex a point."""
    parts = []
    if triangles:
        parts.append(MeshPart(0, triangles, material, name))
    if lines:
        parts.append(MeshPart(0, lines, material, name, "lines"))
    if not triangles and not lines:
        parts.append(MeshPart(0, vertices, material, name, "points"))
    return tuple(parts)


def check_parts(parts: tuple[MeshPart, ...], triangles: int, lines: int, vertices: int, name: str) -> None:
    """Triangle parts cover the triangles and line parts the segments, each exactly once
    in all; point parts are ranges of the vertices."""
    for primitive, total in (("triangles", triangles), ("lines", lines)):
        covered = sum(part.count for part in parts if part.primitive == primitive)
        if covered != total:
            kind = "triangles" if primitive == "triangles" else "line segments"
            raise MeshError(f"{name}: parts cover {covered} of {total} {kind}")
    for part in parts:
        if part.primitive == "points" and not (0 <= part.first and part.count >= 0 and part.first + part.count <= vertices):
            raise MeshError(f"{name}: point part {part.name!r} covers vertices {part.first}..{part.first + part.count - 1}; "
                            f"the mesh has {vertices}")


def triangle_edges(indices: np.ndarray) -> np.ndarray:
    """(E, 2) uint32: every edge of the triangles once (the lower vertex index first). Edges
    between split vertices (UV seams, flat shading's corners) are separate edges on the
    same positions: drawn twice, the same pixels."""
    if not len(indices):
        return np.zeros((0, 2), np.uint32)
    first = indices.reshape(-1)
    second = indices[:, [1, 2, 0]].reshape(-1)
    low = np.minimum(first, second).astype(np.uint64)
    high = np.maximum(first, second).astype(np.uint64)
    keys = np.unique((low << np.uint64(32)) | high)
    keys = keys[(keys >> np.uint64(32)) != (keys & np.uint64(0xFFFFFFFF))]  # a repeated corner is no edge
    return np.stack([(keys >> np.uint64(32)).astype(np.uint32), (keys & np.uint64(0xFFFFFFFF)).astype(np.uint32)], axis=1)


def valid_elements(array, width: int, vertices: int, key: str, shape: str, name: str) -> np.ndarray:
    """Triangles or segments as a (n, width) uint32 array of valid vertex indices."""
    elements = np.asarray(array)
    if elements.ndim == 1 and elements.size % width == 0:
        elements = elements.reshape(-1, width)
    if elements.ndim != 2 or elements.shape[1] != width:
        raise MeshError(f"{name}: {key} must have shape {shape}, got {elements.shape}")
    if not len(elements):
        return np.zeros((0, width), np.uint32)
    if elements.dtype.kind not in "iu":
        if elements.dtype.kind == "f" and np.all(np.isfinite(elements)) and np.all(elements == np.round(elements)):
            elements = elements.astype(np.int64)
        else:
            raise MeshError(f"{name}: {key} must be integers, got dtype {elements.dtype}")
    low, high = int(elements.min()), int(elements.max())
    if low < 0 or high >= vertices:
        culprit = low if low < 0 else high
        raise MeshError(f"{name}: index {culprit} is out of range; the mesh has {vertices} vertices (valid: 0..{vertices - 1})")
    return np.ascontiguousarray(elements, dtype=np.uint32)


def kept_for_lines_and_points(source: np.ndarray, segments, parts):
    """Welding split and renumbered the triangles' vertices (`source`: the given vertex each
    new one copies); the vertices of lines and points are appended after them, unchanged,
    and the segments and point parts renumbered to their copies."""
    kept, count = [source], len(source)
    if segments is not None and len(segments):
        used, inverse = np.unique(segments, return_inverse=True)
        kept.append(used)
        segments = (count + inverse.reshape(-1, 2)).astype(np.uint32)
        count += len(used)
    renumbered = []
    for part in parts:
        if part.primitive == "points":
            kept.append(np.arange(part.first, part.first + part.count))
            part = replace(part, first=count)
            count += part.count
        renumbered.append(part)
    return np.concatenate(kept), segments, tuple(renumbered)
