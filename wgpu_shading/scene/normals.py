"""Welded, creased vertex normals (docs/real-world-files.md), vectorised in numpy.

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

from ..errors import MeshError

FACE_BLOCK = 1 << 18


def face_normals(positions: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit face normals (zero for zero-area faces) and twice the face areas, float64."""
    # Component by component: np.cross on (F, 3) arrays and row gathers cost 4x more.
    # In blocks of faces: the eleven temporaries per face stay ~25 MB however big the
    # mesh (a 10M-triangle scan needed 1 GB for them at once; docs/reliability.md).
    x, y, z = (np.ascontiguousarray(positions[:, k], dtype=np.float64) for k in range(3))
    scale = np.max(np.abs(positions)) if len(positions) else 1.0
    unit = np.zeros((len(faces), 3))
    area = np.zeros(len(faces))
    for start in range(0, len(faces), FACE_BLOCK):
        block = faces[start : start + FACE_BLOCK]
        i0, i1, i2 = (np.ascontiguousarray(block[:, k]) for k in range(3))
        ax, ay, az = x[i1] - x[i0], y[i1] - y[i0], z[i1] - z[i0]
        bx, by, bz = x[i2] - x[i0], y[i2] - y[i0], z[i2] - z[i0]
        cross = np.empty((len(block), 3))
        cross[:, 0] = ay * bz - az * by
        cross[:, 1] = az * bx - ax * bz
        cross[:, 2] = ax * by - ay * bx
        length = np.sqrt(np.einsum("ij,ij->i", cross, cross))
        # "zero area" relative to the mesh's own scale, so tiny meshes (1e-5) keep their faces
        degenerate = length <= 1e-12 * max(scale, 1e-300) ** 2
        np.divide(cross, length[:, None], out=unit[start : start + len(block)], where=~degenerate[:, None])
        area[start : start + len(block)] = np.where(degenerate, 0.0, length)
    return unit, area


def vertex_normals(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Normalized sum of the unit normals of the faces around each vertex (the seeds' rule, docs/conventions.md#vertex-normals).

    Zero-area faces contribute nothing. Where the sum cancels (a vertex shared by a
    thin double-sided sheet, say), the normal of the largest adjacent face is used
    instead, so every vertex that touches a real face gets a unit normal. Vertices
    that touch no face with area keep a zero normal; the shaders then fall back to
    the geometric normal.
    """
    positions = np.asarray(positions, dtype=np.float64)
    unit_faces, areas = face_normals(positions, faces)
    count = len(positions)
    flat_vertices = faces.reshape(-1)
    summed = np.stack(
        [np.bincount(flat_vertices, weights=np.repeat(unit_faces[:, k], 3), minlength=count) for k in range(3)],
        axis=1,
    )
    length = np.linalg.norm(summed, axis=1)
    adjacent = np.bincount(flat_vertices, weights=np.repeat((areas > 0).astype(float), 3), minlength=count)
    # A sum of k unit vectors that is shorter than 1e-6·k has cancelled: its direction is noise.
    cancelled = (length <= 1e-6 * np.maximum(adjacent, 1.0)) & (adjacent > 0)
    result = np.zeros_like(summed)
    good = length > 0
    good &= ~cancelled
    result[good] = summed[good] / length[good, None]
    if cancelled.any():
        # The largest adjacent face wins: sort faces by area and let larger ones overwrite.
        order = np.argsort(areas)
        corner_vertices = faces[order].reshape(-1)
        corner_normals = np.repeat(unit_faces[order], 3, axis=0)
        corner_areas = np.repeat(areas[order], 3)
        keep = cancelled[corner_vertices] & (corner_areas > 0)
        result[corner_vertices[keep]] = corner_normals[keep]
    return result


def validated_normals(normals: np.ndarray, positions: np.ndarray, faces: np.ndarray, name: str) -> np.ndarray:
    if normals.shape != positions.shape:
        raise MeshError(f"{name}: normals must have shape {positions.shape}, got {normals.shape}")
    squared = np.einsum("ij,ij->i", normals, normals)
    if np.all(np.abs(squared - 1.0) < 1e-9):  # already unit (and so finite): computed ones, most files
        return normals
    finite = np.isfinite(normals).all(axis=1)
    length = np.linalg.norm(np.where(finite[:, None], normals, 0.0), axis=1)
    usable = finite & (length > 1e-20)
    result = np.zeros_like(normals)
    result[usable] = normals[usable] / length[usable, None]
    if not usable.all():
        # Zero-length or NaN normals in the input: replace those with computed ones
        # rather than let normalize(0) reach the shader.
        computed = vertex_normals(positions, faces)
        result[~usable] = computed[~usable]
    return result


def weld_by_position(positions: np.ndarray) -> np.ndarray:
    """(N,) id of each vertex's welded vertex (equal coordinates share an id, 0..M-1)."""
    count = len(positions)
    # Fast path for meshes that are already welded (scans, most PLY/OBJ): one sort of a
    # single key. Equal positions give equal keys, so distinct keys prove distinct
    # positions; equal keys (a duplicate, or a rare coincidence) take the full lexsort.
    key = np.sort(positions[:, 0] + 0.7548776662466927 * positions[:, 1] + 0.5698402909980532 * positions[:, 2])
    if not np.any(key[1:] == key[:-1]):
        return np.arange(count, dtype=np.int64)
    order = np.lexsort((positions[:, 2], positions[:, 1], positions[:, 0]))
    ordered = positions[order]
    new = np.empty(count, bool)
    new[:1] = True
    new[1:] = np.any(ordered[1:] != ordered[:-1], axis=1)
    if new.all():  # a coincidence of keys, no duplicate: the identity, as above
        return np.arange(count, dtype=np.int64)
    welded = np.empty(count, np.int64)
    welded[order] = np.cumsum(new) - 1
    return welded


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


def _summed_normals(labels: np.ndarray, corner_faces: np.ndarray | None, unit: np.ndarray, area: np.ndarray, count: int,
                    spread: list | None = None) -> np.ndarray:
    """Per label (0..count-1): the normalized sum of the unit normals of the faces of its
    corners (corner_faces None: every corner, in order); where the sum cancels, the
    largest face's normal (the seeds' rule)."""
    if corner_faces is None:
        # Corner k of every face at once: 9 bincounts over F values are 2x faster than 3
        # over 3F repeated weights (no (3F,) temporaries).
        columns = [np.ascontiguousarray(unit[:, j]) for j in range(3)]
        has_area = (area > 0).astype(float)
        summed = np.zeros((count, 3))
        adjacent = np.zeros(count)
        for k in range(3):
            corner_labels = np.ascontiguousarray(labels.reshape(-1, 3)[:, k])
            for j in range(3):
                summed[:, j] += np.bincount(corner_labels, weights=columns[j], minlength=count)
            adjacent += np.bincount(corner_labels, weights=has_area, minlength=count)
        del columns, has_area, corner_labels  # 4 floats a face, not needed below
    else:
        summed = np.stack([np.bincount(labels, weights=unit[corner_faces, k], minlength=count) for k in range(3)], axis=1)
        adjacent = np.bincount(labels, weights=(area[corner_faces] > 0).astype(float), minlength=count)
    length = np.sqrt(np.einsum("ij,ij->i", summed, summed))
    if spread is not None:  # k − |sum|: how far the k unit normals are from all being equal
        spread.append(adjacent - length)
    # A sum of k unit vectors shorter than 1e-6·k has cancelled: its direction is noise.
    good = length > 1e-6 * np.maximum(adjacent, 1.0)
    result = np.zeros_like(summed)
    result[good] = summed[good] / length[good, None]
    cancelled = ~good & (adjacent > 0)
    if cancelled.any():  # larger faces overwrite smaller ones
        if corner_faces is None:
            corner_faces = np.repeat(np.arange(len(unit)), 3)
        order = np.argsort(area[corner_faces], kind="stable")
        keep = cancelled[labels[order]] & (area[corner_faces[order]] > 0)
        result[labels[order][keep]] = unit[corner_faces[order][keep]]
    return result


def crease_normals(positions: np.ndarray, faces: np.ndarray, crease_angle: float, flat_faces: np.ndarray | None = None):
    """Normals welded by position and split at creases sharper than `crease_angle` degrees.

    Returns (source, faces, normals): source (M,) is the given vertex each output vertex
    copies (None when no vertex had to be split: then faces are the given ones and
    normals are per given vertex), faces (F, 3) uint32 and normals (M, 3) float64 unit.

    Speed: the edge analysis (a sort of half-edges) runs only around vertices where some
    face normal is more than half the crease angle from the vertex's mean normal; at all
    other vertices no two faces can be a crease apart, so their faces form one fan. On a
    smooth scan that is no vertex at all.
    """
    positions = np.asarray(positions, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    vertex_count, face_count = len(positions), len(faces)
    welded = weld_by_position(positions)
    welded_count = int(welded.max()) + 1
    # Already welded (weld_by_position returns the identity then): no (F, 3) gather.
    welded_faces = faces if welded_count == vertex_count else welded[faces]
    corner_welded = welded_faces.reshape(-1)
    unit, area = face_normals(positions, faces)
    spread: list = []
    mean_normal = _summed_normals(corner_welded, None, unit, area, welded_count, spread)
    flat = None if flat_faces is None or not np.any(flat_faces) else np.asarray(flat_faces, bool)
    label = corner_welded  # a fan per welded vertex (index into `table`)
    table = mean_normal
    if crease_angle < 180.0 or flat is not None:
        # Corners whose face leans more than crease/2 from the vertex's mean normal (or is
        # flat, or has no area) put their vertex under the full per-fan analysis.
        half = math.radians(min(max(crease_angle, 0.0), 180.0)) / 2.0
        # Cheap exact pre-test: with k unit normals of sum S around a vertex, each one's
        # cosine to the mean is at least |S| − (k − 1); so k − |S| <= 1 − cos(half) clears
        # the vertex without looking at its corners (every vertex of a smooth scan).
        maybe = spread[0] > (1.0 - math.cos(half)) - 1e-9
        near_crease = np.zeros(welded_count, bool)
        if maybe.any():
            corners = np.flatnonzero(maybe[corner_welded])  # only their corners: the exact test
            corner_vertex = corner_welded[corners]
            lean = np.einsum("ij,ij->i", mean_normal[corner_vertex], unit[corners // 3])
            near_crease[corner_vertex[lean < math.cos(half) - 1e-9]] = True
        degenerate = np.flatnonzero(area <= 0)
        if len(degenerate):
            near_crease[welded_faces[degenerate].reshape(-1)] = True
        if flat is not None:
            near_crease[welded_faces[flat].reshape(-1)] = True
        if near_crease.any():
            corner_faces = np.repeat(np.arange(face_count), 3)
            label = _fan_labels(welded_faces, near_crease, unit, area, crease_angle, flat, corner_faces, welded_count)
            extra = int(label.max()) + 1 - welded_count
            if extra > 0:
                crease_corners = np.flatnonzero(label >= welded_count)
                fan_normals = _summed_normals(label[crease_corners] - welded_count, corner_faces[crease_corners], unit, area, extra)
                table = np.vstack([mean_normal, fan_normals])
    if label is corner_welded:  # one fan per welded vertex: every given vertex takes its vertex's
        return None, faces.astype(np.uint32), table[welded]
    flat_corners = faces.reshape(-1)
    # Does every given vertex lie in exactly one fan? Then no vertex needs splitting.
    vertex_fan = np.full(vertex_count, -1, np.int64)
    vertex_fan[flat_corners] = label
    if np.array_equal(vertex_fan[flat_corners], label):
        normals = np.zeros((vertex_count, 3))
        used = vertex_fan >= 0
        normals[used] = table[vertex_fan[used]]
        return None, faces.astype(np.uint32), normals
    key = flat_corners * len(table) + label
    unique_keys, inverse = np.unique(key, return_inverse=True)
    source = unique_keys // len(table)
    normals = table[unique_keys % len(table)]
    return source, inverse.reshape(-1, 3).astype(np.uint32), normals


def _fan_labels(welded_faces, near_crease, unit, area, crease_angle, flat, corner_faces, welded_count) -> np.ndarray:
    """Per corner: its welded vertex where that vertex is far from creases, else
    welded_count + a compact id of its fan (connected corners around the vertex)."""
    corner_welded = welded_faces.reshape(-1)
    start = corner_welded
    end = welded_faces[:, [1, 2, 0]].reshape(-1)
    involved = np.flatnonzero(near_crease[start] | near_crease[end])  # half-edges touching such a vertex
    cos_crease = math.cos(math.radians(max(crease_angle, 0.0)))
    if crease_angle <= 0.0:
        cos_crease = 1.0 - 1e-12  # 0°: only (numerically) coplanar neighbours join
    left, right = _smooth_corner_pairs_of(involved, start, end, unit, area, cos_crease, flat)
    keep = near_crease[start[left]]  # join corners only at the vertices being analysed
    left, right = left[keep], right[keep]
    analysed = np.flatnonzero(near_crease[corner_welded])
    compact = np.full(len(corner_welded), -1, np.int64)
    compact[analysed] = np.arange(len(analysed))
    roots = _components(len(analysed), compact[left], compact[right])
    _, fan_id = np.unique(roots, return_inverse=True)
    label = corner_welded.copy()
    label[analysed] = welded_count + fan_id
    return label


def _smooth_corner_pairs_of(halfedges, start, end, unit, area, cos_crease, flat):
    """Pairs of corners (3·face + k) joined by the smooth edges among `halfedges`."""
    low, high = np.minimum(start[halfedges], end[halfedges]), np.maximum(start[halfedges], end[halfedges])
    key = low * (int(high.max()) + 1 if len(high) else 1) + high
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    run_start = np.ones(len(sorted_key), bool)
    run_start[1:] = sorted_key[1:] != sorted_key[:-1]
    run_id = np.cumsum(run_start) - 1
    run_length = np.bincount(run_id)
    first = np.flatnonzero(run_start & (run_length[run_id] == 2))  # manifold: exactly two
    h1, h2 = halfedges[order[first]], halfedges[order[first + 1]]
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
    return np.concatenate([a1, b1]), np.concatenate([a2, b2])
