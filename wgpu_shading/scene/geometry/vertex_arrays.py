"""Per-vertex arrays converted into what a Mesh stores (float32), a block of rows at a time.

A point cloud is all vertices: 10 million points are 120 MB of float32 positions, and one
float64 copy of an (N, 3) or (N, 4) array would cost more than the mesh itself. So the
conversions a mesh without triangles needs (positions relative to the origin, unit normals,
colours in [0, 1]) work through blocks of BLOCK_ROWS rows into one float32 result, with
float64 arithmetic inside each block (docs/primitives.md#large-point-clouds).
"""

from __future__ import annotations

import numpy as np

BLOCK_ROWS = 1 << 16  # 65,536 rows: a few MB of float64 temporaries


def row_blocks(count: int):
    """Slices of at most BLOCK_ROWS rows covering `count` rows, in order."""
    for start in range(0, count, BLOCK_ROWS):
        yield slice(start, min(start + BLOCK_ROWS, count))


def relative_positions(positions: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """float32 positions − origin, computed in float64."""
    out = np.empty(positions.shape, np.float32)
    for rows in row_blocks(len(positions)):
        out[rows] = positions[rows].astype(np.float64) - origin
    return out


def bounds(positions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """float64 (lower, upper) corners (min and max are exact in any float type)."""
    return positions.min(axis=0).astype(np.float64), positions.max(axis=0).astype(np.float64)


def unit_colors(colors: np.ndarray) -> np.ndarray:
    """(N, 3 or 4) colours → (N, 4) float32 in [0, 1]: integers are /255, a missing alpha
    is 1, NaN is 1."""
    out = np.ones((len(colors), 4), np.float32)
    columns = colors.shape[1]
    for rows in row_blocks(len(colors)):
        block = colors[rows].astype(np.float32)
        if colors.dtype.kind in "iu":
            block /= 255.0
        out[rows, :columns] = np.clip(np.nan_to_num(block, nan=1.0), 0.0, 1.0)
    return out


def unit_or_zero_normals(normals: np.ndarray) -> np.ndarray:
    """(N, 3) normals made unit length; NaN, infinite or zero ones become zero (for
    vertices of no triangle: a point without a normal is drawn unlit)."""
    out = np.zeros(normals.shape, np.float32)
    for rows in row_blocks(len(normals)):
        block = normals[rows].astype(np.float64)
        finite = np.isfinite(block).all(axis=1)
        block[~finite] = 0.0
        length = np.sqrt(np.einsum("ij,ij->i", block, block))
        usable = length > 1e-20
        out[rows][usable] = block[usable] / length[usable, None]
    return out
