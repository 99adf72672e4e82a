"""Binary PLY triangle meshes read with numpy in blocks (assets/mesh_formats/ply_triangles.py):
the same Mesh as trimesh's reading of the same file, within bounded memory; every other
layout still goes to trimesh."""

from __future__ import annotations

import tracemalloc
from pathlib import Path
from unittest import mock

import numpy as np
import pytest

from ply_reference import assert_same_mesh, through_trimesh
from wgpu_shading import load_mesh
from wgpu_shading.assets.mesh_formats import ply, ply_triangles
from wgpu_shading.assets.mesh_formats.ply_header import read_ply_header
from wgpu_shading.assets.mesh_formats.ply_triangles import read_triangles, triangle_layout
from wgpu_shading.errors import MeshError

# ../shared, beside the project (CI has it), also from a worktree deeper down
SHARED = next((p / "shared" for p in Path(__file__).resolve().parents if (p / "shared" / "corpora").is_dir()), None)
REAL_FILES = SHARED / "corpora" / "realworld2" / "ply" if SHARED is not None else None
# The binary triangle meshes of the corpus (MeshLab with flags and RGBA, a big-endian scan
# with confidence, VTK's Lucy, MeshLab's doubles with quality): all read here.
READ_HERE = ("bone_meshlab.ply", "horse_bigendian_rgb.ply", "lucy.ply", "cube_meshlab_binary.ply", "colored_airplane_meshlab.ply")


def _layout(path: Path):
    return triangle_layout(read_ply_header(path, str(path)), path.stat().st_size)


@pytest.mark.parametrize("name", READ_HERE)
def test_real_binary_ply_meshes_are_read_as_trimesh_reads_them(name):
    if REAL_FILES is None or not (REAL_FILES / name).exists():
        pytest.skip("the shared corpus is not beside the project")
    path = REAL_FILES / name
    assert _layout(path) is not None
    assert_same_mesh(load_mesh(path), through_trimesh(path))


def _octahedron() -> tuple[np.ndarray, np.ndarray]:
    positions = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float) * 0.7 + 0.1
    faces = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    return positions, faces


def write_ply(path: Path, *, order="<", position="float", normals=None, colors=(), extras=(), index="int", count="uchar",
              counts=None, faces=None, vertex_names=None, face_extras=(), tail=b"") -> Path:
    """A binary PLY of the octahedron with the given property types (PLY type names)."""
    from wgpu_shading.assets.mesh_formats.ply_header import PLY_TYPES

    positions, octahedron = _octahedron()
    faces = octahedron.tolist() if faces is None else faces
    rng = np.random.default_rng(7)
    columns = [("x", position), ("y", position), ("z", position)]
    if normals:
        columns += [("nx", normals), ("ny", normals), ("nz", normals)]
    columns += [(name, "uchar") for name in colors] + list(extras) + [(name, "float") for name in (vertex_names or ())]
    row = np.dtype([(name, order + PLY_TYPES[kind]) for name, kind in columns])
    vertices = np.zeros(len(positions), row)
    for axis, name in enumerate("xyz"):
        vertices[name] = positions[:, axis]
    if normals:
        unit = positions / np.linalg.norm(positions, axis=1, keepdims=True) * 1.3  # not unit: kept as given
        for axis, name in enumerate(("nx", "ny", "nz")):
            vertices[name] = unit[:, axis]
    for name, _ in columns[3 + (3 if normals else 0):]:
        vertices[name] = rng.integers(0, 256, len(positions)) if name in colors else rng.random(len(positions))
    header = [f"ply\nformat {'binary_little_endian' if order == '<' else 'binary_big_endian'} 1.0\n",
              f"element vertex {len(positions)}\n"] + [f"property {kind} {name}\n" for name, kind in columns]
    header += [f"element face {len(faces)}\nproperty list {count} {index} vertex_indices\n"]
    header += [f"property {kind} {name}\n" for name, kind in face_extras] + ["end_header\n"]
    body = bytearray(vertices.tobytes())
    for number, face in enumerate(faces):
        body += np.array(len(face) if counts is None else counts[number], order + PLY_TYPES[count]).tobytes()
        body += np.array(face, order + PLY_TYPES[index]).tobytes()
        for column, (_, kind) in enumerate(face_extras):  # (each face its own values: its own colour)
            body += np.array((37 * number + 71 * column) % 200 + 1, order + PLY_TYPES[kind]).tobytes()
    path.write_bytes("".join(header).encode("ascii") + bytes(body) + tail)
    return path


LAYOUTS = {
    "little-endian floats": {},
    "big-endian": {"order": ">"},
    "doubles": {"position": "double"},
    "normals": {"normals": "float"},
    "double normals": {"normals": "double"},
    "RGB": {"colors": ("red", "green", "blue")},
    "RGBA, big-endian": {"colors": ("red", "green", "blue", "alpha"), "order": ">"},
    "MeshLab's flags and quality": {"extras": (("flags", "int"), ("quality", "double")), "colors": ("red", "green", "blue")},
    "uint indices, int counts": {"index": "uint", "count": "int"},
    "uint8/int32 spelling": {"index": "int32", "count": "uint8"},
    "quads": {"faces": [[0, 2, 1, 3], [0, 4, 1, 5], [2, 4, 3, 5]]},  # cut as trimesh cuts them: every (a, b, c), then every (c, d, a)
    "quads, int counts and uint indices": {"faces": [[0, 2, 1, 3], [0, 4, 1, 5]], "count": "int", "index": "uint"},
    "pentagons": {"faces": [[0, 2, 1, 3, 4], [5, 0, 4, 1, 2]]},  # fans, one polygon after the other
    "hexagons, big-endian": {"faces": [[0, 2, 1, 3, 4, 5], [5, 4, 3, 2, 1, 0]], "order": ">"},
    # scalars after the faces' indices, read past (trimesh keeps them aside)
    "MeshLab's face flags and quality": {"face_extras": (("flags", "int"), ("quality", "float")), "extras": (("flags", "int"),)},
    "quads with a face flag, big-endian": {"faces": [[0, 2, 1, 3], [0, 4, 1, 5]], "face_extras": (("flags", "int"),), "order": ">"},
    "pentagons with a uchar and a double after them": {"faces": [[0, 2, 1, 3, 4], [5, 0, 4, 1, 2]],
                                                        "face_extras": (("material", "uchar"), ("quality", "double"))},
    # a triangle's colour (MeshLab's face colours): every corner its own vertex, as trimesh gives them
    "face colours": {"face_extras": (("red", "uchar"), ("green", "uchar"), ("blue", "uchar"))},
    "a face flag and RGBA face colours, big-endian": {"face_extras": (("flags", "int"), ("red", "uchar"), ("green", "uchar"),
                                                                      ("blue", "uchar"), ("alpha", "uchar")), "order": ">"},
    "face colours beside vertex colours (the vertices' drawn)": {"colors": ("red", "green", "blue"),
                                                                 "face_extras": (("red", "uchar"), ("green", "uchar"), ("blue", "uchar"))},
}


@pytest.mark.parametrize("options", LAYOUTS.values(), ids=LAYOUTS.keys())
def test_each_layout_read_here_gives_trimeshs_mesh(tmp_path, options):
    path = write_ply(tmp_path / "mesh.ply", **options)
    assert _layout(path) is not None
    assert_same_mesh(load_mesh(path), through_trimesh(path))


OTHERS = {  # (mixed polygons, and vertex texture coordinates: ply_polygons.py, tests/test_ply_polygons.py;
    # polygons with a colour each, and mixed ones with MeshLab's flags: tests/test_ply_face_colors.py)
    "texture coordinates": {"vertex_names": ("u", "v")},
    "float face colours": {"face_extras": (("red", "float"), ("green", "float"), ("blue", "float"))},
    "float colours": {"extras": (("red", "float"), ("green", "float"), ("blue", "float"))},
}


@pytest.mark.parametrize("options", OTHERS.values(), ids=OTHERS.keys())
def test_other_layouts_still_go_to_trimesh(tmp_path, options):
    """Not read by this module: the same mesh as trimesh's reading (texture coordinates are
    read by ply_polygons.py, the same mesh too), or trimesh's error."""
    path = write_ply(tmp_path / "mesh.ply", **options)
    layout = _layout(path)
    assert layout is None or read_triangles(path, layout, "mesh") is None
    _assert_same_outcome(path, through_trimesh)


def _assert_same_outcome(path: Path, through_trimesh) -> None:
    """load_mesh(path) gives the mesh through_trimesh(path) gives, or raises its error."""
    try:
        expected = through_trimesh(path)
    except MeshError as error:
        with pytest.raises(MeshError) as raised:
            load_mesh(path)
        assert str(raised.value) == str(error)
        return
    assert_same_mesh(load_mesh(path), expected)


def test_a_face_that_is_not_a_triangle_sends_the_file_to_trimesh(tmp_path):
    # A quad and a two-corner face take as many bytes as two triangles: only the counts tell.
    path = write_ply(tmp_path / "mesh.ply", faces=[[0, 2, 4], [2, 1, 4], [0, 1, 2, 3], [0, 5]])
    layout = _layout(path)
    assert layout is not None
    assert read_triangles(path, layout, "mesh") is None


def test_a_face_index_beyond_the_vertices_is_named(tmp_path):
    path = write_ply(tmp_path / "mesh.ply", faces=[[0, 2, 4], [2, 1, 99]])
    assert _layout(path) is not None
    with pytest.raises(MeshError, match="refers to vertex 99, but the file has 6 vertices"):
        load_mesh(path)


def test_a_truncated_file_is_refused_as_before(tmp_path):
    path = write_ply(tmp_path / "mesh.ply")
    path.write_bytes(path.read_bytes()[:-5])
    assert _layout(path) is None
    with pytest.raises(MeshError, match="truncated|face"):
        load_mesh(path)


def test_reading_a_big_mesh_takes_little_more_than_its_arrays(tmp_path):
    """The rows are read a block at a time into the arrays kept: the reader's peak is
    those arrays and one block of rows (trimesh's reading of the same file held the whole
    file and float64/int64 copies of it: 10.6x the arrays here, traced the same way)."""
    side = 400  # a 400 × 400 grid: 160,000 vertices, 318,402 triangles
    u, v = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    positions = np.stack([u, v, 0.1 * np.sin(6 * u)], -1).reshape(-1, 3).astype("<f4")
    grid = np.arange(side * side).reshape(side, side)
    a, b, c, d = grid[:-1, :-1].ravel(), grid[:-1, 1:].ravel(), grid[1:, :-1].ravel(), grid[1:, 1:].ravel()
    faces = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])
    rows = np.zeros(len(faces), np.dtype([("count", "u1"), ("corners", "<i4", (3,))]))
    rows["count"], rows["corners"] = 3, faces
    path = tmp_path / "grid.ply"
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(positions)}\nproperty float x\nproperty float y\n"
              f"property float z\nelement face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    path.write_bytes(header.encode() + positions.tobytes() + rows.tobytes())
    arrays = positions.nbytes + faces.shape[0] * 3 * 4
    tracemalloc.start()
    try:  # blocks of 16,384 rows: this file is a few blocks, as a big one is many
        with mock.patch.object(ply_triangles, "BLOCK_ROWS", 1 << 14):
            piece = ply.read_ply(path, path.stat().st_size).pieces[0]
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    np.testing.assert_array_equal(piece.positions, positions)
    np.testing.assert_array_equal(piece.faces, faces)
    assert peak < 1.25 * arrays, f"peak {peak / arrays:.2f}x the arrays"


def write_ascii_ply(path: Path, *, position="float", normals=None, colors=(), extras=(), faces=None, ending="\n",
                    between="", after="", face_extras=()) -> Path:
    """The octahedron as an ASCII PLY with the given property types; `between` goes after the
    vertex lines, `after` after the face lines; `face_extras`: (name, type) scalars after
    each face's indices."""
    positions, octahedron = _octahedron()
    faces = octahedron.tolist() if faces is None else faces
    rng = np.random.default_rng(11)
    header = ["ply", "format ascii 1.0", f"element vertex {len(positions)}"] + [f"property {position} {axis}" for axis in "xyz"]
    header += [f"property {normals} {axis}" for axis in ("nx", "ny", "nz")] if normals else []
    header += [f"property uchar {name}" for name in colors] + [f"property {kind} {name}" for name, kind in extras]
    header += [f"element face {len(faces)}", "property list uchar int vertex_indices"]
    header += [f"property {kind} {name}" for name, kind in face_extras] + ["end_header"]
    rows = []
    for point in positions * 1e-3:  # exponents: 1.00000000e-04
        row = [f"{value:.8e}" for value in point]
        row += [f"{value:.7g}" for value in point / np.linalg.norm(point) * 1.3] if normals else []
        row += [str(int(rng.integers(0, 256))) for _ in colors]
        row += [str(int(rng.integers(0, 9))) if kind in ("int", "uchar") else f"{rng.random():.6f}" for _, kind in extras]
        rows.append(" ".join(row))
    face_rows = [f"{len(face)} " + " ".join(map(str, face)) + "".join(
        f" {int(rng.integers(0, 9))}" if kind in ("int", "uchar") else f" {rng.random():.6f}" for _, kind in face_extras) for face in faces]
    lines = header + rows + ([between] if between else []) + face_rows
    path.write_bytes((ending.join(lines) + ending + after).encode())
    return path


ASCII_LAYOUTS = {
    "floats": {},
    "doubles, CR LF": {"position": "double", "ending": "\r\n"},
    "normals and RGBA": {"normals": "float", "colors": ("red", "green", "blue", "alpha")},
    "MeshLab's flags and quality": {"extras": (("flags", "int"), ("quality", "double")), "colors": ("red", "green", "blue")},
    "blank lines at the end": {"after": "\n  \n"},
    "quads": {"faces": [[0, 2, 1, 3], [0, 4, 1, 5], [2, 4, 3, 5]]},
    "pentagons, CR LF": {"faces": [[0, 2, 1, 3, 4], [5, 0, 4, 1, 2]], "ending": "\r\n"},
    "MeshLab's face flags and quality": {"face_extras": (("flags", "int"), ("quality", "float"))},
    "quads with a face flag, CR LF": {"faces": [[0, 2, 1, 3], [0, 4, 1, 5]], "face_extras": (("flags", "int"),), "ending": "\r\n"},
}


@pytest.mark.parametrize("block_bytes", [2, 1 << 22])
@pytest.mark.parametrize("options", ASCII_LAYOUTS.values(), ids=ASCII_LAYOUTS.keys())
def test_ascii_ply_meshes_read_in_blocks_of_lines_give_trimeshs_mesh(tmp_path, monkeypatch, options, block_bytes):
    from wgpu_shading.assets import files
    from wgpu_shading.assets.mesh_formats import ply_ascii_triangles

    path = write_ascii_ply(tmp_path / "mesh.ply", **options)
    monkeypatch.setattr(files, "TEXT_BLOCK_BYTES", block_bytes)
    header = read_ply_header(path, "mesh")
    assert ply_ascii_triangles.read_ascii_triangles(path, header, "mesh") is not None
    assert_same_mesh(load_mesh(path), through_trimesh(path))


ASCII_OTHERS = {  # (mixed polygons: read here too, tests/test_ply_polygons.py)
    "a blank line among the rows": {"between": " "},
    "float colours": {"extras": (("red", "float"), ("green", "float"), ("blue", "float"))},
    "faces of two sizes with a face flag": {"faces": [[0, 2, 4], [2, 1, 4, 3]], "face_extras": (("flags", "int"),)},
    "face colours": {"face_extras": (("red", "uchar"), ("green", "uchar"), ("blue", "uchar"))},
}


@pytest.mark.parametrize("options", ASCII_OTHERS.values(), ids=ASCII_OTHERS.keys())
def test_other_ascii_plys_still_go_to_trimesh(tmp_path, options):
    from wgpu_shading.assets.mesh_formats import ply_ascii_triangles

    path = write_ascii_ply(tmp_path / "mesh.ply", **options)
    assert ply_ascii_triangles.read_ascii_triangles(path, read_ply_header(path, "mesh"), "mesh") is None
    _assert_same_outcome(path, through_trimesh)


def test_a_file_of_one_huge_face_is_refused_before_it_is_read(tmp_path, monkeypatch):
    """A face of more than MAX_FACE_CORNERS corners (the limit an OBJ line has): a 48 MB
    PLY of one face of 12M corners took trimesh 2.4 GB and 11 s to reach its error (ASCII:
    1.7 GB and 19 s). Faces
    of one size whose fans pass the triangle limit are refused before any array is made.
    (The limits made small here, the files small.)"""
    monkeypatch.setattr(ply_triangles, "MAX_FACE_CORNERS", 5)
    path = write_ply(tmp_path / "huge.ply", faces=[[0, 1, 2, 3, 4, 5]], count="int")
    with pytest.raises(MeshError, match="a face of 6 corners; at most 5"):
        load_mesh(path)
    counted_otherwise = write_ply(tmp_path / "counted.ply", faces=[[0, 1, 2, 3, 4, 5]], counts=[7], count="int")
    assert read_triangles(counted_otherwise, _layout(counted_otherwise), "mesh") is None  # to trimesh, which says what is wrong
    from wgpu_shading.assets.mesh_formats import ply_ascii_triangles

    monkeypatch.setattr(ply_ascii_triangles, "MAX_FACE_CORNERS", 5)  # an ASCII face: from its line's count (trimesh: 1.7 GB, 19 s)
    path = write_ascii_ply(tmp_path / "huge_ascii.ply", faces=[[0, 1, 2, 3, 4, 5]])
    with pytest.raises(MeshError, match="a face of 6 corners; at most 5"):
        load_mesh(path)
    monkeypatch.setattr(ply_triangles, "MAX_TRIANGLES", 5)
    path = write_ply(tmp_path / "many.ply", faces=[[0, 2, 1, 3], [0, 4, 1, 5], [2, 4, 3, 5]])
    with pytest.raises(MeshError, match="3 faces of 4 corners make 6 triangles; at most 5"):
        load_mesh(path)
    monkeypatch.setattr(ply_ascii_triangles, "MAX_TRIANGLES", 5)  # ASCII faces with scalars after them, the same
    path = write_ascii_ply(tmp_path / "many_ascii.ply", faces=[[0, 2, 1, 3], [0, 4, 1, 5], [2, 4, 3, 5]], face_extras=(("flags", "int"),))
    with pytest.raises(MeshError, match="3 faces of 4 corners make 6 triangles; at most 5"):
        load_mesh(path)


@pytest.mark.parametrize("faces", [[[0, 2, 4], [2, 6, 4]], [[0, 2, 1, 3], [0, 6, 1, 5]]], ids=["triangles (read here)", "quads (trimesh)"])
def test_a_face_colours_index_beyond_the_vertices_is_named(tmp_path, faces):
    """Face colours split every corner into its own vertex: an index beyond the vertices
    (the octahedron has 6) is the error every reader gives, not an IndexError of the split."""
    path = write_ply(tmp_path / "mesh.ply", faces=faces, face_extras=(("red", "uchar"), ("green", "uchar"), ("blue", "uchar")))
    with pytest.raises(MeshError, match="refers to vertex 6"):
        load_mesh(path)
