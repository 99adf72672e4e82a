"""Fans: the corners around a vertex that its smooth edges join (crease_normals.py, step 2).

Two faces around a vertex are in one fan when they share an edge through it that is
smooth: exactly two faces meet there, both with area, neither flagged flat, and their unit
normals within the crease angle. Boundary and non-manifold edges are sharp. A fan is a
connected component of corners, found by hook-and-jump label propagation (scipy is not a
dependency) and numbered by its smallest corner.

Memory: where every vertex is on a crease (a voxel model, a CAD part), every half-edge of
the mesh goes through the edge analysis. Its ids are int32 (corner_ids.py), and the
half-edges are sorted a range of vertices at a time (by the smaller end's vertex, so an
edge's half-edges meet in one range): a sort of every half-edge's 64-bit key with its
order and sorted copy was ~24 bytes a corner at once (docs/performance.md, "Loading a
large mesh"). The fans are the same in any order of ranges: a component's smallest id
does not depend on the order its pairs are joined in.
"""

from __future__ import annotations

import math

import numpy as np

from .corner_ids import RANGE_IDS, id_type, ids_where, vertex_counts, vertex_ranges
from .face_normals import FACE_BLOCK, FaceNormals


def fan_labels(welded_faces, near_crease, normals: FaceNormals, crease_angle, flat, welded_count) -> np.ndarray:
    """Per corner: its welded vertex where that vertex is far from creases, else
    welded_count + a compact id of its fan, numbered in the order of their smallest corners."""
    corner_welded = welded_faces.reshape(-1)
    cos_crease = math.cos(math.radians(max(crease_angle, 0.0)))
    if crease_angle <= 0.0:
        cos_crease = 1.0 - 1e-12  # 0°: only (numerically) coplanar neighbours join
    left, right = _smooth_corner_pairs(welded_faces, near_crease, normals, cos_crease, flat, welded_count)
    keep = near_crease[corner_welded[left]]  # join corners only at the vertices being analysed
    left, right = left[keep], right[keep]
    del keep
    analysed = ids_where(near_crease[corner_welded])
    if len(analysed) < len(corner_welded):  # number the analysed corners 0..n-1 (all of them: already)
        compact = np.full(len(corner_welded), -1, id_type(len(corner_welded)))
        compact[analysed] = np.arange(len(analysed), dtype=compact.dtype)
        left, right = compact[left], compact[right]
        del compact
    roots = _components(len(analysed), left, right)
    del left, right
    # Each root's rank among the roots present: np.unique(roots, return_inverse=True)[1],
    # without sorting every corner (roots are ids below len(analysed)).
    present = np.zeros(len(analysed), bool)
    present[roots] = True
    rank = np.cumsum(present, dtype=roots.dtype) - 1
    del present
    label = corner_welded.astype(id_type(welded_count + len(analysed)))
    label[analysed] = welded_count + rank[roots]
    return label


def _components(count: int, left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Connected components of `count` nodes joined by the pairs: the smallest node id of
    each node's component (hook the larger root onto the smaller, then pointer-jump)."""
    label = np.arange(count, dtype=id_type(count))
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


def _smooth_corner_pairs(welded_faces, near_crease, normals: FaceNormals, cos_crease, flat, vertex_count):
    """Pairs of corners (3·face + k) joined by the smooth edges that touch a vertex near a
    crease, as two int32 arrays (in no particular order)."""
    corner_welded = welded_faces.reshape(-1)
    touching = near_crease[welded_faces]  # (F, 3): each corner's vertex is near a crease
    involved = (touching | touching[:, [1, 2, 0]]).reshape(-1)  # half-edge k runs from corner k to k + 1
    del touching
    ranges, lower = [(0, vertex_count)], None
    if np.count_nonzero(involved) > RANGE_IDS:  # an edge's half-edges share their lower vertex
        lower = np.minimum(welded_faces, welded_faces[:, [1, 2, 0]]).reshape(-1)
        ranges = vertex_ranges(vertex_counts(lower, vertex_count, involved))
    pairs = []
    for low, high in ranges:
        if len(ranges) == 1:
            halfedges = ids_where(involved)
        else:
            halfedges = ids_where(involved & (lower >= low) & (lower < high))
        pairs.append(_smooth_pairs_of(halfedges, corner_welded, normals, cos_crease, flat, vertex_count))
    del involved, lower
    left = np.concatenate([pair[0] for pair in pairs])
    right = np.concatenate([pair[1] for pair in pairs])
    return left, right


def _next_corner(corners: np.ndarray) -> np.ndarray:
    """The next corner of the same face (k → k + 1, 2 → 0)."""
    return corners + 1 - 3 * (corners % 3 == 2).astype(corners.dtype)


def _smooth_pairs_of(halfedges, corner_welded, normals: FaceNormals, cos_crease, flat, vertex_count):
    """Pairs of corners joined by the smooth edges among `halfedges` (ascending ids; every
    half-edge of an edge among them or none)."""
    start, end = corner_welded[halfedges], corner_welded[_next_corner(halfedges)]
    key = np.minimum(start, end).astype(np.int64) * vertex_count + np.maximum(start, end)
    del start, end
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    del key
    run_start = np.ones(len(sorted_key), bool)
    run_start[1:] = sorted_key[1:] != sorted_key[:-1]
    del sorted_key
    starts = np.flatnonzero(run_start)
    del run_start
    first = starts[np.diff(starts, append=len(order)) == 2]  # manifold: exactly two
    del starts
    h1, h2 = halfedges[order[first]], halfedges[order[first + 1]]
    del order, first
    f1, f2 = h1 // 3, h2 // 3
    smooth = np.empty(len(f1), bool)
    for block_start in range(0, len(f1), FACE_BLOCK):  # the two faces' normals a block at a time
        block = slice(block_start, block_start + FACE_BLOCK)
        unit1, area1 = normals.of(f1[block])
        unit2, area2 = normals.of(f2[block])
        smooth[block] = (area1 > 0) & (area2 > 0) & (f1[block] != f2[block])
        smooth[block] &= np.einsum("ij,ij->i", unit1, unit2) >= cos_crease
    if flat is not None:
        smooth &= ~(flat[f1] | flat[f2])
    a1, a2 = h1[smooth], h2[smooth]  # the corners at the edge's start in face 1 and in face 2
    del h1, h2, f1, f2, smooth
    b1, b2 = _next_corner(a1), _next_corner(a2)  # and at its end
    consistent = corner_welded[a2] == corner_welded[b1]  # opposite direction: face 2's start is face 1's end
    a2, b2 = np.where(consistent, b2, a2), np.where(consistent, a2, b2)
    return np.concatenate([a1, b1]), np.concatenate([a2, b2])
