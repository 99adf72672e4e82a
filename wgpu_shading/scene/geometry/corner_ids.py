"""Arrays of corner and vertex ids for the crease analysis, in 32 bits and in ranges.

Where every vertex of a mesh is on a crease (a voxel model, a CAD part written as an STL),
the crease analysis holds several arrays with an entry per corner: three per triangle, so
at 10M triangles each int64 one is 240 MB, as much as a third of the Mesh's own arrays.
A Mesh has at most MAX_TRIANGLES triangles (2^25), so a corner id, and any count of
corners or vertices, fits in an int32: half the memory, the same values
(docs/performance.md, "Loading a large mesh").
"""

from __future__ import annotations

import numpy as np

SCAN_BLOCK = 1 << 22  # mask entries looked at a time by ids_where: 4 MB of bools
RANGE_IDS = 1 << 20  # ids a range of vertices holds at least (vertex_ranges)
MAX_RANGES = 16  # at most: more ids make larger ranges, not more passes over them all


def id_type(count: int) -> type:
    """int32 for ids below `count` when they fit (every Mesh), else int64."""
    return np.int32 if count <= np.iinfo(np.int32).max else np.int64


def ids_where(mask: np.ndarray) -> np.ndarray:
    """np.flatnonzero(mask) in id_type(len(mask)), found a block at a time into the result:
    no int64 array of every id on the way."""
    ids = np.empty(int(np.count_nonzero(mask)), id_type(len(mask)))
    done = 0
    for start in range(0, len(mask), SCAN_BLOCK):
        found = np.flatnonzero(mask[start : start + SCAN_BLOCK])
        ids[done : done + len(found)] = found
        ids[done : done + len(found)] += start
        done += len(found)
    return ids


def vertex_counts(vertex_of: np.ndarray, vertex_count: int, mask: np.ndarray | None = None) -> np.ndarray:
    """np.bincount(vertex_of[mask], minlength=vertex_count), a block at a time (bincount
    takes its input as int64: a whole 32-bit array would be copied at twice its size)."""
    counts = np.zeros(vertex_count, np.int64)
    for start in range(0, len(vertex_of), SCAN_BLOCK):
        block = vertex_of[start : start + SCAN_BLOCK]
        if mask is not None:
            block = block[mask[start : start + SCAN_BLOCK]]
        counts += np.bincount(block, minlength=vertex_count)
    return counts


def vertex_ranges(counts: np.ndarray) -> list[tuple[int, int]]:
    """Ranges [low, high) of vertex ids, each holding about RANGE_IDS of the entries that
    `counts` counts per vertex (every entry of a vertex in one range), at most MAX_RANGES of
    them: the caller sorts the entries of one range at a time, and each range is a pass
    over them all."""
    total = int(counts.sum())
    if total <= RANGE_IDS:
        return [(0, len(counts))]
    per_range = max(RANGE_IDS, -(-total // MAX_RANGES))
    entries_to = np.cumsum(counts)
    cuts = np.searchsorted(entries_to, np.arange(per_range, total, per_range), side="right")
    bounds = [0, *np.unique(cuts).tolist(), len(counts)]
    return [(low, high) for low, high in zip(bounds[:-1], bounds[1:]) if high > low]
