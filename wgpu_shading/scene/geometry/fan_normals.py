"""Normals summed around a vertex or a fan of faces (crease_normals.py): the normalized sum
of the faces' unit normals (the seeds' rule), and where that sum cancels the largest face's
normal. Faces' normals are computed a block at a time (face_normals.py), never kept per face:
the sums are bit for bit those of one np.bincount over every face, in any block size."""

from __future__ import annotations

import numpy as np

from .corner_ids import MAX_RANGES, ids_where
from .face_normals import FACE_BLOCK, FaceNormals

FAN_RANGE = 1 << 21  # fans summed at a time (fan_normals): 64 MB of float64 sums
LENGTHS_AT_ONCE = 1 << 20  # sums' lengths compared with their counts at a time (_normalized): 16 MB of temporaries


def _normalized(summed: np.ndarray, adjacent: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(unit sums, their lengths, cancelled), normalized in place: a sum of k unit vectors
    shorter than 1e-6·k has cancelled, its direction is noise (left zero here)."""
    length = np.einsum("ij,ij->i", summed, summed)
    np.sqrt(length, out=length)
    good = np.empty(len(length), bool)
    for start in range(0, len(length), LENGTHS_AT_ONCE):  # (no third per-vertex float64 array)
        block = slice(start, start + LENGTHS_AT_ONCE)
        good[block] = length[block] > 1e-6 * np.maximum(adjacent[block], 1.0)
    np.divide(summed, length[:, None], out=summed, where=good[:, None])
    summed[~good] = 0.0
    return summed, length, ~good & (adjacent > 0)


def largest_face_normals(result, cancelled, labels, corner_faces, normals: FaceNormals) -> None:
    """Where the sum cancelled, the normal of the largest face around it (the seeds' rule;
    of equal areas, the last corner's; faces without area never). The corners are looked
    at FACE_BLOCK at a time, each label keeping its best face so far: where every vertex
    cancels (a hostile OBJ of one face of repeated corners), all corners' normals at once
    were ~200 bytes a corner."""
    wanted = np.flatnonzero(cancelled)
    slot = np.full(len(cancelled), -1, np.int64)  # label → its place among `wanted`
    slot[wanted] = np.arange(len(wanted))
    best_area = np.zeros(len(wanted))
    best_face = np.full(len(wanted), -1, np.int64)
    for start in range(0, len(labels), FACE_BLOCK):
        block_slots = slot[labels[start : start + FACE_BLOCK]]
        corners = np.flatnonzero(block_slots >= 0)
        if not len(corners):
            continue
        slots = block_slots[corners]
        corners += start
        face_ids = corners // 3 if corner_faces is None else corner_faces[corners]
        _, area = normals.of(face_ids)
        order = np.lexsort((corners, area, slots))  # by label, then area, then corner
        last = np.append(slots[order][1:] != slots[order][:-1], True)
        pick = order[last]  # each label's largest face of the block, the last corner of equal ones
        better = (area[pick] > 0) & (area[pick] >= best_area[slots[pick]])
        best_area[slots[pick][better]] = area[pick][better]
        best_face[slots[pick][better]] = face_ids[pick][better]
    found = best_face >= 0
    if found.any():
        unit, _ = normals.of(best_face[found])
        result[wanted[found]] = unit


def mean_normals(normals: FaceNormals, welded_faces, count: int):
    """Per welded vertex: the normalized sum of its faces' unit normals (the seeds' rule),
    k − |sum| (how far its k unit normals are from all being equal), and the faces without
    area. One pass over blocks of faces: no per-face array is kept.

    Each vertex's sum runs over its corners in corner order (face by face), as fan_normals
    sums a fan's and as one np.bincount over every corner would: np.add.at continues a
    block where the last one stopped, so the normals do not depend on the block size. The
    sums are kept as (count, 3) rows, what the rest of the analysis reads: one per-vertex
    array of sums (24 bytes a vertex) and the counts beside them. Summed a corner slot at a
    time instead (three (3, count) arrays, then a transposed copy), 5M vertices held
    280 MB here where these hold 160, and big meshes computed every face's normal twice."""
    adjacent = np.zeros(count)
    degenerate = []
    summed = np.zeros((count, 3))
    # A small mesh keeps its face normals: all faces are one block, and a bincount is the
    # same sum as add.at into zeros, and faster.
    block = max(len(welded_faces), 1) if normals.kept is not None else FACE_BLOCK
    if block >= len(welded_faces):
        def add_at(sums, labels, weights):
            sums += np.bincount(labels, weights=weights, minlength=count)
    else:
        add_at = np.add.at
    for start in range(0, len(welded_faces), block):
        unit, area = normals.of(slice(start, start + block))
        labels = welded_faces[start : start + block].astype(np.intp).reshape(-1)  # the block's corners, in order
        for j in range(3):
            add_at(summed[:, j], labels, np.repeat(unit[:, j], 3))
        # faces with area around each vertex: whole numbers, exact in any order
        add_at(adjacent, labels, np.repeat((area > 0).astype(np.float64), 3))
        degenerate.append(np.flatnonzero(area <= 0) + start)
    mean_normal, length, cancelled = _normalized(summed, adjacent)
    if cancelled.any():
        largest_face_normals(mean_normal, cancelled, welded_faces.reshape(-1), None, normals)
    spread = np.subtract(adjacent, length, out=adjacent)  # (in place: no third per-vertex array)
    return mean_normal, spread, np.concatenate(degenerate)


def fan_normals(labels, corner_faces, normals: FaceNormals, out: np.ndarray) -> None:
    """Per fan label (0..len(out)-1), into `out` (float32 rows: what a Mesh keeps): the
    normalized sum of the unit normals of the faces of its corners; where it cancels, the
    largest face's normal. Many corners (every vertex on a crease) are summed FACE_BLOCK at
    a time with np.add.at, which goes on where the last block stopped: the same sums, in
    the same order, as one np.bincount (mean_normals). Many fans are summed a range of
    FAN_RANGE or more at a time, each range's corners in their order: float64 sums of every
    fan at once were 32 bytes a fan, as much as the Mesh's arrays of a mesh whose every
    vertex is on a crease."""
    count = len(out)
    if count <= FAN_RANGE:
        out[:] = _fan_range_normals(labels, corner_faces, normals, count)
        return
    per_range = max(FAN_RANGE, -(-count // MAX_RANGES))  # (each range a pass over every label)
    for low in range(0, count, per_range):
        high = min(low + per_range, count)
        chosen = ids_where((labels >= low) & (labels < high))
        out[low:high] = _fan_range_normals(labels[chosen] - low, corner_faces[chosen], normals, high - low)


def _fan_range_normals(labels, corner_faces, normals: FaceNormals, count: int) -> np.ndarray:
    """fan_normals of labels 0..count-1, as float64 rows."""
    if len(labels) <= FACE_BLOCK:
        unit, area = normals.of(corner_faces)
        summed = np.stack([np.bincount(labels, weights=unit[:, k], minlength=count) for k in range(3)], axis=1)
        adjacent = np.bincount(labels, weights=(area > 0).astype(float), minlength=count)
    else:  # (summed in place, a component at a time: no second array of every fan's sums)
        summed, adjacent = np.zeros((count, 3)), np.zeros(count)
        for start in range(0, len(labels), FACE_BLOCK):
            block = slice(start, start + FACE_BLOCK)
            unit, area = normals.of(corner_faces[block])
            block_labels = labels[block].astype(np.intp)
            for k in range(3):
                np.add.at(summed[:, k], block_labels, np.ascontiguousarray(unit[:, k]))
            np.add.at(adjacent, block_labels, (area > 0).astype(float))
    result, _, cancelled = _normalized(summed, adjacent)
    if cancelled.any():
        largest_face_normals(result, cancelled, labels, corner_faces, normals)
    return result
