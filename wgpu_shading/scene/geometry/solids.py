"""Whether a mesh bounds a solid: a closed surface with its triangles wound one way.

Shadows use it (docs/shadows.md#closed-surfaces): a segment from a point of a closed surface
towards a light its triangle faces away from enters the solid, so it must leave it through
the surface again — the point is in the mesh's own shadow, whatever a shadow map's
resolution can tell. An open surface (a quad, a terrain) gives no such answer.
"""

from __future__ import annotations

import numpy as np

from .crease_normals import weld_by_position

# Vertices closer than this fraction of the mesh's size are welded: far above float32's
# rounding of one position (6e-8), far below any edge a mesh means to have.
WELD_TOLERANCE = 1e-6


def solid_orientation(positions: np.ndarray, indices: np.ndarray) -> int:
    """+1 if the triangles form closed surfaces wound counter-clockwise seen from outside,
    −1 if closed and wound the other way (inside out), 0 if not closed.

    Vertices within WELD_TOLERANCE of the mesh's size of each other are one vertex (a UV
    sphere's seam and poles repeat theirs, a torus's seam closes at sin(2π) ≈ −2e-16 instead
    of 0); triangles with a repeated vertex cover nothing and are dropped. The surface is
    closed and consistently wound when every directed edge (a, b) occurs exactly once and
    its reverse (b, a) exactly once (each edge shared by two triangles that agree). Written
    with numpy rather than through trimesh (its watertight and winding checks say the same)
    to keep trimesh's import (~0.3 s) out of a render that casts shadows."""
    if len(indices) == 0:
        return 0
    corners = np.asarray(positions, dtype=np.float64)
    corners = corners - corners.mean(axis=0)
    size = float(np.abs(corners).max())
    if size == 0.0:
        return 0
    welded = weld_by_position(np.round(corners / (WELD_TOLERANCE * size)))
    triangles = welded[np.asarray(indices, dtype=np.int64)].reshape(-1, 3)
    a, b, c = triangles.T
    triangles = triangles[(a != b) & (b != c) & (c != a)]
    if len(triangles) == 0:
        return 0
    count = int(welded.max()) + 1
    edges = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    codes = np.sort(edges[:, 0] * count + edges[:, 1])
    if (codes[1:] == codes[:-1]).any():  # a directed edge twice: not one consistent surface
        return 0
    # Every edge's reverse is an edge: the reversed codes are the same set.
    if not np.array_equal(codes, np.sort(edges[:, 1] * count + edges[:, 0])):
        return 0
    # The signed volume (divergence theorem, relative to the centroid for precision).
    p = corners[np.asarray(indices, dtype=np.int64)]
    volume = float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum()) / 6.0
    if volume == 0.0:
        return 0
    return 1 if volume > 0.0 else -1


def winding_number(positions: np.ndarray, indices: np.ndarray, point: np.ndarray) -> float:
    """How many times the triangles wind around `point` (float64): the sum of their signed
    solid angles seen from it over 4π (A. van Oosterom and J. Strackee, "The Solid Angle of
    a Plane Triangle", IEEE Trans. Biomed. Eng. 30(2), 1983,
    https://doi.org/10.1109/TBME.1983.325207). For a closed surface wound counter-clockwise
    seen from outside it is 1 inside the solid and 0 outside (−1 and 0 inside out), whatever
    its shape: a light near a non-convex solid, inside its bounding box, is told apart."""
    corners = np.asarray(positions, dtype=np.float64)[np.asarray(indices, dtype=np.int64).reshape(-1, 3)] - np.asarray(point, dtype=np.float64)
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
    triple = np.einsum("ij,ij->i", a, np.cross(b, c))
    below = la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", b, c) * la + np.einsum("ij,ij->i", c, a) * lb
    return float(2.0 * np.arctan2(triple, below).sum() / (4.0 * np.pi))
