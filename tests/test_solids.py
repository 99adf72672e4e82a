"""The closed-surface test's early exit (scene/geometry/solids.py, directed_edges_may_pair):
it may only say "open" where the full edge pairing says so too. Checked against trimesh's
own watertight and winding tests (an independent implementation) on closed, open, flipped,
non-manifold and degenerate meshes, and against the full pairing with the exit switched off."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from wgpu_shading.scene.geometry import solids
from wgpu_shading.scene import cube, torus, uv_sphere


def _trimesh_orientation(positions: np.ndarray, indices: np.ndarray) -> int:
    """+1 / −1 / 0 as solid_orientation means them, from trimesh (exact welding: merge_tex
    and merge_norm keep nothing apart here, digits_vertex=None merges only equal positions).
    Every piece on its own: the variants below make a second piece of vertices of their own
    (trimesh's split() would need a graph library the test environment does not have)."""
    mesh = trimesh.Trimesh(positions, indices, process=False)
    mesh.merge_vertices(merge_tex=True, merge_norm=True, digits_vertex=None)
    mesh.update_faces(mesh.nondegenerate_faces(height=0.0))
    if len(mesh.faces) == 0 or not (mesh.is_watertight and mesh.is_winding_consistent):
        return 0
    second = np.asarray(indices).min(axis=1) >= _PIECE_SIZE
    signs = set()
    for faces in (np.asarray(indices)[~second], np.asarray(indices)[second]):
        if len(faces):
            piece = trimesh.Trimesh(positions, faces, process=False)
            signs.add(int(np.sign(piece.volume)))
    return signs.pop() if len(signs) == 1 else 0


_PIECE_SIZE = 1 << 10  # (more than any variant has) the second piece's vertices are numbered from here (padded positions)


def _variants(rng: np.random.Generator):
    """(name, positions, indices): closed meshes and the ways real files break them."""
    for name, mesh in (("cube", cube(1.0)), ("sphere", uv_sphere(1.0, 12, 7)), ("torus", torus(1.0, 0.4, 24, 12))):
        positions, indices = np.asarray(mesh.positions, np.float64), np.asarray(mesh.indices).reshape(-1, 3)
        yield name, positions, indices
        yield f"{name} inside out", positions, indices[:, ::-1]
        yield f"{name}, a triangle missing", positions, np.delete(indices, rng.integers(len(indices)), axis=0)
        flipped = indices.copy()
        flipped[rng.integers(len(indices))] = flipped[rng.integers(len(indices))][::-1]
        yield f"{name}, one triangle flipped", positions, flipped
        yield f"{name}, a triangle twice", positions, np.vstack([indices, indices[:1]])
        yield f"{name}, a triangle and its reverse added", positions, np.vstack([indices, indices[:1], indices[:1, ::-1]])
        degenerate = np.array([[indices[0, 0], indices[0, 0], indices[0, 1]]])
        yield f"{name} with a degenerate triangle", positions, np.vstack([indices, degenerate])
        # A second copy beside the first, its vertices numbered from _PIECE_SIZE (the rows in
        # between are unused copies of the first vertex: no face refers to them).
        assert len(positions) <= _PIECE_SIZE
        padded = np.vstack([positions, np.repeat(positions[:1], _PIECE_SIZE - len(positions), axis=0), positions + 3.0])
        yield f"two {name}s", padded, np.vstack([indices, indices + _PIECE_SIZE])
        yield f"two {name}s, one inside out", padded, np.vstack([indices, indices[:, ::-1] + _PIECE_SIZE])


@pytest.mark.parametrize("seed", range(4))
def test_the_early_exit_agrees_with_the_full_pairing_and_with_trimesh(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    for name, positions, indices in _variants(rng):
        fast = solids.solid_orientation(positions, indices, weld_tolerance=0.0, each_piece=True)
        with monkeypatch.context() as patch:
            patch.setattr(solids, "directed_edges_may_pair", lambda welded, indices: True)
            full = solids.solid_orientation(positions, indices, weld_tolerance=0.0, each_piece=True)
        assert fast == full, name
        assert fast == _trimesh_orientation(positions, indices), name
        if "missing" in name or "flipped" in name or "twice" in name:  # answered by the early exit itself
            assert not solids.directed_edges_may_pair(solids.weld_by_position(positions), indices), name

