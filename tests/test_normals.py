"""docs/real-world-files.md normals: weld by position, crease angle split per vertex fan, OBJ `s off`,
the crease_angle key and flag, the up axis. Expected normals are computed independently
(face normals by hand, exact sphere normals), never with the code under test."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import MeshError, SceneError, load_mesh
from wgpu_shading.assets.scenefile import load_scene
from wgpu_shading.scene import Mesh, SceneObject
from wgpu_shading.scene.geometry.crease_normals import crease_normals, split_vertices, weld_by_position

REAL = Path(__file__).parent / "data" / "real"
CUBE_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
CUBE_FACES = np.array(  # outward, counter-clockwise
    [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]
)


def _soup(positions, faces):
    return positions[faces].reshape(-1, 3), np.arange(3 * len(faces)).reshape(-1, 3)


def test_weld_merges_equal_positions_only():
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 0, 0], [-0.0, 0, 0], [1, 0, 1e-12]])
    ids = weld_by_position(positions)
    assert ids[0] == ids[2] == ids[3] and len({ids[0], ids[1], ids[4]}) == 3


@pytest.mark.parametrize("soup", [False, True])
def test_cube_at_60_degrees_has_face_normals_and_at_180_the_plain_average(soup):
    positions, faces = _soup(CUBE_CORNERS, CUBE_FACES) if soup else (CUBE_CORNERS, CUBE_FACES)
    source, new_faces, normals = crease_normals(positions, faces, 60.0)
    corner_normals = normals[new_faces].reshape(-1, 3)
    p = positions[source] if source is not None else positions
    a, b, c = (p[new_faces[:, k]] for k in range(3))
    face = np.cross(b - a, c - a)
    np.testing.assert_allclose(corner_normals, np.repeat(face / np.linalg.norm(face, axis=1)[:, None], 3, axis=0), atol=1e-12)
    assert len({(tuple(q), tuple(n)) for q, n in zip(p[new_faces].reshape(-1, 3), corner_normals)}) == 24  # 8 corners × 3 fans
    source, new_faces, normals = crease_normals(positions, faces, 180.0)
    p = positions if source is None else positions[source]
    # 180°: every corner gets the normalized sum of the unit normals of all triangles at its position
    unit = {}
    for k, (a, b, c) in enumerate(CUBE_CORNERS[CUBE_FACES]):
        unit[k] = np.cross(b - a, c - a) / np.linalg.norm(np.cross(b - a, c - a))
    for vertex, normal in zip(p[new_faces].reshape(-1, 3), normals[new_faces].reshape(-1, 3)):
        total = sum(unit[k] for k, face in enumerate(CUBE_FACES) if (CUBE_CORNERS[face] == vertex).all(axis=1).any())
        np.testing.assert_allclose(normal, total / np.linalg.norm(total), atol=1e-12)


def test_a_triangle_soup_sphere_shades_smoothly():
    import trimesh

    sphere = trimesh.creation.icosphere(3)
    positions, faces = _soup(np.asarray(sphere.vertices), np.asarray(sphere.faces))
    source, new_faces, normals = crease_normals(positions, faces, 60.0)
    assert source is None  # one fan per soup corner: no split needed, positions stay as given
    exact = positions / np.linalg.norm(positions, axis=1)[:, None]
    assert np.min(np.einsum("ij,ij->i", normals, exact)) > 0.995  # smooth: near the sphere's normal


def test_a_crease_that_fades_out_splits_only_where_it_is_sharp():
    """A vertex whose faces are joined all around except across one sharp edge stays one vertex
    (its fan is connected the other way round); a vertex on a crease that runs through it splits."""
    # A fan of 6 triangles around the origin, with the rim lifted unevenly: measure the
    # dihedral angle at each spoke and put the crease angle between the largest and the rest,
    # so that exactly one spoke is sharp.
    angles = np.radians(np.arange(0, 360, 60))
    rim = np.stack([np.cos(angles), np.sin(angles), [0.0, 0.6, 0.1, 0.0, 0.1, 0.6]], axis=1)
    positions = np.vstack([[0, 0, 0], rim])
    faces = np.array([[0, 1 + k, 1 + (k + 1) % 6] for k in range(6)])
    a, b, c = (positions[faces[:, k]] for k in range(3))
    unit = np.cross(b - a, c - a)
    unit /= np.linalg.norm(unit, axis=1)[:, None]
    spoke_angles = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", unit, np.roll(unit, 1, axis=0)), -1, 1)))
    largest, second = np.sort(spoke_angles)[::-1][:2]
    assert largest - second > 5
    source, _, normals = crease_normals(positions, faces, (largest + second) / 2)
    centre_copies = 1 if source is None else int(np.sum(source == 0))
    assert centre_copies == 1  # faded crease: the centre keeps one normal
    source, _, _ = crease_normals(positions, faces, spoke_angles.min() / 2)  # every spoke sharp: 6 fans
    assert int(np.sum(source == 0)) == 6
    # A crease through the vertex (a folded strip): it splits.
    fold = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 1.0]], float)
    source, _, _ = crease_normals(fold, np.array([[0, 1, 2], [0, 3, 1]]), 20.0)
    assert source is not None and np.sum(source == 0) == 2 and np.sum(source == 1) == 2


def test_uv_seams_do_not_crease_and_keep_their_uvs():
    """A cylinder band whose seam vertices are duplicated with different UVs."""
    segments = 12
    angles = np.linspace(0, 2 * np.pi, segments + 1)  # the last column repeats the first: the seam
    ring = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    positions = np.vstack([np.column_stack([ring, np.zeros(segments + 1)]), np.column_stack([ring, np.ones(segments + 1)])])
    positions[segments] = positions[0]
    positions[2 * segments + 1] = positions[segments + 1]
    uvs = np.column_stack([np.tile(np.linspace(0, 1, segments + 1), 2), np.repeat([0.0, 1.0], segments + 1)])
    faces = []
    for k in range(segments):
        a, b, c, d = k, k + 1, segments + 1 + k + 1, segments + 1 + k
        faces += [[a, b, c], [a, c, d]]
    mesh = Mesh.from_arrays(positions, np.array(faces), uvs=uvs, crease_angle=60.0)
    seam = np.flatnonzero(np.all(np.isclose(mesh.world_positions(), [1, 0, 0], atol=1e-6), axis=1))
    assert len(seam) == 2  # still two vertices (u = 0 and u = 1) ...
    np.testing.assert_allclose(mesh.normals[seam[0]], mesh.normals[seam[1]], atol=1e-6)  # ... with one smooth normal
    assert mesh.normals[seam[0], 0] > 0.99  # (nearly radial: 2 triangles on one side, 1 on the other)
    assert sorted(mesh.uvs[seam, 0].tolist()) == [0.0, 1.0]
    unwelded = Mesh.from_arrays(positions, np.array(faces), uvs=uvs)  # the seeds' per-vertex average
    seam = np.flatnonzero(np.all(np.isclose(unwelded.world_positions(), [1, 0, 0], atol=1e-6), axis=1))
    assert abs(unwelded.normals[seam[0], 1] - unwelded.normals[seam[1], 1]) > 0.3  # the visible seam it fixes


def test_obj_s_off_faces_are_flat_and_s_1_smooth():
    """Blender style: flat_tent under `s off`, smooth_tent under `s 1`; the tents' two faces
    meet at 90°, so at crease angle 180 only `s off` keeps them apart."""
    mesh = load_mesh(REAL / "smoothing_off.obj", crease_angle=180.0)
    p = mesh.world_positions()
    for face in mesh.indices:
        normal = np.cross(p[face[1]] - p[face[0]], p[face[2]] - p[face[0]])
        normal /= np.linalg.norm(normal)
        if p[face[0], 0] < 2.0:  # flat_tent: every corner has its face's normal
            np.testing.assert_allclose(mesh.normals[face], np.tile(normal, (3, 1)), atol=1e-6)
    ridge = np.isclose(p[:, 1], 0.0) & np.isclose(p[:, 2], 0.0)
    assert np.sum(ridge & (p[:, 0] < 2.0)) == 4  # flat: the ridge's 2 vertices split per face
    smooth_ridge = np.flatnonzero(ridge & (p[:, 0] > 2.0))
    assert len(smooth_ridge) == 2  # smooth: one vertex each, the average normal (0, -1, 0)
    np.testing.assert_allclose(mesh.normals[smooth_ridge], [[0, -1, 0], [0, -1, 0]], atol=1e-6)


def test_crease_angle_key_and_its_errors(tmp_path):
    (tmp_path / "cube.obj").write_text(
        "".join(f"v {x} {y} {z}\n" for x, y, z in CUBE_CORNERS) + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in CUBE_FACES)
    )
    (tmp_path / "s.toml").write_text('[[objects]]\nmesh = "cube.obj"\ncrease_angle = 180\n')
    assert load_scene(tmp_path / "s.toml").objects[0].mesh.vertex_count == 8
    assert load_scene(tmp_path / "s.toml", crease_angle=60.0).objects[0].mesh.vertex_count == 24  # the CLI's flag wins
    (tmp_path / "s.toml").write_text('[[objects]]\nmesh = "cube.obj"\n')
    assert load_scene(tmp_path / "s.toml").objects[0].mesh.vertex_count == 24  # default 60°
    (tmp_path / "bad.toml").write_text('[[objects]]\nmesh = "cube.obj"\ncrease_angle = 200\n')
    with pytest.raises(SceneError, match=r"\[\[objects\]\] #1.crease_angle: expected degrees between 0 and 180, got 200"):
        load_scene(tmp_path / "bad.toml")
    with pytest.raises(MeshError, match="crease_angle"):
        load_mesh(tmp_path / "cube.obj", crease_angle=-1)


@pytest.mark.parametrize("up, file_axis", [("+Y", (0, 1, 0)), ("+Z", (0, 0, 1)), ("-Z", (0, 0, -1)), ("+X", (1, 0, 0)), ("-X", (-1, 0, 0)), ("-Y", (0, -1, 0))])
def test_up_axis_turns_the_file_up_to_world_y(up, file_axis):
    obj = SceneObject(load_mesh("builtin:cube"), up=up)
    model = obj.world_from_model()
    direction = model[:3, :3] @ np.array(file_axis, float)
    np.testing.assert_allclose(direction, [0, 1, 0], atol=1e-12)
    assert np.linalg.det(model[:3, :3]) == pytest.approx(1.0)  # a rotation, never a mirror


def test_up_axis_errors_name_the_choices(tmp_path):
    with pytest.raises(SceneError, match=r"object.up: expected one of \+Y, -Y, \+Z, -Z, \+X, -X, got 'Q'"):
        SceneObject(load_mesh("builtin:cube"), up="Q")
    (tmp_path / "s.toml").write_text('[[objects]]\nmesh = "builtin:cube"\nup = "z"\n')
    assert load_scene(tmp_path / "s.toml").objects[0].up == "+Z"


def test_cli_up_turns_a_z_up_file_upright_and_flags_are_checked(tmp_path, capsys):
    """A box 3 units tall along Z: seen as written (+Y up) it lies down; with --up +Z it stands."""
    import imageio.v3 as iio

    from wgpu_shading.cli import main

    corners = CUBE_CORNERS * [0.5, 0.5, 1.5]
    (tmp_path / "tower.obj").write_text(
        "".join(f"v {x} {y} {z}\n" for x, y, z in corners) + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in CUBE_FACES)
    )
    extents = {}
    for up in ("+Y", "+Z"):
        output = tmp_path / f"{up}.png"
        assert main(["render", str(tmp_path / "tower.obj"), "--up", up, "--size", "64", "-o", str(output), "-q"]) == 0
        covered = np.argwhere(iio.imread(output)[..., :3].max(axis=2) > 0)
        extents[up] = np.ptp(covered, axis=0) + 1  # (rows, columns)
    assert extents["+Z"][0] > 2 * extents["+Z"][1]  # standing: much taller than wide
    assert extents["+Y"][0] < extents["+Y"][1] * 1.5  # lying: seen end-on from the front, not tall
    for flag, value, message in (("--up", "sideways", "expected one of +Y"), ("--crease-angle", "270", "between 0 and 180")):
        assert main(["render", str(tmp_path / "tower.obj"), flag, value]) == 2  # a usage error: exit 2, one line
        assert message in capsys.readouterr().err


def test_real_gltf_without_normal_attribute_is_flat():
    mesh = load_mesh(REAL / "cube.glb")  # exported by trimesh without NORMAL
    assert mesh.vertex_count == 3 * mesh.triangle_count == 36
    np.testing.assert_allclose(np.abs(mesh.normals).max(axis=1), 1.0, atol=1e-6)  # face normals of a cube


def test_crease_angle_0_is_flat():
    import trimesh

    sphere = trimesh.creation.icosphere(2)
    positions, faces = np.asarray(sphere.vertices), np.asarray(sphere.faces)
    source, new_faces, normals = crease_normals(positions, faces, 0.0)
    p = positions[source]
    a, b, c = (p[new_faces[:, k]] for k in range(3))
    face = np.cross(b - a, c - a)
    expected = np.repeat(face / np.linalg.norm(face, axis=1)[:, None], 3, axis=0)
    np.testing.assert_allclose(normals[new_faces].reshape(-1, 3), expected, atol=1e-12)


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("range_corners", [1 << 20, 7])
def test_split_vertices_gives_np_unique_of_vertex_and_fan(monkeypatch, seed, range_corners):
    """The output vertices are those of np.unique over (given vertex, fan) keys, in its
    order, with its inverse as the faces: the formulation split_vertices replaced (it sorts
    only the corners of vertices in several fans, a range of vertices at a time: ranges of
    ~7 corners here). Random corners: unused vertices, vertices in one fan, vertices in up
    to four."""
    from wgpu_shading.scene.geometry import corner_ids

    monkeypatch.setattr(corner_ids, "RANGE_IDS", range_corners)
    rng = np.random.default_rng(seed)
    vertex_count, table_size = int(rng.integers(1, 60)), int(rng.integers(1, 90))
    flat_corners = rng.integers(0, vertex_count, 3 * int(rng.integers(1, 80)))
    fans_of = [rng.integers(0, table_size, int(rng.choice([1, 1, 1, 2, 4]))) for _ in range(vertex_count)]
    label = np.array([rng.choice(fans_of[v]) for v in flat_corners], np.int64)
    vertex_fan = np.full(vertex_count, -1, np.int64)
    vertex_fan[flat_corners] = label
    table = rng.normal(size=(table_size, 3))

    source, faces, normals = split_vertices(flat_corners, label, vertex_fan, table)

    keys = flat_corners * table_size + label
    unique_keys, inverse = np.unique(keys, return_inverse=True)
    np.testing.assert_array_equal(source, unique_keys // table_size)
    np.testing.assert_array_equal(faces, inverse.reshape(-1, 3))
    assert faces.dtype == np.uint32
    np.testing.assert_array_equal(normals, table[unique_keys % table_size])


@pytest.mark.parametrize("seed", range(8))
def test_split_vertices_where_each_fan_has_one_vertex_gives_np_unique_of_vertex_and_fan(seed):
    """Where every label's corners share one given vertex (a welded mesh: each fan lies
    around one vertex), the labels are sorted by vertex once (crease_normals._split_by_label):
    still np.unique's vertices, order and inverse."""
    rng = np.random.default_rng(seed)
    vertex_count = int(rng.integers(1, 60))
    fans_of = [rng.choice(5, int(rng.choice([1, 1, 2, 3])), replace=False) + 5 * v for v in range(vertex_count)]
    flat_corners = rng.integers(0, vertex_count, 3 * int(rng.integers(1, 80)))
    label = np.array([rng.choice(fans_of[v]) for v in flat_corners], np.int64)
    vertex_fan = np.full(vertex_count, -1, np.int64)
    vertex_fan[flat_corners] = label
    table = rng.normal(size=(5 * vertex_count, 3))

    source, faces, normals = split_vertices(flat_corners, label, vertex_fan, table)

    unique_keys, inverse = np.unique(flat_corners * len(table) + label, return_inverse=True)
    np.testing.assert_array_equal(source, unique_keys // len(table))
    np.testing.assert_array_equal(faces, inverse.reshape(-1, 3))
    assert faces.dtype == np.uint32
    np.testing.assert_array_equal(normals, table[unique_keys % len(table)])


def test_split_vertices_with_vertices_without_corners_between_ranges(monkeypatch):
    """Ranges are cut by the corners' counts, about 2 corners each here: vertices 1-8 have
    none, so the ranges are uneven; still np.unique's vertices and inverse."""
    from wgpu_shading.scene.geometry import corner_ids

    monkeypatch.setattr(corner_ids, "RANGE_IDS", 2)
    flat_corners = np.array([0, 0, 0, 9, 9, 9, 0, 9, 0])
    label = np.array([1, 2, 1, 3, 4, 3, 2, 4, 1])
    vertex_fan = np.full(10, -1)
    vertex_fan[flat_corners] = label
    table = np.random.default_rng(0).normal(size=(5, 3))
    source, faces, normals = split_vertices(flat_corners, label, vertex_fan, table)
    unique_keys, inverse = np.unique(flat_corners * 5 + label, return_inverse=True)
    np.testing.assert_array_equal(source, unique_keys // 5)
    np.testing.assert_array_equal(faces, inverse.reshape(-1, 3))
    np.testing.assert_array_equal(normals, table[unique_keys % 5])


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("block", [7, 1 << 16])
@pytest.mark.parametrize("given_faces", [False, True])
def test_largest_face_normals_where_sums_cancel_follow_the_whole_array_rule(monkeypatch, seed, block, given_faces):
    """Where the faces' normals around a label sum to nothing (faces there twice, wound both
    ways), its normal is its largest face's; of equal areas (a face and its mirror) the last
    corner's; faces without area never. The whole-array formulation that this blockwise one
    replaced is the reference: every corner's face at once, stably sorted by area, written
    in that order (blocks of 7 corners here too)."""
    from wgpu_shading.scene.geometry import fan_normals
    from wgpu_shading.scene.geometry.face_normals import FaceNormals

    monkeypatch.setattr(fan_normals, "FACE_BLOCK", block)
    rng = np.random.default_rng(seed)
    positions = rng.normal(size=(25, 3))
    faces = rng.integers(0, 25, (80, 3))
    faces = np.concatenate([faces, faces[:, ::-1], faces[:10]])  # mirrors (equal areas), repeats
    faces[:5, 1] = faces[:5, 0]  # triangles without area
    rng.shuffle(faces)
    normals = FaceNormals(positions, faces)
    labels = faces.reshape(-1)
    corner_faces = None
    if given_faces:  # fans (fan_normals): labels of their own, each corner's face given
        labels = rng.integers(0, 40, len(labels))
        corner_faces = np.arange(len(labels)) // 3
    cancelled = rng.random(labels.max() + 1) < 0.7
    result = np.zeros((len(cancelled), 3))
    fan_normals.largest_face_normals(result, cancelled, labels, corner_faces, normals)

    expected = np.zeros((len(cancelled), 3))
    corners = np.flatnonzero(cancelled[labels])
    unit, area = normals.of(corners // 3)
    order = np.argsort(area, kind="stable")
    keep = area[order] > 0
    expected[labels[corners[order]][keep]] = unit[order][keep]
    np.testing.assert_array_equal(result, expected)
    assert (np.abs(expected).sum(axis=1) > 0).sum() > 5  # labels that took a face's normal
