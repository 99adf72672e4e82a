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
_BLOCK = 1 << 14  # triangles a step: the edge codes' temporaries stay small


def solid_orientation(
    positions: np.ndarray, indices: np.ndarray, weld_tolerance: float = WELD_TOLERANCE, each_piece: bool = False
) -> int:
    """+1 if the triangles form closed surfaces wound counter-clockwise seen from outside,
    −1 if closed and wound the other way (inside out), 0 if not closed. With `each_piece`,
    the sign is that of every connected piece's own volume, and 0 where they differ (a
    flipped piece beside a bigger right one would otherwise pass as +1).

    Vertices within `weld_tolerance` of the mesh's size of each other are one vertex (a
    file's seams may repeat a vertex with a last-digit difference); with 0, only vertices
    at exactly the same position are (a surface closed that way has no crack for the
    rasterizer either: render/gpu/clusters.py). Triangles with a repeated vertex cover
    nothing and are dropped. The surface is closed and consistently wound when every edge
    is shared by exactly two triangles that run along it in opposite directions: every
    directed edge (a, b) occurs once and its reverse (b, a) once. Written with numpy rather
    than through trimesh (its watertight and winding checks say the same) to keep trimesh's
    import (~0.3 s) out of a render that casts shadows."""
    if len(indices) == 0:
        return 0
    positions = np.asarray(positions)
    centre = positions.mean(axis=0, dtype=np.float64)
    size = float(np.abs(positions - centre).max()) if weld_tolerance else 1.0
    if size == 0.0:
        return 0
    welded = weld_by_position(np.round((positions - centre) / (weld_tolerance * size)) if weld_tolerance else positions)
    count = int(welded.max()) + 1
    indices = np.asarray(indices).reshape(-1, 3)
    if not directed_edges_may_pair(welded, indices):
        return 0
    # Each edge's code (its two vertices, lower first: int64, up to 2·count²) twice, with
    # the direction it is run along in the lowest bit; a block of triangles at a time (the
    # temporaries stay small). Triangles with a repeated vertex leave their codes at -1.
    codes = np.empty(3 * len(indices), np.int64)
    volume = 0.0
    volumes = np.empty(len(indices))
    for start in range(0, len(indices), _BLOCK):
        block = welded[indices[start : start + _BLOCK]].astype(np.int64)
        empty = (block[:, 0] == block[:, 1]) | (block[:, 1] == block[:, 2]) | (block[:, 2] == block[:, 0])
        for slot in range(3):
            begin, end = block[:, slot], block[:, (slot + 1) % 3]
            code = (np.minimum(begin, end) * count + np.maximum(begin, end)) * 2 + (begin < end)
            code[empty] = -1
            codes[3 * start + slot * len(block) : 3 * start + (slot + 1) * len(block)] = code
        # The signed volume (divergence theorem, relative to the centre for precision).
        a, b, c = (positions[indices[start : start + _BLOCK, slot]] - centre for slot in range(3))
        volumes[start : start + _BLOCK] = (a[:, 0] * (b[:, 1] * c[:, 2] - b[:, 2] * c[:, 1]) + a[:, 1] * (b[:, 2] * c[:, 0] - b[:, 0] * c[:, 2])
                                           + a[:, 2] * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])) / 6.0
        volume += float(volumes[start : start + _BLOCK].sum())
    codes.sort()
    codes = codes[np.searchsorted(codes, 0) :]
    # A closed, consistent surface sorts into pairs (edge, 0), (edge, 1), each edge in one pair only.
    if len(codes) == 0 or len(codes) % 2:
        return 0
    down, up = codes[0::2], codes[1::2]
    if not (np.array_equal(down >> 1, up >> 1) and not (down & 1).any() and (up & 1).all()):
        return 0
    if (down[1:] >> 1 == down[:-1] >> 1).any():  # an edge shared by more than two triangles
        return 0
    del codes, down, up  # (before the pieces' arrays: a lower peak)
    if volume == 0.0:
        return 0
    orientation = 1 if volume > 0.0 else -1
    if each_piece:
        piece = _pieces(welded[indices], count)
        # (the pieces present by bincount, not np.unique: numpy 2's imports numpy.ma, ~10 ms of a cold start)
        sums = np.bincount(piece, weights=volumes, minlength=count)[np.bincount(piece, minlength=count) > 0]
        if not (orientation * sums > 0.0).all():
            return 0
    return orientation


def directed_edges_may_pair(welded: np.ndarray, indices: np.ndarray) -> bool:
    """False when the directed edges cannot pair up with their reverses, which proves the
    surface open or inconsistently wound (solid_orientation's answer 0) without the sort of
    every edge code: most open meshes (scans with holes, a dataset's models) stop here (the
    69K-triangle Stanford bunny's Mesh.exact_solid: 28 → 13 ms, most of what is left the
    weld; a closed mesh pays ~10 % more for the count).

    A weighted count: each vertex gets two pseudo-random 64-bit weights f and g, and every
    directed edge (a, b) adds f[a]·g[b] − f[b]·g[a]. When each directed edge occurs exactly
    as often as its reverse the terms cancel, and modulo 2^64 (numpy's unsigned wrap) they
    cancel exactly; a triangle with a repeated vertex adds 0 on its own, as the full test
    drops it. So a non-zero sum means some edge's count differs from its reverse's, and
    the full test would return 0 too. A zero sum proves nothing: the full test decides."""
    f, g = (_mixed(np.arange(int(welded.max()) + 1, dtype=np.uint64) * np.uint64(2) + np.uint64(k)) for k in (0, 1))
    total = 0  # (a Python int, reduced mod 2^64: numpy's scalars warn where its arrays wrap)
    for start in range(0, len(indices), _BLOCK):
        block = welded[indices[start : start + _BLOCK]]
        for slot in range(3):
            a, b = block[:, slot], block[:, (slot + 1) % 3]
            total += int((f[a] * g[b]).sum(dtype=np.uint64)) - int((f[b] * g[a]).sum(dtype=np.uint64))
    return total % (1 << 64) == 0


def _mixed(values: np.ndarray) -> np.ndarray:
    """SplitMix64's output function (Steele, Lea and Flood, "Fast splittable pseudorandom
    number generators", OOPSLA 2014): well-spread 64-bit weights from consecutive integers,
    without importing numpy.random (~8 ms of a cold start)."""
    z = values + np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def _pieces(triangles: np.ndarray, count: int) -> np.ndarray:
    """Each triangle's connected piece (triangles sharing a vertex are connected), as the
    lowest vertex number of the piece: union by hooking every vertex's label to its
    triangles' lowest, then pointer jumping, until the three corners of every triangle
    agree (a few rounds: the labels halve their distance to the root each jump)."""
    label = np.arange(count, dtype=triangles.dtype)  # (int32, as weld_by_position's ids)
    while True:
        corners = label[triangles]
        lowest = corners.min(axis=1)
        if (corners == lowest[:, None]).all():
            return lowest
        for slot in range(3):
            np.minimum.at(label, corners[:, slot], lowest)
        while True:
            jumped = label[label]
            if np.array_equal(jumped, label):
                break
            label = jumped


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
