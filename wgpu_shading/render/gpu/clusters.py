"""Clusters of triangles that face away from the camera, left out of a frame (same pixels).

A closed surface (every edge shared by two triangles that run along it in opposite
directions, their corners at identical positions: scene/geometry/solids.py without
tolerance) wound counter-clockwise seen from outside, seen from a camera outside it with nothing of it in
front of the near plane: every ray from the eye enters the solid through a triangle turned
towards it before it meets one turned away, so a triangle turned away never shows; its
vertex shading and binning, lavapipe's single-threaded part of a frame, are work for nothing
(docs/performance.md, "the vertex-bound sphere").

Not every triangle turned away can go, though. Where one turned away meets one turned
towards the eye (the silhouette), their depths at a pixel centre close to the shared edge
differ by less than float32's rounding, and the one turned away wins the depth test now and
then: the rasterizer's back-face culling changes such pixels (a cube in 20 random views: one
pixel in 8 of them). So a cluster is left out only when every triangle with a corner on it
(the cluster and the ring of triangles around it) is turned away: the silhouette is then a
whole triangle away, and so is the surface in front of every pixel the cluster covers.

What this does not cover: two sides of a closed surface that come closer than the depth
buffer resolves (a shell thinner than ~1e-6 of its distance from the camera, away from any
silhouette) already fight for their pixels when every triangle is drawn; there, leaving
the side turned away out shows the near side only, which changes those pixels. Nor a
piece that passes through itself so that some region lies inside it negatively (the
closed-surface check sees edges and volumes, not intersections). The tests
(tests/test_clusters.py) compare every output over random views of closed meshes whose
sides are far apart, as solids' are.

Built once per upload, in the vertex-cache order (vertex_order.py): runs of CLUSTER_TRIANGLES
consecutive triangles of a part (coherent patches), each with a cone around the normals of
its triangles and their ring (axis, half-angle) and a sphere around those triangles (the
bounds of meshoptimizer's cluster cone culling, https://github.com/zeux/meshoptimizer#mesh-shading,
widened to the ring). The clusters of a part are then sorted along a Hilbert curve over the
octahedral map of their axes, so the ones a frame leaves out lie together, and a frame draws
the ones it keeps as at most RANGES_PER_PART ranges of the index buffer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

CLUSTER_TRIANGLES = 128
# Meshes clustered: below the minimum a frame's vertex work is too small to repay the test
# and the extra draws (CPU A/B at 512², docs/performance.md: a 10K torus 1.03×, 18K 0.92×,
# a 20K sphere 0.78×, 40K 0.62×); above the maximum the build's working arrays (about
# twice the mesh's arrays) would raise a big upload's memory peak (docs/reliability.md,
# "Peak memory of a large mesh load").
CLUSTER_MIN_TRIANGLES = 1 << 14
CLUSTER_MAX_TRIANGLES = 1 << 22
# An upload's clusters start building (on a worker: cluster_builds.py) that many frames after it
# (mesh_uploads.asks_for_clusters).
CLUSTERS_AFTER_FRAMES = 16
RANGES_PER_PART = 32  # draws per part at most: gaps between kept clusters are closed, smallest first
# A draw costs lavapipe and wgpu-py about what the vertex work of a few hundred triangles does
# (docs/performance.md): shorter gaps between kept clusters are drawn, not skipped.
BRIDGED_TRIANGLES = 3 * CLUSTER_TRIANGLES
# Radians: a cluster is left out only when every triangle of its ring is turned away by more
# than this (the normals are kept in float32, ~1e-7 rad; the test runs in float64).
MARGIN = 1e-5
_BLOCK = 1 << 14  # triangles a step while building
_HILBERT_BITS = 8


@dataclass(frozen=True)
class ClusterTable:
    """The clusters of the uploaded index buffer, in its order; `parts` maps a part's
    index to the slice of clusters that cover it (parts left out have none)."""

    first: np.ndarray  # (C,) int64: first triangle of each cluster in the uploaded order
    count: np.ndarray  # (C,) int64
    axis: np.ndarray  # (C, 3) float64 unit vectors
    half_angle: np.ndarray  # (C,) radians; pi where no cone bounds the ring
    centre: np.ndarray  # (C, 3) float64, the mesh's stored (origin-relative) coordinates
    radius: np.ndarray  # (C,)
    parts: dict[int, slice]

    def facing_away(self, eye: np.ndarray, orthographic: bool) -> np.ndarray:
        """(C,) bool: the clusters whose ring is wholly turned away from `eye` (a point in
        the mesh's stored coordinates, or with `orthographic` the direction towards the
        camera). A triangle with unit normal n through x is turned away when n·(eye − x) < 0;
        for every n within half_angle of the axis and every x within radius of the centre,
        that holds when the angle between the axis and the way to the eye exceeds
        half_angle + 90° + asin(radius / distance)."""
        if orthographic:
            cosine = self.axis @ (eye / np.linalg.norm(eye))
            slack = np.zeros(len(self.radius))
            beyond = np.ones(len(self.radius), bool)
        else:
            towards = eye[None, :] - self.centre
            distance = np.linalg.norm(towards, axis=1)
            beyond = distance > self.radius
            safe = np.where(beyond, distance, 1.0)
            cosine = np.einsum("ij,ij->i", towards, self.axis) / safe
            slack = np.arcsin(np.where(beyond, self.radius / safe, 1.0))
        angle = np.arccos(np.clip(cosine, -1.0, 1.0))
        return beyond & (angle - self.half_angle > 0.5 * math.pi + slack + MARGIN)

    def kept_ranges(self, part: int, away: np.ndarray) -> list[tuple[int, int]] | None:
        """(first triangle, count) ranges that draw every cluster of `part` not in `away`;
        None for a part without clusters (drawn whole). A gap of fewer than BRIDGED_TRIANGLES
        is drawn rather than paid for with another draw, and at most RANGES_PER_PART ranges are
        made (the smallest gaps drawn as well)."""
        span = self.parts.get(part)
        if span is None:
            return None
        keep = ~away[span]
        change = np.diff(np.concatenate(([False], keep, [False])).astype(np.int8))
        starts, stops = np.flatnonzero(change == 1), np.flatnonzero(change == -1)  # runs [start, stop)
        first = self.first[span]
        ends = first + self.count[span]
        gaps = first[starts[1:]] - ends[stops[:-1] - 1]  # triangles left out between runs
        bridged = np.flatnonzero(gaps < BRIDGED_TRIANGLES)
        if len(starts) - len(bridged) > RANGES_PER_PART:
            bridged = np.argsort(gaps, kind="stable")[: len(starts) - RANGES_PER_PART]
        starts, stops = np.delete(starts, bridged + 1), np.delete(stops, bridged)
        return [(int(first[a]), int(ends[b - 1] - first[a])) for a, b in zip(starts, stops)]


def cluster_triangles(ordered: np.ndarray, positions: np.ndarray, parts, skipped: frozenset[int]) -> ClusterTable | None:
    """Group the triangles of every triangle part not in `skipped` into clusters and sort
    each part's clusters by direction, rewriting `ordered` (the flat index buffer, vertex ids
    of `positions`) in place; the table of their bounds, or None when no part has any."""
    from ...scene.geometry.crease_normals import weld_by_position

    runs = [
        (number, part.first, part.count)
        for number, part in enumerate(parts)
        if number not in skipped and part.primitive == "triangles" and part.count >= CLUSTER_TRIANGLES
    ]
    if not runs:
        return None
    triangles = ordered.reshape(-1, 3)
    welded = weld_by_position(positions)
    vertex_cones = _vertex_cones(positions, triangles, welded)
    run_starts = [np.arange(first, first + count, CLUSTER_TRIANGLES) for _, first, count in runs]
    starts = np.concatenate(run_starts)
    stops = np.concatenate([np.append(begins[1:], first + count) for begins, (_, first, count) in zip(run_starts, runs)])
    sizes = stops - starts
    axis, half_angle, centre, radius = _cluster_bounds(positions, triangles, welded, starts, sizes, *vertex_cones)
    del vertex_cones
    # Each part's clusters sorted by axis (those no cone bounds first: always drawn), and
    # their triangles moved accordingly.
    key = np.where(half_angle < 0.5 * math.pi, _hilbert_key(axis), -1)
    chosen, first_triangle, slices, begin = [], [], {}, 0
    for (number, first, count), begins in zip(runs, run_starts):
        members = begin + np.argsort(key[begin : begin + len(begins)], kind="stable")
        new_first = first + np.cumsum(sizes[members]) - sizes[members]
        source = np.repeat(starts[members] - new_first, sizes[members]) + np.arange(first, first + count)
        triangles[first : first + count] = triangles[source]
        chosen.append(members)
        first_triangle.append(new_first)
        slices[number] = slice(begin, begin + len(begins))
        begin += len(begins)
    chosen = np.concatenate(chosen)
    return ClusterTable(
        first=np.concatenate(first_triangle).astype(np.int64), count=sizes[chosen].astype(np.int64), axis=axis[chosen],
        half_angle=half_angle[chosen], centre=centre[chosen], radius=radius[chosen], parts=slices,
    )


def _vertex_cones(positions: np.ndarray, triangles: np.ndarray, welded: np.ndarray):
    """Per welded vertex: the unit axis and half-angle of a cone around the normals of all
    the triangles on it (pi where one of them has no reliable normal: its corners almost in a
    line), and its reach, its longest edge: every point of those triangles lies within reach.
    float64 arithmetic a block of triangles at a time (whole-mesh temporaries cost more in
    page faults than in arithmetic), one coordinate at a time (np.cross is ten times slower)."""
    count = int(welded.max()) + 1
    reach, broken = np.zeros(count), np.zeros(count, bool)
    normals = np.empty((3, len(triangles)), np.float32)
    for start in range(0, len(triangles), _BLOCK):
        block = triangles[start : start + _BLOCK]
        vertex = [welded[block[:, slot]] for slot in range(3)]
        corner = [positions[block[:, slot]].astype(np.float64) for slot in range(3)]
        edges = [corner[(slot + 1) % 3] - corner[slot] for slot in range(3)]  # a→b, b→c, c→a
        lengths = [np.sqrt(np.einsum("ij,ij->i", edge, edge)) for edge in edges]
        normal = _cross(edges[0], -edges[2])  # (b − a) × (c − a)
        area = np.sqrt(normal[0] ** 2 + normal[1] ** 2 + normal[2] ** 2)
        unreliable = area <= 1e-8 * lengths[0] * lengths[2]
        normal /= np.where(unreliable, 1.0, area)
        normals[:, start : start + _BLOCK] = normal
        for slot in range(3):
            np.maximum.at(reach, vertex[slot], np.maximum(lengths[slot], lengths[slot - 1]))  # its two edges
            broken[vertex[slot][unreliable]] = True
    # Each vertex's axis: the sum of its triangles' normals (any axis bounds them: the
    # half-angle is measured from it), a whole-mesh bincount (np.add.at is ~10× slower).
    corners = [welded[triangles[:, slot]] for slot in range(3)]
    total = np.stack([sum(np.bincount(vertex, weights=normals[k], minlength=count) for vertex in corners) for k in range(3)], axis=1)
    del corners
    length = np.sqrt(np.einsum("ij,ij->i", total, total))
    axis = total / np.where(length > 0.0, length, 1.0)[:, None]
    lowest = np.ones(count)
    for start in range(0, len(triangles), _BLOCK):
        block = triangles[start : start + _BLOCK]
        normal = normals[:, start : start + _BLOCK]
        for slot in range(3):
            vertex = welded[block[:, slot]]
            np.minimum.at(lowest, vertex, np.einsum("ki,ik->i", normal, axis[vertex]))
    angle = np.arccos(np.clip(lowest, -1.0, 1.0))
    angle[broken | (length < 1e-6)] = math.pi
    return axis, angle, reach


def _cluster_bounds(positions, triangles, welded, starts, sizes, vertex_axis, vertex_angle, vertex_reach):
    """Each cluster's cone and sphere, a block of whole clusters at a time. The cone holds the
    cones of its corners' vertices: its axis their mean, its half-angle the widest angle from
    it to a vertex's axis plus that vertex's half-angle. The sphere holds its triangles and
    their ring: the centre of its corners' box, the radius its farthest corner's distance
    plus that vertex's reach."""
    count = len(starts)
    axis, half_angle, centre, radius = np.zeros((3, count)), np.zeros(count), np.zeros((3, count)), np.zeros(count)
    vertex_axis = np.ascontiguousarray(vertex_axis.T)  # (3, V): one coordinate at a time
    step = max(1, _BLOCK // CLUSTER_TRIANGLES)
    for first in range(0, count, step):
        members = slice(first, first + step)
        block_sizes = sizes[members]
        offsets = np.cumsum(block_sizes) - block_sizes
        rows = np.repeat(starts[members] - offsets, block_sizes) + np.arange(block_sizes.sum())
        block = triangles[rows]
        vertex = [welded[block[:, slot]] for slot in range(3)]
        total = np.array([sum(np.add.reduceat(vertex_axis[k][v], offsets) for v in vertex) for k in range(3)])
        length = np.sqrt((total * total).sum(axis=0))
        own_axis = total / np.where(length > 0.0, length, 1.0)
        spread = np.repeat(own_axis, block_sizes, axis=1)
        widest = np.zeros(len(block_sizes))
        for v in vertex:
            cosine = (spread * vertex_axis[:, v]).sum(axis=0)
            widest = np.maximum(widest, np.maximum.reduceat(np.arccos(np.clip(cosine, -1.0, 1.0)) + vertex_angle[v], offsets))
        widest[length < 1e-6] = math.pi
        points = [positions[block[:, slot]].T.astype(np.float64) for slot in range(3)]  # (3, T) each
        lower = np.min([np.minimum.reduceat(point, offsets, axis=1) for point in points], axis=0)
        upper = np.max([np.maximum.reduceat(point, offsets, axis=1) for point in points], axis=0)
        middle = (lower + upper) / 2.0
        spread = np.repeat(middle, block_sizes, axis=1)
        farthest = np.zeros(len(block_sizes))
        for point, v in zip(points, vertex):
            away = point - spread
            farthest = np.maximum(farthest, np.maximum.reduceat(np.sqrt((away * away).sum(axis=0)) + vertex_reach[v], offsets))
        axis[:, members], half_angle[members], centre[:, members], radius[members] = own_axis, np.minimum(widest, math.pi), middle, farthest
    return axis.T.copy(), half_angle, centre.T.copy(), radius * (1.0 + 1e-9)


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(3, N) cross products of the rows of two (N, 3) arrays."""
    return np.array([u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1], u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2], u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]])


def _hilbert_key(axis: np.ndarray) -> np.ndarray:
    """Position of each unit vector along a Hilbert curve over its octahedral map: vectors
    close in direction get close keys."""
    folded = axis / np.abs(axis).sum(axis=1, keepdims=True)
    x, y = folded[:, 0].copy(), folded[:, 1].copy()
    lower = folded[:, 2] < 0.0
    x[lower] = (1.0 - np.abs(folded[lower, 1])) * np.where(folded[lower, 0] < 0.0, -1.0, 1.0)
    y[lower] = (1.0 - np.abs(folded[lower, 0])) * np.where(folded[lower, 1] < 0.0, -1.0, 1.0)
    side = 1 << _HILBERT_BITS
    xi = np.clip(((x + 1.0) / 2.0 * side).astype(np.int64), 0, side - 1)
    yi = np.clip(((y + 1.0) / 2.0 * side).astype(np.int64), 0, side - 1)
    key = np.zeros(len(axis), np.int64)
    step = side // 2
    while step > 0:
        right, top = (xi & step) > 0, (yi & step) > 0
        key += step * step * ((3 * right) ^ top)
        turn = ~top
        flip = turn & right
        xi, yi = np.where(flip, side - 1 - xi, xi), np.where(flip, side - 1 - yi, yi)
        xi, yi = np.where(turn, yi, xi), np.where(turn, xi, yi)
        step //= 2
    return key
