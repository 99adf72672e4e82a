"""Welded, creased vertex normals (docs/real-world-files.md), vectorised in numpy.

Files split vertices wherever a UV seam runs, and STL files split every vertex (a
triangle soup): averaging per given vertex would show every seam as a crease and every
STL as faceted. So, when the file has no normals:

1. Weld by position: vertices with equal coordinates are one (a lexsort, not np.unique
   on rows, which is 5x slower; −0.0 and 0.0 compare equal).
2. Per welded vertex, its faces form *fans*: two faces around the vertex are in one fan
   when they share an edge through it that is smooth — exactly two faces meet there, both
   with area, not flagged flat, and their unit normals within the crease angle. Boundary
   and non-manifold edges are sharp (crease_fans.py).
3. Each fan's normal is the normalized sum of its faces' unit normals (the seeds' rule);
   where the sum cancels, the largest face's normal.
4. One output vertex per (given vertex, fan): UV seams and vertex colors stay split, and
   vertices split further only where a crease runs through them.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import MeshError
from ..freed_memory import return_freed_memory
from .corner_ids import SCAN_BLOCK, id_type, ids_where, vertex_counts, vertex_ranges
from .crease_fans import fan_labels
from .face_normals import FACE_BLOCK, FaceNormals, float_positions
from .fan_normals import fan_normals, mean_normals


def _indices(faces) -> np.ndarray:
    """Face indices in the dtype they came in when it is a 32- or 64-bit integer (ids are
    below 2^25, docs/reliability.md): a 10M-triangle mesh's faces as int64 were 240 MB."""
    faces = np.asarray(faces)
    return faces if faces.dtype in (np.int32, np.uint32, np.int64) else faces.astype(np.int64)


class WeldedFaces:
    """welded[faces], gathered where it is read: `[key]` (rows), `reshape(-1)` (the corners,
    read the same way), len(), or whole through np.asarray. A mesh whose vertices repeat
    positions (split along UV seams: a textured scan, an OBJ with `vt` and no `vn`) held
    this (F, 3) copy of its faces through the whole analysis, 120 MB at 10M triangles, where
    only blocks of it are read unless some vertex is near a crease."""

    def __init__(self, welded: np.ndarray, faces: np.ndarray):
        self.welded, self.faces = welded, faces

    def __len__(self) -> int:
        return len(self.faces)

    def __getitem__(self, key) -> np.ndarray:
        return self.welded[self.faces[key]]

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        return self.welded[self.faces] if dtype is None else self.welded[self.faces].astype(dtype)

    def reshape(self, *shape) -> "WeldedFaces":
        return WeldedFaces(self.welded, self.faces.reshape(*shape))


def weld_by_position(positions: np.ndarray) -> np.ndarray:
    """(N,) id of each vertex's welded vertex (equal coordinates share an id, 0..M-1), int32."""
    count = len(positions)
    # Fast path for meshes that are already welded (scans, most PLY/OBJ): one sort of a
    # single key. Equal positions give equal keys, so distinct keys prove distinct
    # positions; equal keys (a duplicate, or a rare coincidence) take the full lexsort.
    key = positions[:, 0].astype(np.float64)  # x + a·y + b·z, summed in place in that order
    key += 0.7548776662466927 * positions[:, 1].astype(np.float64)
    key += 0.5698402909980532 * positions[:, 2].astype(np.float64)
    key.sort()
    if not np.any(key[1:] == key[:-1]):
        return np.arange(count, dtype=np.int32)
    del key
    x, y, z = (np.asarray(positions[:, k], dtype=np.float64) for k in range(3))
    order = np.lexsort((z, y, x))
    new = np.empty(count, bool)
    new[:1] = True
    new[1:] = (x[order][1:] != x[order][:-1]) | (y[order][1:] != y[order][:-1]) | (z[order][1:] != z[order][:-1])
    if new.all():  # a coincidence of keys, no duplicate: the identity, as above
        return np.arange(count, dtype=np.int32)
    welded = np.empty(count, np.int32)
    welded[order] = np.cumsum(new, dtype=np.int32) - 1
    return welded


def crease_normals(positions: np.ndarray, faces: np.ndarray, crease_angle: float, flat_faces: np.ndarray | None = None,
                   vertex_limit: int | None = None, name: str = "mesh"):
    """Normals welded by position and split at creases sharper than `crease_angle` degrees.

    Returns (source, faces, normals): source (M,) is the given vertex each output vertex
    copies (None when no vertex had to be split: then faces are the given ones and
    normals are per given vertex), faces (F, 3) uint32 and normals (M, 3) float32: each the
    float32 nearest a float64 unit normal (a Mesh keeps them as they are).

    `vertex_limit`: a MeshError naming `name` as soon as the fans show that more output
    vertices than that would be made, before their normals and the split (most of the
    work and memory where every corner is on a crease: a 48 MB OBJ of one face of 24M
    repeated corners reached its error at 6.7 GB and 77 s, after the whole split).

    Speed: the edge analysis (a sort of half-edges) runs only around vertices where some
    face normal is more than half the crease angle from the vertex's mean normal; at all
    other vertices no two faces can be a crease apart, so their faces form one fan. On a
    smooth scan that is no vertex at all.

    Memory: positions and faces are used in the types they come in (float32 and 32-bit
    indices from the loaders), and no per-face array of normals is kept: they are computed
    for a block of faces at a time, and again for the few faces the crease analysis looks
    at. The per-vertex sums are the largest arrays (docs/reliability.md).
    """
    result = _creased(float_positions(positions), _indices(faces), crease_angle, flat_faces, vertex_limit, name)
    if np.size(faces) > SCAN_BLOCK:
        # A big mesh's temporaries handed back, whichever way the analysis ended: its blocks'
        # arrays are freed onto glibc's heap, which kept 240 MB of a 10M-triangle OBJ's
        # resident under the render's peak, which comes next (scene/freed_memory.py).
        return_freed_memory()
    return result


def _creased(positions: np.ndarray, faces: np.ndarray, crease_angle: float, flat_faces, vertex_limit, name: str):
    """crease_normals of float positions and integer faces."""
    vertex_count = len(positions)
    welded = weld_by_position(positions)
    welded_count = int(welded.max()) + 1
    # Already welded (weld_by_position returns the identity then): no (F, 3) gather; else
    # the welded faces are gathered a block at a time where they are read, unless the crease
    # analysis needs them whole.
    welded_faces = faces if welded_count == vertex_count else WeldedFaces(welded, faces)
    corner_welded = welded_faces.reshape(-1)
    normals = FaceNormals(positions, faces)
    mean_normal, spread, degenerate = mean_normals(normals, welded_faces, welded_count)
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
        maybe = spread > (1.0 - math.cos(half)) - 1e-9
        del spread
        near_crease = np.zeros(welded_count, bool)
        # Only their corners take the exact test (a block of corners at a time: where every
        # vertex may be near a crease, all their ids at once were 8 bytes a corner).
        for scan in range(0, len(corner_welded) if maybe.any() else 0, SCAN_BLOCK):
            corners = np.flatnonzero(maybe[corner_welded[scan : scan + SCAN_BLOCK]]) + scan
            for start in range(0, len(corners), FACE_BLOCK):
                block = corners[start : start + FACE_BLOCK]
                corner_vertex = corner_welded[block]
                unit, _ = normals.of(block // 3)
                lean = np.einsum("ij,ij->i", mean_normal[corner_vertex], unit)
                near_crease[corner_vertex[lean < math.cos(half) - 1e-9]] = True
        # Every corner of a face without area or flagged flat is a fan of its own (no smooth
        # edge): three output vertices each, known before the edge analysis.
        alone = len(degenerate) if flat is None else int(flat.sum()) + int(np.count_nonzero(~flat[degenerate]))
        check_split_count(3 * alone, vertex_limit, name)
        if len(degenerate):
            near_crease[welded_faces[degenerate].reshape(-1)] = True
        if flat is not None:
            near_crease[welded_faces[flat].reshape(-1)] = True
        if near_crease.any():
            label = fan_labels(np.asarray(welded_faces), near_crease, normals, crease_angle, flat, welded_count)
            extra = int(label.max()) + 1 - welded_count
            # Each crease fan (labels from welded_count on, numbered densely) becomes at least one output vertex.
            check_split_count(extra, vertex_limit, name)
            if extra > 0:
                # The table of normals, per welded vertex then per fan, in float32: what a
                # Mesh keeps (each the float32 nearest its float64 unit normal, as a Mesh's
                # conversion of float64 normals gives), half the memory.
                table = np.empty((welded_count + extra, 3), np.float32)
                table[:welded_count] = mean_normal
                del mean_normal
                crease_corners = ids_where(label >= welded_count)
                fan_normals(label[crease_corners] - welded_count, crease_corners // 3, normals, table[welded_count:])
                del crease_corners
    if label is corner_welded:  # one fan per welded vertex: every given vertex takes its vertex's (table: the float64 means)
        table = table.astype(np.float32)
        del mean_normal  # (the float64 means, 24 bytes a vertex, let go before the gather below)
        return None, _uint32(faces), table if welded_count == vertex_count else table[welded]  # welded: the identity, or not
    flat_corners = faces.reshape(-1)
    # Does every given vertex lie in exactly one fan? Then no vertex needs splitting.
    vertex_fan = np.full(vertex_count, -1, id_type(len(table)))
    vertex_fan[flat_corners] = label
    split = vertex_fan[flat_corners] != label  # a corner whose vertex also lies in another fan
    if not split.any():
        normals = np.zeros((vertex_count, 3), np.float32)
        used = vertex_fan >= 0
        normals[used] = table[vertex_fan[used]]
        return None, _uint32(faces), normals
    return split_vertices(flat_corners, label, vertex_fan, table, split)


def check_split_count(at_least: int, vertex_limit: int | None, name: str) -> None:
    """A MeshError when the split makes (at least) `at_least` vertices, over `vertex_limit`."""
    if vertex_limit is not None and at_least > vertex_limit:
        raise MeshError(
            f"{name}: at least {at_least} vertices once split at creases (sharp edges, flat faces or "
            f"triangles without area, around most vertices); at most {vertex_limit} are supported"
        )


def split_vertices(flat_corners: np.ndarray, label: np.ndarray, vertex_fan: np.ndarray, table: np.ndarray,
                   split: np.ndarray | None = None):
    """One output vertex per (given vertex, fan label) of the corners, in the order of
    np.unique over the keys vertex·len(table) + label (vertex first, then label), without
    sorting every corner: only the corners of vertices that lie in more than one fan are
    sorted (the few along creases: 63 of the 70K-triangle bunny's 35,947 vertices), and
    every other used vertex gives one output vertex. np.unique over all 208K corners took
    15.8 ms of the bunny's ~90 ms load, this 2.3 ms. `vertex_fan`: the label some corner
    of each vertex has (−1: unused); `split`: vertex_fan[flat_corners] != label, when the
    caller has it. Returns (source, faces, normals) as crease_normals does."""
    by_label = _split_by_label(flat_corners, label, table, len(vertex_fan))
    if by_label is not None:
        return by_label
    if split is None:
        split = vertex_fan[flat_corners] != label
    several = np.zeros(len(vertex_fan), bool)
    several[flat_corners[split]] = True
    in_several = several[flat_corners]  # the corners of those vertices: all of them where every vertex is on a crease
    if in_several.all():
        in_several, corner_vertex = None, flat_corners  # (then their ids would be 0..n-1: no copies of every corner)
    else:
        in_several = ids_where(in_several)
        corner_vertex = flat_corners[in_several]
    # The keys a range of vertices at a time (every key of a vertex in its range): np.unique
    # of each range is the global one's part for those vertices, and where every vertex is
    # on a crease the keys of every corner at once were ~200 bytes a corner of temporaries
    # (docs/performance.md, "Loading a large mesh"). Two passes: the fans a vertex has, then
    # each corner's place among them.
    ranges = vertex_ranges(vertex_counts(corner_vertex, len(vertex_fan)))
    fans = np.zeros(len(vertex_fan), np.int64)
    kept = None  # one range (few corners on creases: most meshes): its corners and np.unique, for the second pass
    for low, high in ranges:
        chosen, keys = _range_keys(corner_vertex, label, in_several, low, high, len(table))
        if len(ranges) == 1:
            unique_keys, inverse = np.unique(keys, return_inverse=True)
            kept = chosen, unique_keys, inverse
        else:  # (sorted and compared: np.unique without an inverse hashes, 5x slower here)
            keys.sort()
            unique_keys = keys[np.concatenate([[True], keys[1:] != keys[:-1]])] if len(keys) else keys
        fans += np.bincount(unique_keys // len(table), minlength=len(vertex_fan))
    del chosen, keys
    count = (vertex_fan >= 0).astype(np.int64)
    count[several] = 0
    count += fans
    del fans
    # Each corner's output vertex, numbered straight into the faces (uint32, every output
    # vertex below the corners' count): from its vertex's first output vertex, then, for
    # the vertices in several fans, its fan's place among that vertex's.
    first = (np.cumsum(count) - count).astype(np.uint32)  # each given vertex's first output vertex
    faces = np.empty((len(flat_corners) // 3, 3), np.uint32)
    output = faces.reshape(-1)
    np.take(first, flat_corners, out=output)
    del first
    for low, high in ranges:
        if kept is not None:
            chosen, unique_keys, inverse = kept
        else:
            chosen, keys = _range_keys(corner_vertex, label, in_several, low, high, len(table))
            unique_keys, inverse = np.unique(keys, return_inverse=True)
            del keys
        key_vertex = unique_keys // len(table)
        rank = np.arange(len(key_vertex)) - np.searchsorted(key_vertex, key_vertex)  # fan's place among its vertex's
        output[_corner_ids(in_several, chosen)] += rank[inverse.reshape(-1)].astype(np.uint32)
    del corner_vertex, in_several, kept
    output_label = np.empty(int(count.sum()), id_type(len(table)))
    output_label[output] = label
    del output
    normals = table[output_label]
    del output_label
    return np.repeat(np.arange(len(vertex_fan), dtype=id_type(len(vertex_fan))), count), faces, normals


def _split_by_label(flat_corners: np.ndarray, label: np.ndarray, table: np.ndarray, vertex_count: int):
    """split_vertices where every label's corners share one given vertex (a welded mesh, as an
    STL's soup is once its corners are joined: each fan lies around one vertex), else None.
    Then the (vertex, label) pairs are the labels used, and np.unique's order is theirs by
    vertex, then label: one sort of a key a label, where every corner of a vertex in several
    fans (all of them in a voxel or CAD mesh) was sorted twice by key (10M triangles of
    cubes: 2.7 s instead of 8.8)."""
    # Corners a block at a time: numpy indexes with a 64-bit copy of a 32-bit index array.
    blocks = [slice(start, start + SCAN_BLOCK) for start in range(0, len(label), SCAN_BLOCK)]
    fan_vertex = np.full(len(table), -1, id_type(vertex_count))
    for block in blocks:
        fan_vertex[label[block]] = flat_corners[block]
    if not all(np.array_equal(fan_vertex[label[block]], flat_corners[block]) for block in blocks):
        return None
    used = ids_where(fan_vertex >= 0)  # the labels used, in order
    keys = fan_vertex[used].astype(np.int64)
    del fan_vertex
    keys *= len(table)
    keys += used
    del used
    keys.sort()  # by vertex, then label: distinct keys, so any sort gives np.unique's order
    output_label = (keys % len(table)).astype(id_type(len(table)))
    source = (keys // len(table)).astype(id_type(vertex_count))
    del keys
    output_of = np.empty(len(table), np.uint32)  # each label's output vertex
    output_of[output_label] = np.arange(len(output_label), dtype=np.uint32)
    faces = np.empty((len(flat_corners) // 3, 3), np.uint32)
    for block in blocks:
        np.take(output_of, label[block], out=faces.reshape(-1)[block])
    del output_of
    return source, faces, table[output_label]


def _range_keys(corner_vertex, label, in_several, low: int, high: int, labels: int):
    """(which of the corners, their keys vertex·labels + label) for the vertices [low, high)."""
    chosen = np.flatnonzero((corner_vertex >= low) & (corner_vertex < high))
    return chosen, corner_vertex[chosen].astype(np.int64) * labels + label[_corner_ids(in_several, chosen)]


def _corner_ids(in_several: np.ndarray | None, chosen: np.ndarray) -> np.ndarray:
    """The ids of the `chosen` ones of the corners in several fans (None: every corner)."""
    return chosen if in_several is None else in_several[chosen]


def _uint32(faces: np.ndarray) -> np.ndarray:
    return faces if faces.dtype == np.uint32 else faces.astype(np.uint32)
