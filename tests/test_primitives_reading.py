"""Points and lines read from files (issue 27, docs/primitives.md): faceless PLY, OBJ and OFF
are point clouds, OBJ `l`/`p` records lines and points, glTF's seven modes each what the
specification says; real files (tests/data/real/primitives, LICENCES.md there) are checked
against an independent reading of the file (its JSON and buffer decoded here, or trimesh)."""

from __future__ import annotations

import base64
import json
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import MeshError, load_mesh
from wgpu_shading.scene import Mesh

REAL = Path(__file__).parent / "data" / "real" / "primitives"


def _segments_by_position(mesh: Mesh, part) -> set[tuple]:
    """A line part's segments as unordered pairs of rounded model-space endpoints."""
    ends = mesh.world_positions()[mesh.line_indices[part.first : part.first + part.count]]
    return {tuple(sorted((tuple(np.round(a, 4)), tuple(np.round(b, 4))))) for a, b in ends}


def test_mesh_primitive_modes_reads_each_mode_as_the_specification_says():
    """Khronos' MeshPrimitiveModes: one hexagon (7 vertices) per node, in modes 0..6. The
    expected elements come from the file's own index lists, decoded here from its base64
    buffer: POINTS 7 points, LINES 6 segments, LINE_LOOP 7 (closing back to the first),
    LINE_STRIP 6 (not closed), and the three triangle modes 6 + 4 + 6 triangles."""
    document = json.loads((REAL / "MeshPrimitiveModes.gltf").read_text())
    blob = base64.b64decode(document["buffers"][0]["uri"].split(",", 1)[1])
    view = document["bufferViews"][0]
    accessors = document["accessors"]

    def indices(number):
        accessor = accessors[number]
        start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
        return np.frombuffer(blob, np.uint16, accessor["count"], start).astype(int)

    positions_view = document["bufferViews"][accessors[7]["bufferView"]]
    hexagon = np.frombuffer(blob, np.float32, 21, positions_view.get("byteOffset", 0)).reshape(7, 3).astype(float)
    mesh = load_mesh(REAL / "MeshPrimitiveModes.gltf")
    kinds = [part.primitive for part in mesh.parts]
    assert kinds == ["points", "lines", "lines", "lines", "triangles", "triangles", "triangles"]
    assert [part.count for part in mesh.parts] == [7, 6, 7, 6, 6, 4, 6]
    for node, part in enumerate(mesh.parts[1:4], start=1):  # LINES, LINE_LOOP, LINE_STRIP
        listed = indices(node)
        if node == 1:
            pairs = listed.reshape(-1, 2)
        else:  # a loop closes back to its first vertex, a strip does not
            pairs = np.stack([listed, np.roll(listed, -1)], 1) if node == 2 else np.stack([listed[:-1], listed[1:]], 1)
        offset = np.asarray(document["nodes"][node]["translation"], float)
        expected = {tuple(sorted((tuple(np.round(hexagon[a] + offset, 4)), tuple(np.round(hexagon[b] + offset, 4))))) for a, b in pairs}
        assert _segments_by_position(mesh, part) == expected, node
    points = mesh.world_positions()[mesh.parts[0].first : mesh.parts[0].first + 7]
    np.testing.assert_allclose(points, hexagon[indices(0)] + document["nodes"][0]["translation"], atol=1e-6)
    assert not mesh.normals[:7].any()  # no NORMAL: drawn unlit
    assert all(part.material.unlit for part in mesh.parts[:4]) and not any(part.material.unlit for part in mesh.parts[4:])


@pytest.mark.parametrize("name, closed", [("Mesh_PrimitiveMode_02.gltf", True), ("Mesh_PrimitiveMode_03.gltf", True)])
def test_line_loop_and_strip_from_the_asset_generator_close_the_quad(name, closed):
    """LINE_LOOP's closing edge exists only through the loop; the LINE_STRIP repeats its first
    vertex at the end: both draw the same closed quad of 4 segments."""
    mesh = load_mesh(REAL / name)
    (part,) = mesh.parts
    assert part.primitive == "lines" and part.count == 4
    ends = {tuple(np.round(p, 4)) for p in mesh.world_positions()}
    assert len(ends) == 4
    degree = {}
    for a, b in _segments_by_position(mesh, part):
        degree[a] = degree.get(a, 0) + 1
        degree[b] = degree.get(b, 0) + 1
    assert sorted(degree.values()) == [2, 2, 2, 2]  # a closed loop through all four corners


def test_obj_lines_keep_their_usemtl_materials():
    """Online3DViewer's lines_colors.obj: `l 1 2`, `l 3 4` red, the polyline `l 5 6 7 8 5`
    green (4 segments), `l 1 5` blue, with the MTL's Kd."""
    mesh = load_mesh(REAL / "lines_colors.obj")
    assert [(p.primitive, p.count, p.name) for p in mesh.parts] == [("lines", 2, "Red"), ("lines", 4, "Green"), ("lines", 1, "Blue")]
    assert [p.material.diffuse[:3] for p in mesh.parts] == [(0.8, 0.2, 0.2), (0.15294, 0.60784, 0.38039), (0.0, 0.54118, 0.72157)]
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)

    def pairs(*indices):
        return {tuple(sorted((tuple(v[a - 1]), tuple(v[b - 1])))) for a, b in indices}

    assert _segments_by_position(mesh, mesh.parts[0]) == pairs((1, 2), (3, 4))
    assert _segments_by_position(mesh, mesh.parts[1]) == pairs((5, 6), (6, 7), (7, 8), (8, 5))
    assert _segments_by_position(mesh, mesh.parts[2]) == pairs((1, 5))


def test_blender_wireframe_and_bare_vertices():
    wire = load_mesh(REAL / "obj_wireframe.obj")
    assert wire.primitives == {"lines"} and wire.line_count == 12 and wire.vertex_count == 8
    corners = {tuple(p) for p in np.round(wire.world_positions())}
    assert corners == {(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)}
    points = load_mesh(REAL / "obj_points.obj")
    assert points.primitives == {"points"} and points.point_count == 8 and points.material is None


def test_obj_point_records_relative_indices_and_errors(tmp_path):
    (tmp_path / "p.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 -1\nl 1/1 2/1\nf 1 2 3\n")
    mesh = load_mesh(tmp_path / "p.obj")
    assert sorted(p.primitive for p in mesh.parts) == ["lines", "points", "triangles"]
    point_part = next(p for p in mesh.parts if p.primitive == "points")
    np.testing.assert_allclose(mesh.world_positions()[point_part.first : point_part.first + 2], [[0, 0, 0], [0, 1, 0]])
    for text, words in (("v 0 0 0\nl 1\n", "bad.obj:2: a line needs at least 2 vertices"),
                        ("v 0 0 0\nv 1 0 0\nl 1 3\n", "bad.obj:3: 'l 1 3' refers to a vertex that does not exist"),
                        ("v 0 0 0\nv 1 0 0\nl 0 1\n", "bad.obj:3: 'l 0 1' refers to a vertex that does not exist"),
                        ("v 0 0 0\np x\n", "bad.obj:2: cannot read 'p x'")):
        (tmp_path / "bad.obj").write_text(text)
        with pytest.raises(MeshError, match=words):
            load_mesh(tmp_path / "bad.obj")


@pytest.mark.parametrize("name", ["ply_points_ascii.ply", "ply_points_bin.ply", "livingroom1_slac_fragment_000.ply"])
def test_faceless_ply_files_are_point_clouds_with_their_colours_and_normals(name):
    """trimesh (an independent PLY reader) gives the positions and colours; the binary files
    go through our numpy reader (mesh_formats/ply.py), the ASCII one through trimesh."""
    import trimesh

    reference = trimesh.load(REAL / name, process=False)
    mesh = load_mesh(REAL / name)
    assert mesh.primitives == {"points"} and mesh.point_count == len(reference.vertices)
    np.testing.assert_allclose(mesh.world_positions(), reference.vertices, atol=1e-6)
    if len(getattr(reference, "colors", ())):
        np.testing.assert_allclose(mesh.colors, np.asarray(reference.colors) / 255.0, atol=1e-6)
    if name == "livingroom1_slac_fragment_000.ply":
        raw = reference.metadata["_ply_raw"]["vertex"]["data"]
        normals = np.stack([raw[k] for k in ("nx", "ny", "nz")], axis=1).reshape(-1, 3)
        np.testing.assert_allclose(mesh.normals, normals / np.linalg.norm(normals, axis=1, keepdims=True), atol=1e-6)
    elif name == "ply_points_bin.ply":
        assert not mesh.normals.any()  # the file's normals are all zero: drawn unlit


def test_binary_point_clouds_in_either_byte_order_and_truncated(tmp_path):
    points = np.array([[0, 0, 0], [1, 2, 3], [-1, 0.5, 2]], np.float32)
    for order, tag in (("<", "binary_little_endian"), (">", "binary_big_endian")):
        header = f"ply\nformat {tag} 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
        records = np.zeros(3, [("p", order + "f4", 3), ("c", "u1", 4)])
        records["p"], records["c"] = points, [[255, 0, 0, 255], [0, 255, 0, 128], [0, 0, 255, 0]]
        (tmp_path / "c.ply").write_bytes(header.encode() + records.tobytes())
        mesh = load_mesh(tmp_path / "c.ply")
        np.testing.assert_allclose(mesh.world_positions(), points, atol=1e-6)
        np.testing.assert_allclose(mesh.colors, records["c"] / 255.0, atol=1e-7)
        (tmp_path / "c.ply").write_bytes(header.encode() + records.tobytes()[:-1])
        with pytest.raises(MeshError, match="c.ply"):
            load_mesh(tmp_path / "c.ply")


def test_an_off_without_faces_is_a_point_cloud(tmp_path):
    (tmp_path / "p.off").write_text("OFF\n3 0 0\n3600 7400 2740\n3601 7401 2741\n3602 7400 2742\n")
    mesh = load_mesh(tmp_path / "p.off")
    assert mesh.primitives == {"points"} and mesh.point_count == 3
    np.testing.assert_allclose(mesh.world_positions()[1], [3601, 7401, 2741])


def test_mesh_from_arrays_builds_point_clouds_and_line_sets():
    cloud = Mesh.from_arrays(np.random.default_rng(0).random((5, 3)))
    assert cloud.primitives == {"points"} and cloud.triangle_count == 0 and not cloud.normals.any()
    lines = Mesh.from_arrays([[0, 0, 0], [1, 0, 0], [1, 1, 0]], lines=[[0, 1], [1, 2]])
    assert lines.primitives == {"lines"} and lines.line_count == 2
    with pytest.raises(MeshError, match="index 3 is out of range"):
        Mesh.from_arrays([[0, 0, 0], [1, 0, 0], [1, 1, 0]], lines=[[0, 3]])
    # welding at a crease keeps the lines on vertices of their own
    mixed = Mesh.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5], [6, 5, 5]], [[0, 1, 2]], lines=[[3, 4]], crease_angle=30)
    np.testing.assert_allclose(mixed.world_positions()[mixed.line_indices[0]], [[5, 5, 5], [6, 5, 5]])


def test_a_long_obj_line_record_is_read_in_c_with_its_relative_indices(tmp_path):
    """One `l` record of 600,000 vertices, a third of them relative and some `v/vt` tokens:
    the segments join consecutive vertices as the tokens say (read one by one here), and
    the record costs a few tens of bytes a vertex (42 here, and a fixed ~17 MB of reading
    a file), not a Python list of its tokens (144: a 48 MB record of 24M vertices took
    3.3 GB to load, now ~1 GB)."""
    import tracemalloc

    rng = np.random.default_rng(3)
    count = 600_000
    vertex = rng.integers(1, 11, count)  # 1-based, of 10 `v` lines
    relative, with_uv = rng.random(count) < 0.3, rng.random(count) < 0.2
    words = [(str(v - 11) if r else str(v)) + ("/1" if u else "") for v, r, u in zip(vertex.tolist(), relative.tolist(), with_uv.tolist())]
    positions = rng.normal(size=(10, 3))
    path = tmp_path / "track.obj"
    path.write_text("".join(f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in positions) + "vt 0 0\nl " + " ".join(words) + "\n")
    tracemalloc.start()
    try:
        mesh = load_mesh(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert mesh.line_count == count - 1
    ends = mesh.world_positions()[np.asarray(mesh.line_indices)]
    np.testing.assert_allclose(ends[:, 0], positions[vertex[:-1] - 1], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(ends[:, 1], positions[vertex[1:] - 1], rtol=1e-6, atol=1e-6)
    assert peak < 70 * count, f"{peak / count:.0f} bytes a vertex"
