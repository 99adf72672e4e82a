"""An STL's corners joined into vertices a block at a time, binary (float32) or ASCII (float64).

STL stores every corner of every triangle, ~6 copies of each vertex: a 10M-triangle file's
corners alone are 360 MB as float32, 1.5x the mesh they make (docs/reliability.md). So a
block's distinct corners (an integer sort of their bits) are looked up in a sorted index of
those met before (big-endian bits compared bytewise: coordinate order), and only new ones
are added; each corner gets the id of its vertex in the order vertices were met, and
`finish` gives the rank that renumbers them in sorted order, for one pass over the ids at
the end. The corners are never all in memory at once, whatever the order of the triangles.
Equal coordinates are equal bits once -0.0 is made 0.0; the crease normals weld by exact
position anyway (docs/conventions.md), so joining here changes no normal.
"""

from __future__ import annotations

import numpy as np

# float type → (the unsigned integer of its bits, the same big-endian: compared bytewise in order)
_BITS = {np.dtype(np.float32): (np.uint32, ">u4"), np.dtype(np.float64): (np.uint64, ">u8")}
RENUMBER_BLOCK = 3 << 18  # ids renumbered at a time by finish()


class CornerJoin:
    """Blocks of (k, 3) corners in, the id of each one's vertex out (ids in the order the
    vertices were first met); finish() gives the vertices sorted by their bits and the
    rank of each id among them."""

    def __init__(self, dtype):
        self.dtype = np.dtype(dtype)
        self._bits, self._big_endian = _BITS[self.dtype]
        self._key = np.dtype(f"V{3 * self.dtype.itemsize}")  # a corner's three coordinates' bits
        self._index = np.empty(0, self._key)  # the distinct corners so far, sorted
        self._index_ids = np.empty(0, np.uint32)  # the id (order met) of each

    def add(self, corners: np.ndarray) -> np.ndarray:
        """The (k,) uint32 vertex ids of a block of (k, 3) corners."""
        corners = corners.astype(self.dtype, copy=False) + self.dtype.type(0.0)  # -0.0 becomes 0.0: equal coordinates, equal bits
        rows, inverse = _join_equal(corners.view(self._bits))  # integer sorts: 5x faster than sorting keys bytewise
        del corners
        keys = rows.astype(self._big_endian).view(self._key).ravel()
        del rows
        index, index_ids = self._index, self._index_ids
        at = np.searchsorted(index, keys)
        known = at < len(index)
        known[known] = index[at[known]] == keys[known]
        ids = np.empty(len(keys), np.uint32)
        ids[known] = index_ids[at[known]]
        fresh = np.flatnonzero(~known)
        ids[fresh] = np.arange(len(index), len(index) + len(fresh), dtype=np.uint32)
        self._index = np.insert(index, at[fresh], keys[fresh])
        self._index_ids = np.insert(index_ids, at[fresh], ids[fresh])
        return ids[inverse]

    def finish(self, ids: np.ndarray) -> np.ndarray:
        """The vertices (V, 3), sorted by their bits (x, then y, then z, as unsigned
        integers); `ids` (every id add() gave, a C-contiguous uint32 array of any shape)
        renumbered in place to those rows, a block at a time: no second array of every
        corner."""
        rank = np.empty(len(self._index), np.uint32)
        rank[self._index_ids] = np.arange(len(self._index), dtype=np.uint32)
        positions = self._index.view(self._big_endian).reshape(-1, 3).astype(self._bits).view(self.dtype)
        self._index, self._index_ids = np.empty(0, self._key), np.empty(0, np.uint32)
        flat = ids.reshape(-1)  # (a view: renumbered in place)
        for start in range(0, len(flat), RENUMBER_BLOCK):
            flat[start : start + RENUMBER_BLOCK] = rank[flat[start : start + RENUMBER_BLOCK]]
        return positions


def _join_equal(bits: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct rows of `bits` (N, 3) unsigned sorted by (column 0, 1, 2), and each row's
    index among them. np.unique(axis=0, return_inverse=True) on the rows held five arrays of
    the rows' size at once; this holds one sort order and one key."""
    if bits.dtype == np.uint32:
        high = (bits[:, 0].astype(np.uint64) << np.uint64(32)) | bits[:, 1]
        order = np.lexsort((bits[:, 2], high))
        del high
    else:
        order = np.lexsort((bits[:, 2], bits[:, 1], bits[:, 0]))
    new = np.zeros(len(order), bool)
    new[:1] = True
    for column in range(3):  # one sorted column at a time, not a sorted copy of every row
        ordered = bits[order, column]
        new[1:] |= ordered[1:] != ordered[:-1]
    del ordered
    vertex = np.cumsum(new, dtype=np.uint32)
    vertex -= 1
    inverse = np.empty(len(order), np.uint32)
    inverse[order] = vertex
    return bits[order[new]], inverse
