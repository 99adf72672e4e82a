"""Meshes: built-ins with exact normals, files through trimesh, computed vertex normals,
and clear errors for invalid data."""

from __future__ import annotations

import numpy as np
import pytest

from test_file_parts import head_on, pixel
from wgpu_shading import MeshError, SceneObject, load_mesh
from wgpu_shading.scene import Mesh, sphere_for_triangles, uv_sphere, vertex_normals


@pytest.mark.parametrize(
    "spec, triangles",
    [
        ("builtin:sphere?slices=5&stacks=3", 20),
        ("builtin:sphere?slices=20&stacks=20", 2 * 20 * 19),
        ("builtin:torus", 2 * 48 * 48),
        ("builtin:cube", 12),
        ("builtin:plane?subdivisions=3", 18),
    ],
)
def test_builtins(spec, triangles):
    mesh = load_mesh(spec)
    assert mesh.triangle_count == triangles
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, atol=1e-6)
    # Counter-clockwise front faces: the face normal agrees with the vertex normals.
    p = mesh.world_positions()
    f = mesh.indices
    face = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
    assert (np.einsum("ij,ij->i", face, mesh.normals[f].sum(axis=1)) > 0).all()


def test_sphere_normals_are_exact():
    mesh = uv_sphere(2.0, 16, 8)
    p = mesh.world_positions()
    np.testing.assert_allclose(np.linalg.norm(p, axis=1), 2.0, rtol=1e-6)
    np.testing.assert_allclose(mesh.normals, p / 2.0, atol=1e-6)


@pytest.mark.parametrize("wanted", [20, 1000, 100_000])
def test_sphere_for_triangles(wanted):
    assert abs(sphere_for_triangles(wanted).triangle_count - wanted) / wanted < 0.1


def test_computed_normal_is_the_normalized_sum_of_unit_face_normals():
    # A vertex shared by a big face in the XY plane and a small face in the XZ plane:
    # unit normals (not area-weighted) sum to (0, 1, 1)/sqrt(2); area weights would give mostly +Z.
    positions = np.array([[0, 0, 0], [10, 0, 0], [0, 10, 0], [0, 0, 1]], float)
    faces = np.array([[0, 1, 2], [0, 3, 1]])
    normals = vertex_normals(positions, faces)
    np.testing.assert_allclose(normals[0], np.array([0, 1, 1]) / np.sqrt(2), atol=1e-12)


def test_cancelling_normals_fall_back_to_the_largest_face():
    # Both sides of a sheet share vertices: unit normals cancel exactly.
    positions = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0]], float)
    faces = np.array([[0, 1, 2], [0, 2, 1]])
    normals = vertex_normals(positions, faces)
    assert np.all(np.isfinite(normals))
    np.testing.assert_allclose(np.abs(normals[:, 2]), 1.0)


def test_zero_area_faces_contribute_nothing():
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]], float)
    faces = np.array([[0, 1, 2], [0, 1, 3]])  # the second is degenerate (collinear)
    normals = vertex_normals(positions, faces)
    np.testing.assert_allclose(normals[0], [0, 0, 1])
    np.testing.assert_allclose(normals[3], [0, 0, 0])  # touches no real face


def test_far_from_origin_keeps_precision():
    base = np.array([1e5, 1e5, 1e5])
    positions = base + np.array([[0, 0, 0], [1e-3, 0, 0], [0, 1e-3, 0]])
    mesh = Mesh.from_arrays(positions, [[0, 1, 2]])
    # float32 absolute coordinates near 1e5 have a spacing of ~0.008; relative ones keep 1e-3 exactly enough.
    np.testing.assert_allclose(mesh.world_positions(), positions, atol=1e-9)


@pytest.mark.parametrize(
    "positions, faces, message",
    [
        ([[0, 0, 0], [1, 0, 0], [0, np.nan, 0]], [[0, 1, 2]], "1 vertex has NaN or infinite coordinates (first: vertex 2"),
        ([[0, 0, 0], [1, 0, 0], [0, np.inf, 0]], [[0, 1, 2]], "NaN or infinite"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]], "index 3 is out of range; the mesh has 3 vertices"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, -1]], "index -1 is out of range"),
        (np.zeros((0, 3)), np.zeros((0, 3), int), "the mesh is empty"),
        ([[0, 0, 0], [1, 0, 0]], [[0, 1]], "indices must have shape (F, 3)"),
    ],
)
def test_invalid_meshes_are_clear_errors(positions, faces, message):
    with pytest.raises(MeshError) as error:
        Mesh.from_arrays(np.asarray(positions, float), np.asarray(faces), name="bad")
    assert message in str(error.value) and str(error.value).startswith("bad:")


def test_obj_file_normals_are_used_when_present(tmp_path):
    path = tmp_path / "tri.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0.6 0.8\nvn 0 0.6 0.8\nvn 0 0.6 0.8\nf 1//1 2//2 3//3\n")
    mesh = load_mesh(path)
    np.testing.assert_allclose(mesh.normals, [[0, 0.6, 0.8]] * 3, atol=1e-6)


def test_obj_file_without_normals_gets_computed_ones(tmp_path):
    path = tmp_path / "tri.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    np.testing.assert_allclose(load_mesh(path).normals, [[0, 0, 1]] * 3, atol=1e-6)


def test_obj_material_from_mtl(tmp_path):
    (tmp_path / "m.mtl").write_text("newmtl shiny\nKa 0.1 0.2 0.3\nKd 0.4 0.5 0.6\nKs 0.7 0.8 0.9\nNs 42\nKe 0.05 0 0\nd 0.5\n")
    (tmp_path / "m.obj").write_text("mtllib m.mtl\nusemtl shiny\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    m = load_mesh(tmp_path / "m.obj").material
    assert m is not None and m.name == "shiny"
    assert m.ambient == (0.1, 0.2, 0.3, 0.5) and m.diffuse == (0.4, 0.5, 0.6, 0.5)
    assert m.specular == (0.7, 0.8, 0.9, 0.5) and m.shininess == 42.0 and m.emission == (0.05, 0.0, 0.0, 1.0)


def test_mesh_file_errors(tmp_path):
    with pytest.raises(MeshError, match="not found"):
        load_mesh(tmp_path / "missing.obj")
    (tmp_path / "notes.txt").write_text("hello")
    with pytest.raises(MeshError, match="unsupported format '.txt'"):
        load_mesh(tmp_path / "notes.txt")
    (tmp_path / "empty.obj").write_text("# nothing\n")
    with pytest.raises(MeshError, match="no triangles"):
        load_mesh(tmp_path / "empty.obj")
    with pytest.raises(MeshError, match="unknown parameter 'slice'"):
        load_mesh("builtin:sphere?slice=3")


def test_obj_texture_from_mtl_map_kd(tmp_path, renderer):
    """An OBJ whose MTL names a texture (map_Kd) renders with it, as its author meant."""
    import imageio.v3 as iio

    from wgpu_shading import Camera, Scene, SceneObject

    pixels = np.zeros((4, 4, 3), np.uint8)
    pixels[:, :2] = (255, 0, 0)  # left half red
    pixels[:, 2:] = (0, 0, 255)  # right half blue
    iio.imwrite(tmp_path / "halves.png", pixels)
    (tmp_path / "m.mtl").write_text("newmtl painted\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nmap_Kd halves.png\n")
    (tmp_path / "quad.obj").write_text(
        "mtllib m.mtl\nusemtl painted\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"
    )
    mesh = load_mesh(tmp_path / "quad.obj")
    assert mesh.material is not None and mesh.material.texture is not None
    scene = Scene(objects=(SceneObject(mesh, mesh.material),), camera=Camera(eye=(0, 0, 2.0)), ambient=(1, 1, 1, 1), size=(32, 32))
    image = renderer.render(scene)
    assert image[16, 4, 0] > 200 and image[16, 4, 2] < 30  # left: red
    assert image[16, 27, 2] > 200 and image[16, 27, 0] < 30  # right: blue


@pytest.mark.parametrize("suffix", [".ply", ".stl", ".off", ".glb", ".obj"])
def test_every_supported_file_format_loads(tmp_path, suffix):
    """The formats the README promises, written by trimesh's exporters and read back."""
    import trimesh

    source = load_mesh("builtin:sphere?slices=12&stacks=6")
    path = tmp_path / f"sphere{suffix}"
    trimesh.Trimesh(source.world_positions(), source.indices.astype(np.int64), process=False).export(path)
    mesh = load_mesh(path)
    assert mesh.triangle_count == source.triangle_count
    # STL stores unshared corners; the others keep the vertices. Either way the surface is the
    # unit sphere and every computed normal points outward.
    positions = mesh.world_positions()
    np.testing.assert_allclose(np.linalg.norm(positions, axis=1), 1.0, atol=1e-5)
    assert (np.einsum("ij,ij->i", mesh.normals, positions) > 0.5).all()


def _facet(a, b, c) -> str:
    return "facet normal 0 0 1\nouter loop\n" + "".join(f"vertex {x} {y} 0\n" for x, y in (a, b, c)) + "endloop\nendfacet\n"


def _solid(name: str, x0: float) -> str:
    corners = [(x0, -0.5), (x0 + 1, -0.5), (x0 + 1, 0.5), (x0, 0.5)]
    return f"solid {name}\n" + _facet(corners[0], corners[1], corners[2]) + _facet(corners[0], corners[2], corners[3]) + f"endsolid {name}\n"


def test_ascii_stl_with_several_solids_draws_them_all(tmp_path, renderer):
    """CAD tools export an assembly as one ASCII STL with a `solid` per body (trimesh's
    models/multibody.stl, two_objects_mixed_case_names.stl); f3d and slicers draw every body.
    It used to stop with "expected one mesh, found 2"."""
    (tmp_path / "two.stl").write_text(_solid("left", -1.5) + _solid("Right", 0.5))
    mesh = load_mesh(tmp_path / "two.stl")
    assert sum(p.count for p in mesh.parts) == 4
    image = renderer.render(head_on([SceneObject(mesh)], "flat"))
    left, right, gap = pixel(image, -1.0, 0.0), pixel(image, 1.0, 0.0), pixel(image, 0.0, 0.0)
    assert left[3] == right[3] == 255 and left[:3].sum() > 100
    assert tuple(left) == tuple(right)  # same default material, same facing
    assert tuple(gap[:3]) == (0, 0, 0)


@pytest.mark.parametrize("angle", [-5, 180.5, float("nan")])
def test_a_bad_crease_angle_is_refused_for_a_builtin_too(angle):
    # A built-in's normals are exact, so the angle does nothing there, but a bad value is
    # still the caller's mistake and must not pass silently.
    with pytest.raises(MeshError, match="crease_angle"):
        load_mesh("builtin:cube", crease_angle=angle)
