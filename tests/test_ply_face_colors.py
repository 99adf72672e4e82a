"""A PLY face's colour on polygons: every triangle a face is cut into gets the face's colour.

VTK and MeshLab write a colour a face (`property uchar red` ... after the face's index list)
for quads and polygons too. Those files went to trimesh, which cuts a quad into two
triangles but keeps one colour a quad, and the load failed ("colors must be numbers of
shape (12, 3 or 4), got (6, 4)"; a binary file of mixed sizes: "PLY is unexpected length!").
The reference here is the file's own polygons: each triangle of the mesh is matched, by its
corners' positions, to the one polygon that holds all three, whose colour it must have.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ply_reference import assert_same_mesh, through_trimesh, vertex_bytes
from wgpu_shading import load_mesh
from wgpu_shading.assets.mesh_formats import ply_polygons
from wgpu_shading.assets.mesh_formats.ply_header import PLY_TYPES

# A 4 × 3 grid of distinct positions; faces chosen so that no triangle's three corners lie
# in two faces (the reference below finds each triangle's face by its corners).
POSITIONS = np.array([[x, y, 0.1 * x * y] for y in range(3) for x in range(4)], np.float32) * 0.5
MIXED = [[0, 1, 5, 4], [1, 2, 6], [1, 6, 5], [4, 5, 9, 8], [6, 7, 11, 10, 9], [2, 3, 7], [0, 4], [5, 6, 9]]
QUADS = [[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [4, 5, 9, 8], [5, 6, 10, 9], [6, 7, 11, 10]]
PENTAGONS = [[0, 1, 2, 6, 5], [4, 5, 6, 10, 9], [2, 3, 7, 11, 6]]


def face_colors_of(faces) -> np.ndarray:
    rng = np.random.default_rng(len(faces))
    return rng.integers(0, 256, (len(faces), 4)).astype(np.uint8)


def write_ply(path: Path, faces, *, ascii=False, order="<", scalars=(("red", "uchar"), ("green", "uchar"), ("blue", "uchar")),
              vertex_colors=False) -> Path:
    """The grid's faces as a PLY whose faces carry `scalars` after their indices: the
    colour channels from face_colors_of(faces), any other scalar a number of its own."""
    colors = face_colors_of(faces)
    values = {name: colors[:, "rgba".index(name[0]) if name != "alpha" else 3] for name in ("red", "green", "blue", "alpha")}
    values["flags"] = np.arange(len(faces)) * 3 + 1
    values["quality"] = np.linspace(0.25, 0.75, len(faces))
    values = {name: values[name] for name, _ in scalars}
    if any(kind == "float" for name, kind in scalars if name in ("red", "green", "blue")):
        values |= {name: values[name] / 255.0 for name, kind in scalars if kind == "float" and name in ("red", "green", "blue")}
    vertex_columns = [("x", "float"), ("y", "float"), ("z", "float")] + (
        [("red", "uchar"), ("green", "uchar"), ("blue", "uchar")] if vertex_colors else [])
    vertex_values = {name: POSITIONS[:, "xyz".index(name)] for name in "xyz"}
    vertex_values |= {name: (np.arange(len(POSITIONS)) * (20 + 7 * k)) % 256 for k, name in enumerate(("red", "green", "blue"))}
    header = (f"ply\nformat {'ascii' if ascii else 'binary_little_endian' if order == '<' else 'binary_big_endian'} 1.0\n"
              f"element vertex {len(POSITIONS)}\n" + "".join(f"property {kind} {name}\n" for name, kind in vertex_columns)
              + f"element face {len(faces)}\nproperty list uchar int vertex_indices\n"
              + "".join(f"property {kind} {name}\n" for name, kind in scalars) + "end_header\n")
    if ascii:
        text = lambda value, kind: repr(float(value)) if kind in ("float", "double") else str(int(value))  # noqa: E731
        rows = [" ".join(text(vertex_values[name][i], kind) for name, kind in vertex_columns) for i in range(len(POSITIONS))]
        rows += [" ".join([str(len(face)), *map(str, face)] + [text(values[name][i], kind) for name, kind in scalars])
                 for i, face in enumerate(faces)]
        body = ("\n".join(rows) + "\n").encode()
    else:
        body = vertex_bytes(vertex_columns, vertex_values, len(POSITIONS), order)
        for i, face in enumerate(faces):
            body += np.array(len(face), np.uint8).tobytes() + np.array(face, order + "i4").tobytes()
            for name, kind in scalars:
                body += np.array(values[name][i], order + PLY_TYPES[kind]).tobytes()
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(header.encode() + bytes(body))
    return path


def expected_triangle_colors(mesh, faces, channels: int) -> np.ndarray:
    """The colour of each of the mesh's triangles: that of the file's face holding its three
    corners (found by position), as the file gives it (0..1)."""
    positions = np.asarray(mesh.world_positions(), np.float64)  # (a Mesh keeps them about its origin)
    vertex_of = [int(np.argmin(np.abs(POSITIONS - corner).sum(axis=1))) for corner in positions]
    assert np.allclose(POSITIONS[vertex_of], positions, atol=1e-6)
    colors = face_colors_of(faces)[:, :channels] / 255.0
    expected = []
    for triangle in np.asarray(mesh.indices):
        corners = {vertex_of[int(index)] for index in triangle}
        holders = [number for number, face in enumerate(faces) if len(face) >= 3 and corners <= set(face)]
        assert len(holders) == 1, (triangle, corners, holders)
        expected.append(colors[holders[0]])
    return np.array(expected)


def assert_face_colors(mesh, faces, channels: int = 3) -> None:
    expected = expected_triangle_colors(mesh, faces, channels)
    assert mesh.colors is not None
    corner_colors = np.asarray(mesh.colors)[np.asarray(mesh.indices)]  # (triangles, 3, 4)
    for corner in range(3):  # every corner of a triangle its face's colour (unblended)
        np.testing.assert_allclose(corner_colors[:, corner, :channels], expected, atol=1e-6)
    assert mesh.triangle_count == sum(len(face) - 2 for face in faces if len(face) >= 3)


RGB = (("red", "uchar"), ("green", "uchar"), ("blue", "uchar"))
RGBA_AND_OTHERS = (("flags", "int"), ("red", "uchar"), ("green", "uchar"), ("blue", "uchar"), ("alpha", "uchar"), ("quality", "float"))
LAYOUTS = {
    "RGB": {"scalars": RGB},
    "big-endian, RGBA between MeshLab's flags and quality": {"order": ">", "scalars": RGBA_AND_OTHERS},
    "ASCII RGB": {"ascii": True, "scalars": RGB},
    "ASCII, RGBA between flags and quality": {"ascii": True, "scalars": RGBA_AND_OTHERS},
}


@pytest.mark.parametrize("block_bytes", [7, 8 << 20])
@pytest.mark.parametrize("faces", [MIXED, QUADS, PENTAGONS], ids=["mixed sizes", "quads", "pentagons"])
@pytest.mark.parametrize("options", LAYOUTS.values(), ids=LAYOUTS.keys())
def test_every_triangle_of_a_polygon_gets_the_polygons_colour(tmp_path, monkeypatch, options, faces, block_bytes):
    monkeypatch.setattr(ply_polygons, "BLOCK_BYTES", block_bytes)  # records cut across blocks
    mesh = load_mesh(write_ply(tmp_path / "mesh.ply", faces, **options))
    channels = 4 if ("alpha", "uchar") in options["scalars"] else 3
    assert_face_colors(mesh, faces, channels)


@pytest.mark.parametrize("faces", [MIXED, QUADS], ids=["mixed sizes", "quads"])
def test_binary_and_ascii_files_of_the_same_faces_give_the_same_mesh(tmp_path, faces):
    binary = load_mesh(write_ply(tmp_path / "binary" / "mesh.ply", faces))
    text = load_mesh(write_ply(tmp_path / "ascii" / "mesh.ply", faces, ascii=True))  # (through trimesh)
    for name in ("positions", "indices", "colors", "origin"):
        np.testing.assert_array_equal(getattr(binary, name), getattr(text, name), err_msg=name)


def test_float_face_colours_of_quads_are_given_to_their_triangles(tmp_path):
    """Float face colours are read by trimesh, which keeps one a quad: given to both its triangles."""
    scalars = (("red", "float"), ("green", "float"), ("blue", "float"))
    mesh = load_mesh(write_ply(tmp_path / "mesh.ply", QUADS, scalars=scalars))
    expected = expected_triangle_colors(mesh, QUADS, 3)
    corner_colors = np.asarray(mesh.colors)[np.asarray(mesh.indices)]
    np.testing.assert_allclose(corner_colors[:, 0, :3], expected, atol=1 / 255)  # (trimesh rounds them to bytes)


@pytest.mark.parametrize("ascii", [False, True], ids=["binary", "ASCII"])
def test_vertex_colours_win_over_face_colours_as_trimesh_reads_them(tmp_path, ascii):
    mesh = load_mesh(write_ply(tmp_path / "mesh.ply", MIXED, ascii=ascii, vertex_colors=True))
    assert mesh.vertex_count == len(POSITIONS)  # (no corner split for the faces' colours)
    expected = np.stack([(np.arange(len(POSITIONS)) * (20 + 7 * k)) % 256 for k in range(3)], axis=1) / 255.0
    np.testing.assert_allclose(np.asarray(mesh.colors)[:, :3], expected, atol=1e-6)


def test_polygon_colours_follow_the_order_trimesh_cuts_polygons_in():
    counts = np.array([4, 3, 2, 5, 4, 3, 6])
    colors = np.arange(len(counts))[:, None] * np.ones((1, 3), int)
    # triangles in file order, then every quad's first half, every quad's second, then fans
    expected = [1, 5] + [0, 4] + [0, 4] + [3] * 3 + [6] * 4
    np.testing.assert_array_equal(ply_polygons.polygon_colors(counts, colors)[:, 0], expected)


@pytest.mark.parametrize("order", ["<", ">"])
def test_mixed_polygons_with_meshlabs_flags_give_trimeshs_mesh_of_the_ascii_file(tmp_path, order):
    """Scalars after a face's indices sent a binary file of mixed sizes to trimesh, which
    refused it ("PLY is unexpected length!"): now read past, as trimesh reads the ASCII file."""
    scalars = (("flags", "int"), ("quality", "float"))
    binary = write_ply(tmp_path / "binary" / "mesh.ply", MIXED, order=order, scalars=scalars)
    expected = through_trimesh(write_ply(tmp_path / "ascii" / "mesh.ply", MIXED, ascii=True, scalars=scalars))
    assert_same_mesh(load_mesh(binary), expected)
