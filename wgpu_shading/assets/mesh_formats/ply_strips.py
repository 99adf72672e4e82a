"""A PLY's `tristrips` element (`vertex_indices`, strips separated by -1), as Cyberware's and
the Stanford scanning tools' files (igea, from alecjacobson/common-3d-test-models) hold their
surface: each strip's triangles, every other one turned so they all keep the first one's
winding (OpenGL's GL_TRIANGLE_STRIP; Paul Bourke's PLY description). trimesh reads the
element without interpreting it (a point cloud of the vertices); the triangles are made here.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import MeshError


def strip_triangles(data, vertex_count: int, path: Path) -> np.ndarray:
    """(t, 3) triangles of the strips in trimesh's raw `tristrips` element `data` (a
    structured array from binary files, a dict of columns from ASCII ones), degenerate
    ones (a repeated vertex: how strips are joined) left out."""
    where = f"mesh file {str(path)!r}"
    names = getattr(getattr(data, "dtype", None), "names", None) or (tuple(data) if isinstance(data, dict) else ())
    if "vertex_indices" not in names:
        raise MeshError(f"{where}: the PLY element 'tristrips' has no 'vertex_indices' list")
    column = data["vertex_indices"]
    rows = column["f1"] if getattr(column, "dtype", None) is not None and column.dtype.names else column
    try:
        indices = np.concatenate([np.asarray(row, dtype=np.int64).reshape(-1) for row in rows]) if len(rows) else np.zeros(0, np.int64)
    except (TypeError, ValueError):
        raise MeshError(f"{where}: the PLY's triangle strips are not lists of vertex indices") from None
    if len(indices) and (indices.max() >= vertex_count or indices.min() < -1):
        culprit = int(indices.max() if indices.max() >= vertex_count else indices.min())
        raise MeshError(f"{where}: a triangle strip refers to vertex {culprit}, but the file has {vertex_count} vertices (valid: 0..{vertex_count - 1}; -1 ends a strip)")
    if len(indices) < 3:
        return np.zeros((0, 3), np.int64)
    breaks = indices == -1
    # where each position's strip starts: the position after the last -1 before it
    start = np.maximum.accumulate(np.where(breaks, np.arange(len(indices)) + 1, 0))
    first = np.arange(len(indices) - 2)
    corners = np.stack([indices[first], indices[first + 1], indices[first + 2]], axis=1)
    whole = ~(breaks[first] | breaks[first + 1] | breaks[first + 2])
    odd = (first - start[first]) % 2 == 1
    corners[odd] = corners[odd][:, [1, 0, 2]]  # every other triangle of a strip is wound the other way
    degenerate = (corners[:, 0] == corners[:, 1]) | (corners[:, 1] == corners[:, 2]) | (corners[:, 0] == corners[:, 2])
    return corners[whole & ~degenerate]
