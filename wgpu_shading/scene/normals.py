"""Welded, creased vertex normals (SPEC §12), vectorised in numpy.

Files split vertices wherever a UV seam runs, and STL files split every vertex (a
triangle soup): averaging per given vertex would show every seam as a crease and every
STL as faceted. So, when the file has no normals:

1. Weld by position: vertices with equal coordinates are one (a lexsort, not np.unique
   on rows, which is 5x slower; −0.0 and 0.0 compare equal).
2. Per welded vertex, its faces form *fans*: two faces around the vertex are in one fan
   when they share an edge through it that is smooth — exactly two faces meet there, both
   with area, not flagged flat, and their unit normals within the crease angle. Boundary
   and non-manifold edges are sharp. A fan is a connected component of corners, found by
   hook-and-jump label propagation (scipy is not a dependency).
3. Each fan's normal is the normalized sum of its faces' unit normals (the seeds' rule);
   where the sum cancels, the largest face's normal.
4. One output vertex per (given vertex, fan): UV seams and vertex colors stay split, and
   vertices split further only where a crease runs through them.
"""

from __future__ import annotations

import math

import numpy as np



def face_normals(positions: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit face normals (zero for zero-area faces) and twice the face areas, float64."""
    p0, p1, p2 = (positions[faces[:, k]] for k in range(3))
    cross = np.cross(p1 - p0, p2 - p0)
    length = np.linalg.norm(cross, axis=1)
    scale = np.max(np.abs(positions)) if len(positions) else 1.0
    # "zero area" relative to the mesh's own scale, so tiny meshes (1e-5) keep their faces
    degenerate = length <= 1e-12 * max(scale, 1e-300) ** 2
    unit = np.zeros_like(cross)
    np.divide(cross, length[:, None], out=unit, where=~degenerate[:, None])
    return unit, np.where(degenerate, 0.0, length)


def weld_by_position(positions: np.ndarray) -> np.ndarray:
    """(N,) id of each vertex's welded vertex (equal coordinates share an id, 0..M-1)."""
    count = len(positions)
    order = np.lexsort((positions[:, 2], positions[:, 1], positions[:, 0]))
    ordered = positions[order]
    new = np.empty(count, bool)
    new[:1] = True
    new[1:] = np.any(ordered[1:] != ordered[:-1], axis=1)
    welded = np.empty(count, np.int64)
    welded[order] = np.cumsum(new) - 1
    return welded


def _smooth_corner_pairs(welded_faces: np.ndarray, unit: np.ndarray, area: np.ndarray, cos_crease: float, flat: np.ndarray | None):
    """Pairs of corners (indices 3·face + k) that belong to one fan: the two corners at each
    end of every smooth edge."""
    face_count = len(welded_faces)
    start = welded_faces.reshape(-1)  # half-edge h = 3f + k runs from corner k to corner k+1
    end = welded_faces[:, [1, 2, 0]].reshape(-1)
    low, high = np.minimum(start, end), np.maximum(start, end)
    key = low * (int(welded_faces.max()) + 1) + high
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    same_as_next = sorted_key[1:] == sorted_key[:-1]
    # Manifold edges: exactly two half-edges with this key.
    run_start = np.ones(len(sorted_key), bool)
    run_start[1:] = ~same_as_next
    run_id = np.cumsum(run_start) - 1
    run_length = np.bincount(run_id)
    first = np.flatnonzero(run_start & (run_length[run_id] == 2))
    h1, h2 = order[first], order[first + 1]
    f1, f2 = h1 // 3, h2 // 3
    smooth = (area[f1] > 0) & (area[f2] > 0) & (f1 != f2)
    smooth &= np.einsum("ij,ij->i", unit[f1], unit[f2]) >= cos_crease
    if flat is not None:
        smooth &= ~(flat[f1] | flat[f2])
    h1, h2 = h1[smooth], h2[smooth]
    f1, f2, k1, k2 = h1 // 3, h2 // 3, h1 % 3, h2 % 3
    a1, b1 = 3 * f1 + k1, 3 * f1 + (k1 + 1) % 3  # the corners at the edge's two ends in face 1
    a2, b2 = 3 * f2 + k2, 3 * f2 + (k2 + 1) % 3
    consistent = start[a2] == start[b1]  # opposite direction: face 2's start is face 1's end
    a2, b2 = np.where(consistent, b2, a2), np.where(consistent, a2, b2)
    del face_count
    return np.concatenate([a1, b1]), np.concatenate([a2, b2])


def _components(count: int, left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Connected components of `count` nodes joined by the pairs: the smallest node id of
    each node's component (hook the larger root onto the smaller, then pointer-jump)."""
    label = np.arange(count, dtype=np.int64)
    while True:
        root_left, root_right = label[left], label[right]
        differ = root_left != root_right
        if not differ.any():
            return label
        root_left, root_right = root_left[differ], root_right[differ]
        left, right = left[differ], right[differ]
        smaller = np.minimum(root_left, root_right)
        np.minimum.at(label, np.maximum(root_left, root_right), smaller)
        while True:  # pointer jumping: every node straight to its root
            jumped = label[label]
            if np.array_equal(jumped, label):
                break
            label = jumped


def crease_normals(positions: np.ndarray, faces: np.ndarray, crease_angle: float, flat_faces: np.ndarray | None = None):
    """Normals welded by position and split at creases sharper than `crease_angle` degrees.

    Returns (source, faces, normals): source (M,) is the given vertex each output vertex
    copies (None when no vertex had to be split: then faces are the given ones and
    normals are per given vertex), faces (F, 3) uint32 and normals (M, 3) float64 unit.
    """
    positions = np.asarray(positions, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    vertex_count, face_count = len(positions), len(faces)
    welded = weld_by_position(positions)
    welded_faces = welded[faces]
    unit, area = face_normals(positions, faces)
    flat = None if flat_faces is None else np.asarray(flat_faces, bool)
    corners = 3 * face_count
    if crease_angle >= 180.0 and (flat is None or not flat.any()):
        fan = welded_faces.reshape(-1)  # one fan per welded vertex: the plain average
    else:
        cos_crease = math.cos(math.radians(max(crease_angle, 0.0)))
        if crease_angle <= 0.0:
            cos_crease = 1.0 - 1e-12  # 0°: only (numerically) coplanar neighbours join
        left, right = _smooth_corner_pairs(welded_faces, unit, area, cos_crease, flat)
        fan = _components(corners, left, right)
    corner_face = np.repeat(np.arange(face_count), 3)
    summed = np.stack([np.bincount(fan, weights=unit[corner_face, k], minlength=corners) for k in range(3)], axis=1)
    length = np.linalg.norm(summed, axis=1)
    adjacent = np.bincount(fan, weights=(area[corner_face] > 0).astype(float), minlength=corners)
    fan_normal = np.zeros_like(summed)
    good = length > 1e-6 * np.maximum(adjacent, 1.0)
    fan_normal[good] = summed[good] / length[good, None]
    cancelled = ~good & (adjacent > 0)
    if cancelled.any():  # the largest face of the fan wins (faces in increasing area order)
        order = np.argsort(area[corner_face], kind="stable")
        keep = cancelled[fan[order]] & (area[corner_face[order]] > 0)
        fan_normal[fan[order][keep]] = unit[corner_face[order][keep]]
    flat_corners = faces.reshape(-1)
    # Does every given vertex lie in exactly one fan? Then no vertex needs splitting.
    vertex_fan = np.full(vertex_count, -1, np.int64)
    vertex_fan[flat_corners] = fan
    if np.array_equal(vertex_fan[flat_corners], fan):
        normals = np.zeros((vertex_count, 3))
        used = vertex_fan >= 0
        normals[used] = fan_normal[vertex_fan[used]]
        return None, faces.astype(np.uint32), normals
    key = flat_corners * corners + fan
    unique_keys, inverse = np.unique(key, return_inverse=True)
    source = unique_keys // corners
    normals = fan_normal[unique_keys % corners]
    return source, inverse.reshape(-1, 3).astype(np.uint32), normals
