"""Unit face normals and doubled areas, in float64 from positions of any float type, a block
of faces at a time (crease_normals.py asks for them by block or by any set of faces).

The arithmetic of each face is its own, so a face's values are the same bits however the
faces are grouped: whole, in blocks, or picked out by id.
"""

from __future__ import annotations

import numpy as np

FACE_BLOCK = 1 << 16  # faces whose normals are computed at a time: ~12 MB of temporaries
KEPT_FACES = 1 << 18  # meshes up to this many faces keep their face normals (8 MB) instead of recomputing them


def _scale(positions: np.ndarray) -> float:
    """The largest absolute coordinate (np.abs(positions).max(), without the (N, 3) copy)."""
    return max(float(-positions.min()), float(positions.max())) if len(positions) else 1.0


def _normals_of(positions: np.ndarray, faces: np.ndarray, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals and twice the areas of `faces` (a block), float64 from positions of any
    float type (each coordinate converted exactly, then every operation in float64)."""
    # Component by component: np.cross on (F, 3) arrays costs 4x more. np.take along axis 0,
    # and no copy of float64 rows: indexing rows (positions[i]) and copying them took 4 ms
    # of the bunny's 70K faces, this 1 ms (the same values).
    i0, i1, i2 = (np.ascontiguousarray(faces[:, k]) for k in range(3))
    p0, p1, p2 = (np.take(positions, i, axis=0).astype(np.float64, copy=False) for i in (i0, i1, i2))
    ax, ay, az = p1[:, 0] - p0[:, 0], p1[:, 1] - p0[:, 1], p1[:, 2] - p0[:, 2]
    bx, by, bz = p2[:, 0] - p0[:, 0], p2[:, 1] - p0[:, 1], p2[:, 2] - p0[:, 2]
    cross = np.empty((len(faces), 3))
    cross[:, 0] = ay * bz - az * by
    cross[:, 1] = az * bx - ax * bz
    cross[:, 2] = ax * by - ay * bx
    length = np.sqrt(np.einsum("ij,ij->i", cross, cross))
    # "zero area" relative to the mesh's own scale, so tiny meshes (1e-5) keep their faces
    degenerate = length <= 1e-12 * max(scale, 1e-300) ** 2
    unit = np.zeros((len(faces), 3))
    np.divide(cross, length[:, None], out=unit, where=~degenerate[:, None])
    return unit, np.where(degenerate, 0.0, length)


def face_normals(positions: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit face normals (zero for zero-area faces) and twice the face areas, float64."""
    # In blocks of faces: the temporaries stay ~25 MB however big the mesh (a 10M-triangle
    # scan needed 1 GB for them at once; docs/reliability.md).
    positions = float_positions(positions)
    return _in_blocks(positions, len(faces), lambda block: faces[block], _scale(positions))


def _in_blocks(positions: np.ndarray, count: int, faces_of, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """(unit, area) of `count` faces, FACE_BLOCK at a time into the result: faces_of(block)
    gives the (k, 3) faces of a slice of them."""
    unit, area = np.empty((count, 3)), np.empty(count)
    for start in range(0, count, FACE_BLOCK):
        block = slice(start, start + FACE_BLOCK)
        unit[block], area[block] = _normals_of(positions, faces_of(block), scale)
    return unit, area


class FaceNormals:
    """Unit normals and doubled areas of a mesh's faces, for any block or subset of them.
    A big mesh computes them when asked (no per-face array is kept: 32 bytes a face); a
    small one (at most KEPT_FACES faces) computes them once. Either way a face's values are
    the same: each face's arithmetic is its own."""

    def __init__(self, positions: np.ndarray, faces: np.ndarray):
        self.positions, self.faces, self.scale = positions, faces, _scale(positions)
        self.kept = face_normals(positions, faces) if len(faces) <= KEPT_FACES else None

    def of(self, face_ids) -> tuple[np.ndarray, np.ndarray]:
        """(unit, area) of the faces `face_ids` (an index array or a slice). Many ids are
        computed FACE_BLOCK at a time into the result: the crease analysis asks for every
        corner's face where every vertex is on a crease, and the temporaries of all at once
        were ~30 bytes an id for every byte of the result (docs/performance.md, "Loading a
        large mesh")."""
        if self.kept is not None:
            return self.kept[0][face_ids], self.kept[1][face_ids]
        if isinstance(face_ids, slice):
            return _normals_of(self.positions, self.faces[face_ids], self.scale)
        runs = _repeated_runs(face_ids)
        if runs is not None:  # each face once, then repeated: a face's values are its own either way
            unit, area = self.of(face_ids[runs])
            lengths = np.diff(runs, append=len(face_ids))
            return np.repeat(unit, lengths, axis=0), np.repeat(area, lengths)
        if len(face_ids) <= FACE_BLOCK:
            return _normals_of(self.positions, self.faces[face_ids], self.scale)
        return _in_blocks(self.positions, len(face_ids), lambda block: self.faces[face_ids[block]], self.scale)


def _repeated_runs(face_ids: np.ndarray) -> np.ndarray | None:
    """Where each run of equal consecutive ids starts, when the runs are at most half the ids
    (the crease analysis asks for every corner's face, corners in order: each face three
    times in a row where every vertex is near a crease, as on a voxel model or a CAD part:
    its normals were computed three times, a quarter of a 2M-triangle voxel STL's load);
    None otherwise."""
    if len(face_ids) < 2:
        return None
    starts = np.flatnonzero(face_ids[1:] != face_ids[:-1]) + 1
    if 2 * (len(starts) + 1) > len(face_ids):
        return None
    return np.concatenate([[0], starts])


def float_positions(positions) -> np.ndarray:
    """float32 positions stay float32 (every use converts what it reads to float64, exactly);
    anything else becomes float64."""
    positions = np.asarray(positions)
    return positions if positions.dtype in (np.float32, np.float64) else positions.astype(np.float64)
