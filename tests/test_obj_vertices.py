"""An OBJ's (v, vt, vn) corners made into vertices (assets/mesh_formats/obj_vertices.py): the
rows np.unique(axis=0) gives, from far less memory and time, for files whose exporter
numbers vt and vn on their own (Blender, Maya, Cinema 4D)."""

from __future__ import annotations

import numpy as np
import pytest
from test_obj_reading import read_in_small_blocks


@pytest.mark.parametrize("seed", range(40))
def test_distinct_triples_are_the_sorted_unique_rows(seed):
    """Against np.unique(rows, axis=0, return_inverse=True), the reading before: the same
    vertices in the same order and each corner's index among them, for runs of corners of
    one triple a vertex, a few seams, or every corner its own, runs of `v` only and
    runs numbered as their v among them, a run cut again with fewer triangles (ear clipping), any subset of the columns;
    and each run's corners given back whole as they came."""
    import copy

    from wgpu_shading.assets.mesh_formats.obj_vertices import CornerTriples

    rng = np.random.default_rng(seed)
    vertex_count, triples = int(rng.integers(1, 30)), CornerTriples()
    runs, wholes, seen = [], [], 0
    for _ in range(int(rng.integers(1, 5))):
        triangles = int(rng.integers(0, 60))
        width = 1 if rng.random() < 0.15 else 3
        corners = np.zeros((triangles, 3, width), np.int64)
        corners[:, :, 0] = rng.integers(0, vertex_count, (triangles, 3))
        shape, form = (triangles, 3), int(rng.integers(4))
        for column in range(1, width):
            corners[:, :, column] = [
                rng.integers(-1, 6, shape),  # unrelated to v: seams everywhere, some absent
                (corners[:, :, 0] * 5 + column) % 11,  # one per vertex, numbered otherwise
                np.where(rng.random(shape) < 0.15, rng.integers(0, 40, shape), corners[:, :, 0] * 2),  # a few seams
                corners[:, :, 0],  # numbered as v (one index a vertex)
            ][form]
        seen = max(seen, int(corners[:, :, 0].max(initial=-1)) + 1)  # the v lines so far: the table grows run by run
        run = triples.split(corners, seen)
        whole = np.full((triangles, 3, 3), -1)
        whole[:, :, :width] = corners
        np.testing.assert_array_equal(triples.whole(run), corners if (corners[:, :, 1:] != -1).any() else corners[:, :, :1])
        runs.append(run)
        wholes.append(whole)
    if seed % 2:  # a run cut again, with some triangles gone
        index = int(rng.integers(len(runs)))
        wholes[index] = wholes[index][rng.random(len(wholes[index])) < 0.5]
        runs[index] = triples.split(wholes[index], vertex_count)
    corners = np.concatenate(wholes)
    for columns in ([0, 1, 2], [0, 1], [0, 2]):
        found, faces = copy.deepcopy(triples).distinct(copy.deepcopy(runs), columns, vertex_count)  # (both used up)
        rows, inverse = np.unique(np.stack([corners[:, :, c].reshape(-1) for c in columns], 1), axis=0, return_inverse=True)
        np.testing.assert_array_equal(found, rows.reshape(-1, len(columns)))
        np.testing.assert_array_equal(faces.reshape(-1), inverse.reshape(-1))
        assert faces.dtype == np.uint32 and faces.shape == (len(corners), 3) and faces.base is None


def _exported_grid(side: int, seam_every: int) -> tuple[str, list[tuple]]:
    """A grid written as Blender writes a mesh: vt and vn lines in their own orders (vn one
    per vertex, from the last; vt one per vertex, shuffled), a second vt along every
    seam_every-th column (a UV seam: one position, two uvs). And each triangle's corners as
    (position, uv, normal) values, for the check."""
    rng = np.random.default_rng(7)
    count = side * side
    grid = np.arange(count).reshape(side, side)
    u, v = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    positions = np.round(np.stack([u, v, 0.1 * np.sin(6 * u)], -1).reshape(-1, 3), 6)
    uv_of = rng.permutation(count)  # vertex → its vt line
    uvs = np.round(rng.random((count, 2)), 4)  # uvs[uv_of[i]] is vertex i's
    seam_uvs = np.round(rng.random((count, 2)), 4)  # vertex i's second uv, at count + i
    normal_of = count - 1 - np.arange(count)
    normals = np.round(rng.normal(size=(count, 3)), 4)
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in positions]
    lines += [f"vt {a:.4f} {b:.4f}" for a, b in np.concatenate([uvs, seam_uvs])]
    lines += [f"vn {a:.4f} {b:.4f} {c:.4f}" for a, b, c in normals]
    triangles = []
    for row in range(side - 1):
        for column in range(side - 1):
            a, b, c, d = grid[row, column], grid[row, column + 1], grid[row + 1, column], grid[row + 1, column + 1]
            seam = column % seam_every == 0
            for triangle in ((a, b, d), (a, d, c)):
                tokens, corners = [], []
                for corner in triangle:
                    second = seam and corner in (a, c)  # this quad's left edge takes the seam's second uvs
                    uv = count + corner if second else uv_of[corner]
                    tokens.append(f"{corner + 1}/{uv + 1}/{normal_of[corner] + 1}")
                    corners.append((tuple(positions[corner]), tuple(seam_uvs[corner] if second else uvs[uv]), tuple(normals[normal_of[corner]])))
                lines.append("f " + " ".join(tokens))
                triangles.append(tuple(corners))
    return "\n".join(lines) + "\n", triangles


def test_an_exported_obj_makes_one_vertex_per_distinct_corner(tmp_path, monkeypatch):
    """Each corner keeps its position, uv and normal; a vertex is made for each distinct
    (v, vt, vn) and no more (a seam's corners two); read in blocks of 64 KiB, tracemalloc's
    peak of the reading stays a few times the arrays it gives: 2.4x here, 5.7x when every
    corner's indices were kept and their rows went through np.unique (docs/performance.md)."""
    text, expected = _exported_grid(side=120, seam_every=10)
    path = tmp_path / "exported.obj"
    path.write_text(text)
    piece, peak = read_in_small_blocks(path, monkeypatch)
    corners = np.array(expected, dtype=object)
    np.testing.assert_array_equal(piece.positions[piece.faces], np.array(corners[:, :, 0].tolist()))
    np.testing.assert_array_equal(piece.uvs[piece.faces], np.float32(corners[:, :, 1].tolist()))  # (kept as the Mesh keeps them)
    np.testing.assert_array_equal(piece.normals[piece.faces], np.array(corners[:, :, 2].tolist()))
    seam_vertices = 120 * len(range(10, 119, 10))  # each seam column but the first has quads on both sides
    assert len(piece.positions) == 120 * 120 + seam_vertices
    arrays = sum(array.nbytes for array in (piece.positions, piece.faces, piece.uvs, piece.normals))
    assert peak < 3.2 * arrays, f"peak {peak / arrays:.2f}x the arrays"
