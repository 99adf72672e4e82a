"""A big mesh's per-vertex arrays are converted a block of rows at a time, the same bits as
the whole-array arithmetic (issue #29, docs/performance.md "Loading a large mesh"):

- a glTF's float32 POSITION and NORMAL are read as stored and placed by their node in
  float64 block by block (assets/gltf/primitives.py), its indices read as uint32;
- normals a caller or a file gives are made unit length block by block into float32
  (scene/geometry/vertex_normals.py, validated_normals).

The references here are the whole arrays computed in float64 as the readers did before,
and the blocks are made small (vertex_arrays.BLOCK_ROWS) so that every array spans many."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from gltf_builder import FLOAT, UBYTE, UINT, USHORT, Doc
from wgpu_shading import Mesh, load_mesh
from wgpu_shading.scene.geometry import vertex_arrays


def _grid(side: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A wavy square of side² vertices: float32 positions, float32 unit normals (rounded, so
    not unit within 1e-9 in float64), uint32 triangles."""
    u, v = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    positions = np.stack([u, v, 0.1 * np.sin(6 * u)], -1).reshape(-1, 3)
    normals = np.stack([-0.6 * np.cos(6 * u), np.zeros_like(u), np.ones_like(u)], -1).reshape(-1, 3)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    grid = np.arange(side * side).reshape(side, side)
    a, b, c, d = grid[:-1, :-1].ravel(), grid[:-1, 1:].ravel(), grid[1:, :-1].ravel(), grid[1:, 1:].ravel()
    faces = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])
    return positions.astype(np.float32), normals.astype(np.float32), faces.astype(np.uint32)


def _write(folder, positions, normals, faces, matrix=None, index_type=UINT, name="grid"):
    """A .gltf with its arrays in a .bin beside it (as exporters write one), one node."""
    doc = Doc()
    attributes = {"POSITION": doc.accessor(positions, FLOAT, 34962), "NORMAL": doc.accessor(normals, FLOAT, 34962)}
    primitive = {"attributes": attributes, "indices": doc.accessor(faces.reshape(-1), index_type, 34963)}
    (folder / f"{name}.bin").write_bytes(bytes(doc.blob))
    node = {"mesh": 0} | ({} if matrix is None else {"matrix": np.asarray(matrix, float).T.reshape(-1).tolist()})
    return doc.write(folder / f"{name}.gltf", [[primitive]], [node], uri=f"{name}.bin")


def _assert_same_mesh(mesh: Mesh, expected: Mesh) -> None:
    for key in ("positions", "normals", "indices"):
        got, want = getattr(mesh, key), getattr(expected, key)
        assert got.dtype == want.dtype and got.shape == want.shape and got.tobytes() == want.tobytes(), key
    assert mesh.origin == expected.origin


@pytest.mark.parametrize("mirrored", [False, True])
def test_a_node_places_stored_float32_arrays_as_the_whole_float64_product(tmp_path, monkeypatch, mirrored):
    monkeypatch.setattr(vertex_arrays, "BLOCK_ROWS", 7)  # 144 rows: 21 blocks and a part
    positions, normals, faces = _grid(12)
    turn = np.array([[0.36, -0.48, 0.8], [0.8, 0.6, 0.0], [-0.48, 0.64, 0.6]])
    linear = turn @ np.diag([-1.5 if mirrored else 1.5, 0.7, 2.25])
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = linear, [0.25, -3.5, 7.0]
    mesh = load_mesh(_write(tmp_path, positions, normals, faces, matrix))
    # What the reader computed before: the float64 copies, each whole array at once.
    placed = positions.astype(np.float64) @ linear.T + matrix[:3, 3]
    turned = normals.astype(np.float64) @ np.linalg.inv(linear)
    expected = Mesh.from_arrays(placed, faces[:, ::-1] if mirrored else faces, normals=turned)
    _assert_same_mesh(mesh, expected)


def test_8_16_and_32_bit_indices_give_the_same_mesh(tmp_path):
    positions, normals, faces = _grid(12)
    meshes = [load_mesh(_write(tmp_path, positions, normals, faces, index_type=kind, name=f"grid{kind}"))
              for kind in (UBYTE, USHORT, UINT)]  # (144 vertices: a byte holds every index)
    assert meshes[0].indices.dtype == np.uint32
    for mesh in meshes[1:]:
        _assert_same_mesh(mesh, meshes[0])
    np.testing.assert_array_equal(meshes[0].indices, faces)


@pytest.mark.parametrize("placed, bound", [("scaled and moved", 3.0), ("without a transform", 2.5)])
def test_a_big_gltf_loads_in_a_few_times_its_mesh_arrays(tmp_path, monkeypatch, placed, bound):
    """tracemalloc's peak of load_mesh, in the Mesh's arrays, for a 40,000-vertex glTF with
    normals, blocks of 4,096 rows (65,536 scaled to this file). A node that scales and
    moves it: 2.4x (its positions placed in float64); a node without a transform: 2.2x
    (placed positions and normals are float32 exactly: kept so). Float64 and int64 copies
    of every accessor and whole-array temporaries peaked at 4.6x either way; resident, for
    a 10M-triangle GLB: 4.61x then, 2.58x now (`python -m benchmarks --only memory`)."""
    monkeypatch.setattr(vertex_arrays, "BLOCK_ROWS", 4096)
    positions, normals, faces = _grid(200)
    matrix = None
    if placed == "scaled and moved":
        matrix = np.diag([2.0, 2.0, 2.0, 1.0])
        matrix[:3, 3] = [1.0, 2.0, 3.0]
    path = _write(tmp_path, positions, normals, faces, matrix)
    load_mesh(path)  # (imports and first-use caches outside the measurement)
    tracemalloc.start()
    try:
        mesh = load_mesh(path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    arrays = mesh.positions.nbytes + mesh.normals.nbytes + mesh.indices.nbytes
    assert peak < bound * arrays, f"peak {peak / arrays:.2f}x the arrays"


def test_a_node_without_a_transform_keeps_the_stored_values(tmp_path, monkeypatch):
    """Placed values that are all exactly float32 are kept as float32 (half the memory):
    the Mesh is the one their float64 copies make, bit for bit. A block with a value that
    is not makes the array float64 from there on, the rows before it copied exactly."""
    monkeypatch.setattr(vertex_arrays, "BLOCK_ROWS", 7)
    positions, normals, faces = _grid(12)
    for matrix in (None, np.diag([1.0, 1.0, 1.0, 1.0])):
        mesh = load_mesh(_write(tmp_path, positions, normals, faces, matrix, name=f"plain{matrix is None}"))
        _assert_same_mesh(mesh, Mesh.from_arrays(positions.astype(np.float64), faces, normals=normals.astype(np.float64)))
    positions[:70] = np.round(positions[:70] * 8)  # whole numbers: + 0.5 is exact for the first 10 blocks of 7 rows
    moved = np.eye(4)
    moved[:3, 3] = [0.5, 0.0, 0.0]
    mesh = load_mesh(_write(tmp_path, positions, normals, faces, moved, name="moved"))
    placed = positions.astype(np.float64) @ moved[:3, :3].T + moved[:3, 3]
    _assert_same_mesh(mesh, Mesh.from_arrays(placed, faces, normals=normals.astype(np.float64) @ np.linalg.inv(moved[:3, :3])))


@pytest.mark.parametrize("kind", ["unit float64", "unit float32", "rounded unit float32", "scaled", "some unusable", "some unit", "integers"])
def test_given_normals_are_made_unit_block_by_block_as_whole_float64_arrays(monkeypatch, kind):
    """Mesh.from_arrays with the caller's normals: already unit ones kept (float64 within
    1e-9 of unit length, float32 within what rounding to float32 allows: 2^-22), others
    divided by their float64 length, NaN, infinite or zero ones replaced by the computed
    normal; all the same bits in blocks of 7 rows as whole arrays in float64."""
    monkeypatch.setattr(vertex_arrays, "BLOCK_ROWS", 7)
    positions, normals, faces = _grid(40 if kind == "rounded unit float32" else 9)
    rng = np.random.default_rng(5)
    # Unit float64 vectors rounded to float32 (what crease normals give a Mesh): renormalized
    # in float64, ~1 % of their rows would move by one float32 step.
    rounded = rng.normal(size=normals.shape)
    rounded = (rounded / np.linalg.norm(rounded, axis=1, keepdims=True)).astype(np.float32)
    given = {
        "unit float64": normals.astype(np.float64) / np.linalg.norm(normals.astype(np.float64), axis=1, keepdims=True),
        "unit float32": normals,
        "rounded unit float32": rounded,
        "scaled": normals * rng.uniform(0.5, 3.0, (len(normals), 1)).astype(np.float32),
        "some unusable": normals * np.float32(2.0),
        "some unit": normals * np.where(rng.random((len(normals), 1)) < 0.5, np.float32(1.0), np.float32(1.5)),
        "integers": rng.integers(-2, 3, normals.shape),
    }[kind]
    if kind == "some unusable":
        given[[3, 40, 77]] = 0.0
        given[[5, 50], 1] = np.nan
        given[60, 2] = np.inf
    mesh = Mesh.from_arrays(positions, faces, normals=given)
    whole = np.asarray(given, np.float64)
    squared = np.einsum("ij,ij->i", whole, whole)
    unit = np.abs(squared - 1.0) < (2.0**-22 if given.dtype == np.float32 else 1e-9)
    if unit.all():
        expected = whole
    else:
        finite = np.isfinite(whole).all(axis=1)
        length = np.linalg.norm(np.where(finite[:, None], whole, 0.0), axis=1)
        usable = finite & (length > 1e-20)
        expected = np.zeros_like(whole)
        expected[usable] = whole[usable] / length[usable, None]
        if given.dtype == np.float32:  # unit float32 rows as given
            expected[unit] = whole[unit]
        computed = Mesh.from_arrays(positions, faces).normals  # the seeds' normalized sum, for the rest
        expected[~usable] = computed[~usable]
    if kind == "rounded unit float32":
        renormalized = (whole / np.linalg.norm(whole, axis=1, keepdims=True)).astype(np.float32)
        assert (renormalized != given).any() and mesh.normals.tobytes() == given.tobytes()
    assert mesh.normals.dtype == np.float32
    assert mesh.normals.tobytes() == expected.astype(np.float32).tobytes()


@pytest.mark.parametrize("dtype", [np.float32, np.float64, np.int32])
def test_column_bounds_and_finite_rows_are_numpys_row_reductions(dtype):
    """vertex_arrays.column_bounds and finite_rows give what rows.min(axis=0), rows.max(axis=0)
    and np.isfinite(rows).all(axis=1) give (NaN and infinities too), a column at a time."""
    rng = np.random.default_rng(5)
    for columns in (1, 2, 3, 4):
        rows = (rng.normal(size=(1000, columns)) * 100).astype(dtype)
        lower, upper = vertex_arrays.column_bounds(rows)
        assert lower.dtype == rows.dtype and np.array_equal(lower, rows.min(axis=0)) and np.array_equal(upper, rows.max(axis=0))
        assert vertex_arrays.finite_rows(rows) is None
        if dtype is np.int32:
            continue
        rows[[3, 500], 0] = np.nan
        rows[7, columns - 1] = -np.inf
        lower, upper = vertex_arrays.column_bounds(rows)
        np.testing.assert_array_equal(lower, rows.min(axis=0))
        np.testing.assert_array_equal(upper, rows.max(axis=0))
        np.testing.assert_array_equal(vertex_arrays.finite_rows(rows), np.isfinite(rows).all(axis=1))
