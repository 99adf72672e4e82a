"""An OBJ's face corners, each a (v, vt, vn) triple of indices, kept compactly as the blocks
are read and made into vertices at the end: one vertex per distinct triple, in the order
of the triples sorted (v, then vt, then vn), as np.unique(triples, axis=0,
return_inverse=True) gives them.

Exporters (Blender, Maya, Cinema 4D) number texture coordinates and normals on their own, so
a file's triples are not its `v` numbers. Every corner's three indices, kept until the end,
were 36 bytes a triangle, and np.unique over them sorted every corner's row as one
structured item: 72 s and 13x the mesh's arrays in memory for a 10M-triangle Blender-style
OBJ (docs/performance.md, "Loading a large mesh"). But a vertex has one triple at almost
every corner (a second only along a UV seam or a crease). So each `v` takes the (vt, vn)
of the first corner met with it, its own pair; a run of faces keeps its corners' `v` and,
only for the corners whose pair is not their v's own, their places and pairs; and at the
end only one triple a `v` and those few are sorted.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...scene.freed_memory import return_freed_memory
from .line_sections import GIVE_BACK_BYTES

UNSEEN = -2  # no corner of this v met yet (−1 is an absent vt or vn)


@dataclass
class RunCorners:
    """A run's triangle corners: their `v` (T, 3) int32, and the corners whose (vt, vn) pair
    is not their v's own: their flat indices (int32) and pairs ((M, 2) int32, −1 absent);
    `odd` None while the pairs follow from `v` alone (a run of `v` corners, or of corners
    whose vt and vn numbers are their v's, as exporters of one index a vertex write them:
    most files, which never need the pairs). The flags say whether every corner has a
    vt / a vn, and whether every corner's vt / vn number is its v number."""

    vertices: np.ndarray
    odd: np.ndarray | None
    odd_pairs: np.ndarray | None
    paired: bool  # corners of (v, vt, vn), not of v alone
    all_uv: bool
    all_normal: bool
    same_uv: bool
    same_normal: bool

    def __len__(self) -> int:
        return len(self.vertices)


class CornerTriples:
    """Each `v`'s own (vt, vn) pair, grown as runs of corners are split against it."""

    def __init__(self) -> None:
        self._own = np.full((0, 2), UNSEEN, np.int32)

    def split(self, corners: np.ndarray, vertex_count: int) -> RunCorners:
        """A run's resolved corners (T, 3, k): k = 1 (`v` only) or 3 (v, vt, vn; −1 absent),
        each v below vertex_count (the `v` lines so far)."""
        flat = corners.reshape(-1, corners.shape[2])
        v = flat[:, 0]
        vertices = v.reshape(-1, 3).astype(np.int32)
        if corners.shape[2] != 3 or (flat[:, 1:] == -1).all():  # (v only: faces `f a b c`, most scans)
            return RunCorners(vertices, None, None, False, False, False, False, False)
        same_uv, same_normal = bool(np.array_equal(v, flat[:, 1])), bool(np.array_equal(v, flat[:, 2]))
        run = RunCorners(vertices, None, None, True, same_uv or bool((flat[:, 1] >= 0).all()),
                         same_normal or bool((flat[:, 2] >= 0).all()), same_uv, same_normal)
        if not (same_uv and same_normal):
            run.odd, run.odd_pairs = self._odd(v, flat[:, 1:3], vertex_count)
        return run

    def whole(self, run: RunCorners) -> np.ndarray:
        """The run's corners again, (T, 3, 3) int32 (v, vt, vn), or (T, 3, 1) when they had
        neither vt nor vn: for ear clipping."""
        if not run.paired:
            return run.vertices[:, :, None].copy()
        flat = np.empty((len(run) * 3, 3), np.int32)
        flat[:, 0] = run.vertices.reshape(-1)
        if run.odd is None:  # vt and vn numbered as v
            flat[:, 1] = flat[:, 2] = flat[:, 0]
        else:
            flat[:, 1:] = self._own[flat[:, 0]]
            flat[run.odd, 1:] = run.odd_pairs
        return flat.reshape(-1, 3, 3)

    def _odd(self, v: np.ndarray, pairs: np.ndarray, vertex_count: int) -> tuple[np.ndarray, np.ndarray]:
        """The corners (v, and their (vt, vn) pairs) whose pair is not their v's own, as
        RunCorners keeps them; each v met for the first time takes its first corner's pair."""
        if vertex_count > len(self._own):  # (most files: every v line before the faces, one table)
            grown = np.full((max(vertex_count, len(self._own) * 3 // 2), 2), UNSEEN, np.int32)
            grown[: len(self._own)] = self._own
            self._own = grown
        own = self._own
        unseen = np.flatnonzero(own[v, 0] == UNSEEN)
        if len(unseen):  # each new v's first corner (numpy stores in order: the last write, reversed, is the first)
            own[v[unseen[::-1]]] = pairs[unseen[::-1]]
        odd = np.flatnonzero((own[v] != pairs).any(axis=1))
        return odd.astype(np.int32), pairs[odd].astype(np.int32)

    def distinct(self, runs: list[RunCorners], columns: list[int], vertex_count: int) -> tuple[np.ndarray, np.ndarray]:
        """(triples, faces): the distinct (v, vt, vn) of the runs' corners restricted to
        `columns` (0 = v, 1 = vt, 2 = vn), sorted, as an (N, len(columns)) int32 array;
        and each corner's row among them, the runs' triangles in order, (T, 3) uint32. The
        runs are used up, their arrays let go as their corners are numbered, and so is the
        table of own pairs.

        No sort of every vertex: the v's own triples are in order already (one a v), so only
        the odd corners' triples are sorted, and each v's rows are counted to place them:
        v's rows start after every row of a smaller v, its own among its odd ones by (vt, vn)."""
        kept = [column - 1 for column in columns[1:]]
        for run in runs:  # the pairs that followed from v, split now (they are needed after all)
            if run.odd is None:
                v = run.vertices.reshape(-1)
                pairs = np.stack([v, v], axis=1) if run.paired else np.full((len(v), 2), -1, np.int32)
                run.odd, run.odd_pairs = self._odd(v, pairs, vertex_count)
        own_used = _own_used(runs, vertex_count)
        # The odd corners' triples, sorted by (v, pair), each distinct one kept once.
        odd_v = np.concatenate([run.vertices.reshape(-1)[run.odd] for run in runs] + [np.empty(0, np.int32)])
        odd_key = np.concatenate([_pair_key(run.odd_pairs[:, kept]) for run in runs] + [np.empty(0, np.int64)])
        order = np.lexsort((odd_key, odd_v))
        odd_v, odd_key = odd_v[order], odd_key[order]
        first = np.ones(len(order), bool)
        first[1:] = (odd_v[1:] != odd_v[:-1]) | (odd_key[1:] != odd_key[:-1])
        row_of = np.cumsum(first) - 1  # each sorted odd corner → its distinct triple
        odd_v, odd_key = odd_v[first], odd_key[first]
        own_key = _pair_key(self._own[odd_v][:, kept])
        with_own = own_used[odd_v]
        as_own = with_own & (odd_key == own_key)  # the restricted triple is its v's own after all
        after_own = with_own & (own_key < odd_key)
        # Rows a v has: its own (if used) and its distinct odd triples; each v's rows start
        # after every row of a smaller v.
        alone = ~as_own
        counts = own_used.astype(np.uint32)
        counts += np.bincount(odd_v[alone], minlength=vertex_count).astype(np.uint32)
        starts = np.cumsum(counts, dtype=np.uint32)
        starts -= counts
        del counts
        vertex_of = starts.copy()  # the own triple's row: after the odd ones of its v below it
        vertex_of += np.bincount(odd_v[alone & with_own & ~after_own], minlength=vertex_count).astype(np.uint32)
        vertex_of[~own_used] = 0
        # An odd triple's row: its place among its v's odd ones, one more when the own is below it.
        group_start = np.flatnonzero(np.r_[True, odd_v[alone][1:] != odd_v[alone][:-1]]) if alone.any() else np.empty(0, np.intp)
        place = np.arange(int(alone.sum())) - np.repeat(group_start, np.diff(np.r_[group_start, alone.sum()]))
        odd_rank = np.empty(len(odd_v), np.uint32)
        odd_rank[alone] = starts[odd_v[alone]] + place + after_own[alone]
        odd_rank[as_own] = vertex_of[odd_v[as_own]]
        del starts
        used = np.flatnonzero(own_used).astype(np.int32)
        del own_used
        triples = np.empty((len(used) + int(alone.sum()), len(columns)), np.int32)
        at = vertex_of[used]
        triples[at, 0] = used
        for k, column in enumerate(kept, 1):  # (a column at a time: no copy of every own pair)
            triples[at, k] = self._own[used, column]
        del at, used
        self._own = np.full((0, 2), UNSEEN, np.int32)  # (used up: the pairs are in the triples now)
        triples[odd_rank[alone], 0] = odd_v[alone]
        triples[odd_rank[alone], 1:] = _pairs_of_key(odd_key[alone], len(kept))
        corner_rank = np.empty(len(order), np.uint32)  # each odd corner's row, in the runs' order
        corner_rank[order] = odd_rank[row_of]
        del order, row_of, odd_rank
        return triples, _numbered_faces(runs, vertex_of, corner_rank)


_NONE = np.empty(0, np.int32)  # a used-up run's arrays


def _own_used(runs: list[RunCorners], vertex_count: int) -> np.ndarray:
    """Each v whose own pair some corner still has (ear clipping may drop triangles)."""
    own_used = np.zeros(vertex_count, bool)
    for run in runs:
        plain = np.ones(len(run) * 3, bool)
        plain[run.odd] = False
        own_used[run.vertices.reshape(-1)[plain]] = True
    return own_used


def _numbered_faces(runs: list[RunCorners], vertex_of: np.ndarray, odd_rows: np.ndarray) -> np.ndarray:
    """Every corner numbered as its v's own vertex (`vertex_of`), then the odd ones as their
    own (`odd_rows`, in the runs' order): (T, 3) uint32, owning its memory (a Mesh keeps it
    without a copy). Each run's arrays are let go once numbered."""
    faces = np.empty((sum(len(run) for run in runs), 3), np.uint32)
    row, odd_start, let_go = 0, 0, 0
    for run in runs:
        ids = faces[row : row + len(run)]
        np.take(vertex_of, run.vertices, out=ids)
        ids.reshape(-1)[run.odd] = odd_rows[odd_start : odd_start + len(run.odd)]
        row, odd_start, let_go = row + len(run), odd_start + len(run.odd), let_go + run.vertices.nbytes
        run.vertices = run.odd = run.odd_pairs = _NONE
        if let_go >= GIVE_BACK_BYTES:  # (as line_sections.joined does: glibc keeps the runs' arrays resident)
            return_freed_memory()
            let_go = 0
    return faces


def _pair_key(pairs: np.ndarray) -> np.ndarray:
    """(vt, vn) pairs (n, 0..2) of int32 from −1 (absent) on as one int64 each, in the same order."""
    key = np.zeros(len(pairs), np.int64)
    for column in range(pairs.shape[1]):
        key <<= 32
        key |= pairs[:, column].astype(np.int64) + 1
    return key


def _pairs_of_key(key: np.ndarray, width: int) -> np.ndarray:
    """_pair_key's pairs again, (n, width) int32."""
    pairs = np.empty((len(key), width), np.int32)
    for column in reversed(range(width)):
        pairs[:, column] = (key & 0xFFFFFFFF) - 1
        key = key >> 32
    return pairs
