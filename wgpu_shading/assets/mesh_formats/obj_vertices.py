"""An OBJ's face corners, each a (v, vt, vn) triple of indices, made into vertices: one
vertex per distinct triple, in the order of the triples sorted (v, then vt, then vn), as
np.unique(triples, axis=0, return_inverse=True) gives them.

Exporters (Blender, Maya, Cinema 4D) number texture coordinates and normals on their own, so
a file's triples are not its `v` numbers. np.unique over the rows sorted every corner's row
as one structured item: 12 s and ~12x the mesh's arrays in memory for a 2M-triangle
Blender-style OBJ (docs/performance.md, "Loading a large mesh"). But a vertex has one
triple at almost every corner (a second only along a UV seam or a crease), so: each `v`
takes the triple of one of its corners (its last), the corners with another triple are
found by comparing, and only those (the few along seams) and one triple a `v` are sorted.
Every pass over the corners runs a block at a time: the temporaries stay bounded.
"""

from __future__ import annotations

import numpy as np

CORNERS_AT_ONCE = 1 << 20  # corners compared and numbered at a time


def distinct_triples(corners: np.ndarray, columns: list[int], vertex_count: int) -> tuple[np.ndarray, np.ndarray]:
    """(triples, faces): the distinct rows of corners[:, :, columns] (corners: (T, 3, k)
    non-negative resolved indices, `v` in column 0, below vertex_count), sorted, as an
    (N, len(columns)) array of corners' type; and each corner's row among them, (T, 3) uint32."""
    flat = corners.reshape(-1, corners.shape[2])  # (a view: corners are C-contiguous)
    count = len(flat)
    v = flat[:, 0]
    others = [flat[:, column] for column in columns[1:]]
    # Each used `v`'s representative corner: the last corner of it (numpy's fancy assignment
    # stores in order, the last write stays; any corner would do, the result is the same).
    representative = np.full(vertex_count, -1, np.int64)
    for start in range(0, count, CORNERS_AT_ONCE):
        stop = min(start + CORNERS_AT_ONCE, count)
        representative[v[start:stop]] = np.arange(start, stop)
    used = np.flatnonzero(representative >= 0)
    chosen = representative[used]
    del representative
    base = [flat[chosen, column] for column in columns[1:]]  # each used v's own (vt, vn)
    own = [np.full(vertex_count, -1, flat.dtype) for _ in base]
    for table, values in zip(own, base):
        table[used] = values
    # The corners whose (vt, vn) is not their v's own: seams and creases.
    different = []
    for start in range(0, count, CORNERS_AT_ONCE):
        stop = min(start + CORNERS_AT_ONCE, count)
        block_v = v[start:stop]
        other = np.zeros(stop - start, bool)
        for table, column in zip(own, others):
            other |= table[block_v] != column[start:stop]
        different.append(np.flatnonzero(other) + start)
    del own
    different = np.concatenate(different) if different else np.empty(0, np.intp)
    # The candidates: each used v's own triple, then each different corner's.
    rows = np.empty((len(used) + len(different), len(columns)), flat.dtype)
    rows[: len(used), 0] = used
    rows[len(used) :, 0] = v[different]
    for k, (values, column) in enumerate(zip(base, others), 1):
        rows[: len(used), k] = values
        rows[len(used) :, k] = column[different]
    del base, chosen
    order = np.lexsort(rows.T[::-1])  # sorted by v, then vt, then vn
    new = np.zeros(len(order), bool)
    new[:1] = True
    for k in range(len(columns)):
        sorted_column = rows[order, k]
        new[1:] |= sorted_column[1:] != sorted_column[:-1]
    rank = np.empty(len(order), np.uint32)
    rank[order] = np.cumsum(new, dtype=np.uint32) - 1
    triples = rows[order[new]]
    del order, new, rows
    # Every corner takes its v's vertex, then the different ones their own.
    vertex_of = np.zeros(vertex_count, np.uint32)
    vertex_of[used] = rank[: len(used)]
    faces = np.empty((count // 3, 3), np.uint32)  # (owning its memory: a Mesh keeps it without a copy)
    ids = faces.reshape(-1)  # (a view)
    for start in range(0, count, CORNERS_AT_ONCE):
        stop = min(start + CORNERS_AT_ONCE, count)
        ids[start:stop] = vertex_of[v[start:stop]]
    ids[different] = rank[len(used) :]
    return triples, faces
