"""Vertex normals as the seeds define them, and normals a caller gives made usable.

`vertex_normals`: the normalized sum of the unit normals of the faces around each given
vertex (no welding: crease_normals.py welds and creases). `validated_normals`: given normals made
unit length, with computed ones where a given one has no direction.
"""

from __future__ import annotations

import numpy as np

from ...errors import MeshError
from .face_normals import face_normals
from .vertex_arrays import row_blocks

# How far from 1 the squared length of a unit vector rounded to float32 can be: each
# component moves by at most 2^-24 of itself, so |n|^2 by at most 2·2^-24 + 2^-48.
FLOAT32_UNIT = 2.0**-22


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
    """The given (N, 3) normals as float32 unit vectors: already unit ones (all of them:
    computed ones, most files) as given, otherwise each made unit length in float64, with
    computed ones where a given one has no direction. "Unit" is to the precision the
    normals are stored in (_unit_rows): within 1e-9 for float64 values, and for float32
    values (float32 arrays, or float64 ones that hold float32 numbers, as trimesh's reading of
    a float32 file does) within what rounding a unit vector to float32 can move its length
    (FLOAT32_UNIT): renormalizing those would move ~1 % of their rows by one float32 step,
    and none closer to unit. Converted a block of rows at a time: a float64 copy of 10M
    vertices' normals would be half the mesh again; float32 normals that are unit are the
    result itself (a Mesh copies them unless they are read-only and own their memory, as
    the file readers' crease normals are)."""
    if normals.shape != positions.shape:
        raise MeshError(f"{name}: normals must have shape {positions.shape}, got {normals.shape}")
    if normals.dtype.kind not in "iuf":
        normals = np.asarray(normals, dtype=np.float64)  # what cannot be a number fails here, as before
    blocks = list(row_blocks(len(normals)))
    if all(_unit_rows(normals[rows]).all() for rows in blocks):
        if normals.dtype == np.float32:
            return np.ascontiguousarray(normals)
        out = np.empty(normals.shape, np.float32)
        for rows in blocks:
            out[rows] = normals[rows].astype(np.float64, copy=False)
        return out
    out = np.empty(normals.shape, np.float32)
    usable = np.empty(len(normals), bool)
    for rows in blocks:
        block = normals[rows].astype(np.float64, copy=False)
        finite = np.isfinite(block).all(axis=1)
        length = np.linalg.norm(np.where(finite[:, None], block, 0.0), axis=1)
        usable[rows] = finite & (length > 1e-20)
        unit = np.zeros_like(block)
        unit[usable[rows]] = block[usable[rows]] / length[usable[rows], None]
        as_given = _unit_rows(normals[rows], float32_only=True)  # (unit float64 ones: normalized, as before)
        unit[as_given] = block[as_given]
        out[rows] = unit
    if not usable.all():
        # Zero-length or NaN normals in the input: replace those with computed ones
        # rather than let normalize(0) reach the shader.
        computed = vertex_normals(positions, faces)
        out[~usable] = computed[~usable]
    return out


def _float32_values(block: np.ndarray) -> np.ndarray:
    """Per row of a float64 block: are its values float32 numbers (stored as float32)?"""
    with np.errstate(over="ignore", invalid="ignore"):
        return (block == block.astype(np.float32)).all(axis=1)


def _unit_rows(rows: np.ndarray, float32_only: bool = False) -> np.ndarray:
    """Per row: unit to the precision it is stored in (validated_normals); NaN rows are not.
    `float32_only`: only rows stored as float32 count."""
    block = rows.astype(np.float64, copy=False)
    off_unit = np.abs(np.einsum("ij,ij->i", block, block) - 1.0)
    stored_as_float32 = np.ones(len(block), bool) if rows.dtype == np.float32 else _float32_values(block)
    if float32_only:
        return stored_as_float32 & (off_unit < FLOAT32_UNIT)
    return off_unit < np.where(stored_as_float32, FLOAT32_UNIT, 1e-9)
