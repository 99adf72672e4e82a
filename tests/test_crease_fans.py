"""Crease normals against a plain-Python reference of their rule, and their memory where
every vertex is on a crease (issue #29: a voxel or CAD mesh of 10M triangles loads and
renders within 3× its arrays; docs/performance.md, "Loading a large mesh").

The reference (docs/real-world-files.md, "Normals"): vertices are welded by position;
around a welded vertex whose faces all lean at most half the crease angle from their mean
normal (and none is flat or without area) the faces form one fan; elsewhere two corners at
the vertex are in one fan when a smooth edge joins their faces, where exactly two faces
meet, both with area, neither flat, their unit normals within the crease angle. A fan's
normal is the normalized sum of its corners' unit face normals, or its largest face's
where that sum cancels. Here it is written as loops over faces and edges with a
dictionary and a union-find, and compared corner by corner with crease_normals, with the
ranges and blocks of the vectorised code made small so that every array spans many."""

from __future__ import annotations

import math
import tracemalloc

import numpy as np
import pytest

from wgpu_shading import Mesh
from wgpu_shading.scene.geometry import corner_ids, crease_fans, crease_normals as creases, face_normals, fan_normals


def _small_blocks(monkeypatch) -> None:
    """Every range and block of the crease analysis a few entries long."""
    for module, name, value in (
        (corner_ids, "SCAN_BLOCK", 37), (creases, "SCAN_BLOCK", 37), (corner_ids, "RANGE_IDS", 11),
        (corner_ids, "MAX_RANGES", 5), (crease_fans, "RANGE_IDS", 11), (fan_normals, "FAN_RANGE", 7),
        (fan_normals, "MAX_RANGES", 5), (face_normals, "FACE_BLOCK", 13), (fan_normals, "FACE_BLOCK", 13),
        (creases, "FACE_BLOCK", 13), (crease_fans, "FACE_BLOCK", 13), (face_normals, "KEPT_FACES", 0),
    ):
        monkeypatch.setattr(module, name, value)


def _reference(positions, faces, crease_angle, flat):
    """Per corner: (welded vertex, fan id) and its normal, by the rule in the module docstring."""
    points = [tuple(map(float, p)) for p in np.asarray(positions, np.float64)]
    weld: dict[tuple, int] = {}
    welded = [weld.setdefault(p, len(weld)) for p in points]  # (-0.0 == 0.0: one key)
    scale = max(max(abs(c) for p in points for c in p), 1e-300)
    units, areas = [], []
    for face in faces:
        a, b, c = (np.array(points[i]) for i in face)
        cross = np.cross(b - a, c - a)
        length = float(np.sqrt(cross @ cross))
        has_area = length > 1e-12 * scale * scale
        units.append(cross / length if has_area else np.zeros(3))
        areas.append(length if has_area else 0.0)
    corner_vertex = [welded[i] for face in faces for i in face]
    corners_at: dict[int, list[int]] = {}
    for corner, vertex in enumerate(corner_vertex):
        corners_at.setdefault(vertex, []).append(corner)

    def fan_normal(corners):
        total = sum((units[c // 3] for c in corners), np.zeros(3))
        with_area = sum(areas[c // 3] > 0 for c in corners)
        length = float(np.sqrt(total @ total))
        if length > 1e-6 * max(with_area, 1):
            return total / length
        best = None  # cancelled: the largest face's normal (the last corner's of equal ones)
        for c in corners:
            if areas[c // 3] > 0 and (best is None or areas[c // 3] >= areas[best // 3]):
                best = c
        return np.zeros(3) if best is None else units[best // 3]

    half = math.radians(min(max(crease_angle, 0.0), 180.0)) / 2.0
    analysed = set()
    for vertex, corners in corners_at.items():
        mean = fan_normal(corners)
        lean = any(float(mean @ units[c // 3]) < math.cos(half) - 1e-9 for c in corners)
        special = any(areas[c // 3] == 0 or (flat is not None and flat[c // 3]) for c in corners)
        if special or (crease_angle < 180.0 and lean):
            analysed.add(vertex)

    parent = list(range(3 * len(faces)))

    def root(c):
        while parent[c] != c:
            parent[c] = parent[parent[c]]
            c = parent[c]
        return c

    edges: dict[tuple, list[tuple[int, int]]] = {}
    for f in range(len(faces)):
        for k in range(3):
            a, b = corner_vertex[3 * f + k], corner_vertex[3 * f + (k + 1) % 3]
            edges.setdefault((min(a, b), max(a, b)), []).append((f, k))
    cos_crease = 1.0 - 1e-12 if crease_angle <= 0 else math.cos(math.radians(crease_angle))
    for (f1, k1), (f2, k2) in (h for h in edges.values() if len(h) == 2):
        if f1 == f2 or areas[f1] <= 0 or areas[f2] <= 0 or float(units[f1] @ units[f2]) < cos_crease:
            continue
        if flat is not None and (flat[f1] or flat[f2]):
            continue
        for c1 in (3 * f1 + k1, 3 * f1 + (k1 + 1) % 3):
            for c2 in (3 * f2 + k2, 3 * f2 + (k2 + 1) % 3):
                if corner_vertex[c1] == corner_vertex[c2] and corner_vertex[c1] in analysed:
                    parent[root(c1)] = root(c2)
    fan_of = [root(c) if corner_vertex[c] in analysed else -1 for c in range(3 * len(faces))]
    members: dict[tuple, list[int]] = {}
    for c in range(3 * len(faces)):
        members.setdefault((corner_vertex[c], fan_of[c]), []).append(c)
    normal_of = {key: fan_normal(corners) for key, corners in members.items()}
    return [(corner_vertex[c], fan_of[c]) for c in range(3 * len(faces))], [normal_of[(corner_vertex[c], fan_of[c])] for c in range(3 * len(faces))]


def _random_mesh(seed: int):
    rng = np.random.default_rng(seed)
    kind = seed % 4
    if kind == 0:  # a height field of steps: creases at several angles, coplanar runs
        side = int(rng.integers(3, 9))
        x, y = np.meshgrid(np.arange(side), np.arange(side))
        positions = np.stack([x, y, rng.integers(0, 3, x.shape) * rng.choice([0.3, 1.0])], -1).reshape(-1, 3)
        grid = np.arange(side * side).reshape(side, side)
        a, b, c, d = grid[:-1, :-1].ravel(), grid[:-1, 1:].ravel(), grid[1:, :-1].ravel(), grid[1:, 1:].ravel()
        faces = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])
    elif kind == 1:  # cubes as a triangle soup (an STL of a voxel model), some faces wound backwards
        corner = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
        cube = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                         [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
        origins = rng.integers(0, 3, (int(rng.integers(1, 6)), 3)) * 1.0
        faces = (np.arange(len(origins))[:, None, None] * 8 + cube).reshape(-1, 3)
        flip = rng.random(len(faces)) < 0.1
        faces[flip] = faces[flip][:, ::-1]
        positions = (origins[:, None] + corner).reshape(-1, 3)[faces.reshape(-1)]
        faces = np.arange(len(positions)).reshape(-1, 3)
    elif kind == 2:  # random triangles over few vertices: non-manifold edges, repeats, no area
        positions = rng.normal(size=(int(rng.integers(4, 12)), 3))
        faces = rng.integers(0, len(positions), (int(rng.integers(2, 40)), 3))
    else:  # a noisy closed sphere
        u, v = np.meshgrid(np.linspace(0.3, np.pi - 0.3, 6), np.linspace(0, 2 * np.pi, 7, endpoint=False))
        radius = 1 + rng.random(u.shape) * 0.4
        positions = np.stack([radius * np.sin(u) * np.cos(v), radius * np.sin(u) * np.sin(v), radius * np.cos(u)], -1).reshape(-1, 3)
        grid = np.arange(positions.shape[0]).reshape(7, 6)
        a, b = grid[:, :-1].ravel(), grid[:, 1:].ravel()
        c, d = np.roll(grid, -1, 0)[:, :-1].ravel(), np.roll(grid, -1, 0)[:, 1:].ravel()
        faces = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])
    flat = rng.random(len(faces)) < 0.15 if rng.random() < 0.3 else None
    angle = float(rng.choice([0.0, 20.0, 45.0, 60.0, 100.0, 180.0]))
    return positions.astype(rng.choice([np.float32, np.float64])), faces.astype(rng.choice([np.int32, np.uint32, np.int64])), flat, angle


@pytest.mark.parametrize("small", [False, True])
@pytest.mark.parametrize("seed", range(24))
def test_crease_normals_follow_the_rule_corner_by_corner(monkeypatch, seed, small):
    if small:
        _small_blocks(monkeypatch)
    positions, faces, flat, angle = _random_mesh(seed)
    source, new_faces, normals = creases.crease_normals(positions, faces, angle, flat)
    corners = new_faces.reshape(-1).astype(np.int64)
    given = faces.reshape(-1) if source is None else np.asarray(source)[corners]
    np.testing.assert_array_equal(given, faces.reshape(-1))  # every corner keeps its given vertex
    keys, expected = _reference(positions, faces, angle, flat)
    # Two corners share an output vertex exactly when they share a given vertex and a fan.
    output_of: dict[tuple, int] = {}
    for corner, key in enumerate(keys):
        assert output_of.setdefault((int(faces.reshape(-1)[corner]), key), int(corners[corner])) == corners[corner]
    assert len(set(output_of.values())) == len(output_of)
    assert normals.dtype == np.float32
    np.testing.assert_allclose(normals[corners], np.array(expected), atol=1e-6)


def _cubes(count: int) -> tuple[np.ndarray, np.ndarray]:
    """`count` separate unit cubes in a row: every vertex on a 90° crease, three fans each."""
    corner = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], np.float32)
    cube = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                     [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    origins = np.zeros((count, 3), np.float32)
    origins[:, 0] = 1.5 * np.arange(count)
    faces = (np.arange(count)[:, None, None] * 8 + cube).reshape(-1, 3).astype(np.uint32)
    return (origins[:, None] + corner).reshape(-1, 3), faces


def test_a_mesh_whose_every_vertex_is_on_a_crease_takes_a_bounded_multiple_of_its_arrays(monkeypatch):
    """20,000 cubes (240K triangles, 480K vertices once split): tracemalloc's peak of the
    crease normals and the Mesh, over the Mesh's arrays, with blocks and ranges ~1/32 of
    their size (so that they are as small against this mesh as against 10M triangles):
    1.9× now (2.0× while the vertex sums were kept per corner slot), 3.6× with int64 ids, float64 fan sums of every fan at once and float64
    normals (the 10M-triangle voxel STL: 2.41× resident to load, 3.95× before)."""
    for module, name, value in (
        (corner_ids, "SCAN_BLOCK", 1 << 17), (creases, "SCAN_BLOCK", 1 << 17), (corner_ids, "RANGE_IDS", 1 << 15),
        (crease_fans, "RANGE_IDS", 1 << 15), (fan_normals, "FAN_RANGE", 1 << 16),
        (face_normals, "FACE_BLOCK", 2048), (fan_normals, "FACE_BLOCK", 2048), (creases, "FACE_BLOCK", 2048),
        (crease_fans, "FACE_BLOCK", 2048), (face_normals, "KEPT_FACES", 0),
    ):
        monkeypatch.setattr(module, name, value)
    positions, faces = _cubes(20_000)
    tracemalloc.start()
    try:
        mesh = Mesh.from_arrays(positions, faces, crease_angle=60.0)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert mesh.vertex_count == 24 * 20_000  # each cube corner split into its three faces' normals
    np.testing.assert_array_equal(np.abs(mesh.normals).max(axis=1), 1.0)
    arrays = mesh.positions.nbytes + mesh.normals.nbytes + mesh.indices.nbytes
    assert peak < 2.4 * arrays, f"{peak / arrays:.2f}x the mesh arrays"


def _seamed_torus(segments: int, rings: int):
    """A smooth torus whose grid is cut open along one ring and one segment, as a textured
    mesh's UV seams cut it: the seams' vertices repeated (same positions), no crease."""
    u = np.linspace(0.0, 2.0 * np.pi, segments + 1)  # the last column repeats the first
    v = np.linspace(0.0, 2.0 * np.pi, rings + 1)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    positions = np.stack([(1.0 + 0.4 * np.cos(vv)) * np.cos(uu), (1.0 + 0.4 * np.cos(vv)) * np.sin(uu), 0.4 * np.sin(vv)], axis=-1)
    positions = positions.reshape(-1, 3)
    grid = np.arange((segments + 1) * (rings + 1)).reshape(segments + 1, rings + 1)
    a, b, c, d = grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return positions, faces.astype(np.uint32)


def test_welding_a_seamed_mesh_keeps_one_array_of_vertex_sums(monkeypatch):
    """A mesh whose vertices repeat positions along its UV seams (an OBJ with `vt` and no
    `vn`, as Agisoft Metashape writes one) and no crease: the vertex sums are one
    (vertices, 3) float64 array, summed face by face in corner order, and the mean normals
    are the float32 of the reference's, bit for bit (each vertex's unit face normals
    summed in corner order, as fan_normals sums a fan's). Summed a corner slot at a time (three (3, vertices) arrays and a transposed
    copy), the analysis's tracemalloc peak was 3.9× the float64 positions, now 2.3×; the 10M-triangle
    OBJ's load peak was 2.85× its Mesh arrays, now 2.7× (docs/performance.md, "Memory")."""
    for module, name, value in ((face_normals, "FACE_BLOCK", 2048), (fan_normals, "FACE_BLOCK", 2048),
                                (creases, "FACE_BLOCK", 2048), (crease_fans, "FACE_BLOCK", 2048), (face_normals, "KEPT_FACES", 0)):
        monkeypatch.setattr(module, name, value)
    positions, faces = _seamed_torus(300, 200)
    tracemalloc.start()
    try:
        source, given_faces, normals = creases.crease_normals(positions, faces, 60.0)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert source is None and given_faces is not None  # no crease: the vertices as given
    assert peak < 2.6 * positions.nbytes, f"{peak / positions.nbytes:.2f}x the positions"
    welded = {}
    ids = [welded.setdefault(tuple(p), len(welded)) for p in positions.tolist()]
    unit, _ = face_normals.face_normals(positions, faces)  # (the same face normals: the order of the sums is what is tested)
    sums = np.zeros((len(welded), 3))
    for corner, vertex in enumerate(faces.reshape(-1)):  # corner order
        sums[ids[vertex]] += unit[corner // 3]
    expected = (sums / np.sqrt(np.einsum("ij,ij->i", sums, sums))[:, None]).astype(np.float32)
    np.testing.assert_array_equal(normals, expected[ids])


def test_a_faces_normal_is_the_same_bits_asked_once_or_in_runs(monkeypatch):
    """FaceNormals.of computes a face asked for several times in a row once (the crease
    analysis asks for every corner's face, corners in order): the same bits as each id
    computed on its own, in blocks or not."""
    monkeypatch.setattr(face_normals, "KEPT_FACES", 0)  # (a big mesh's path: nothing kept)
    positions, faces = _cubes(40)
    rng = np.random.default_rng(3)
    positions = positions + rng.normal(scale=1e-3, size=positions.shape).astype(np.float32)
    normals = face_normals.FaceNormals(positions, faces)
    corners = np.sort(rng.choice(3 * len(faces), 2 * len(faces), replace=False))
    asked = corners // 3  # runs of one to three equal ids
    one_by_one = [normals.of(np.array([face])) for face in asked.tolist()]
    for block in (10_000, 7):
        monkeypatch.setattr(face_normals, "FACE_BLOCK", block)
        unit, area = normals.of(asked)
        assert unit.view(np.int64).tolist() == np.concatenate([u for u, _ in one_by_one]).view(np.int64).tolist()
        assert area.view(np.int64).tolist() == np.concatenate([a for _, a in one_by_one]).view(np.int64).tolist()
