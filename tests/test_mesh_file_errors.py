"""Mesh files that cannot be drawn: each is exit 2 with one line naming the file and what is
wrong, and load_mesh raises MeshError with the same text; a size is judged from the header
before anything is allocated (docs/reliability.md)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from cli_errors import one_line_error, run_cli
from wgpu_shading import MeshError, load_mesh


def _write(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


MESH_CASES = [
    ("garbage.stl", lambda: np.random.default_rng(1).bytes(3000), ["garbage.stl", "not a valid STL file"]),
    ("garbage.obj", lambda: np.random.default_rng(2).bytes(3000), ["garbage.obj"]),
    ("garbage.ply", lambda: np.random.default_rng(3).bytes(3000), ["garbage.ply", "not a PLY file"]),
    ("garbage.off", lambda: np.random.default_rng(4).bytes(3000), ["garbage.off"]),
    ("empty.obj", lambda: b"", ["empty.obj", "empty"]),
    (
        "truncated.ply",
        lambda: b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        b"element face 200000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        ["truncated.ply", "200000000 faces"],
    ),
    (
        "short.ply",
        lambda: b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        b"element face 2000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        ["short.ply", "2000 faces", "truncated or damaged"],
    ),
    (
        "missing_face.ply",
        lambda: b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        b"element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        ["missing_face.ply", "truncated", "2 faces"],
    ),
    (  # found by the fuzz test: trimesh reads PLY faces unchecked, normals then failed with IndexError
        "face_out_of_range.ply",
        lambda: b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
        b"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n3 0 0 1\n",
        ["face_out_of_range.ply", "a face refers to vertex 1", "1 vertices"],
    ),
    ("face_out_of_range.stl", lambda: b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid\n", ["face_out_of_range.stl", "NaN or infinite"]),
    ("tiny.obj", lambda: b"v 0 0 0\nv 1e-20 0 0\nv 0 1e-20 0\nf 1 2 3\n", ["tiny.obj", "1.41e-20 units across"]),
    ("huge.obj", lambda: b"v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n", ["huge.obj"]),
    ("far.obj", lambda: b"v 1e15 0 0\nv 1e15 1 0\nv 1e15 0 1\nf 1 2 3\n", ["mesh", "far.obj", "automatic camera and lights"]),
]


@pytest.mark.parametrize("name, data, words", MESH_CASES, ids=[case[0] for case in MESH_CASES])
def test_bad_mesh_files_are_one_line_errors(tmp_path, capsys, name, data, words):
    path = _write(tmp_path / name, data())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"), "--size", "16")
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    for word in words:
        assert word in lines[0], lines[0]
    if name != "far.obj":
        with pytest.raises(MeshError) as error:
            load_mesh(path)
        assert lines[0] == f"wgpu-shading: error: {error.value}"


def test_a_two_gigabyte_ply_of_zeros_is_refused_from_its_header(tmp_path, capsys):
    path = tmp_path / "zeros.ply"
    with open(path, "wb") as file:
        file.truncate(2_000_000_000)  # sparse: no disk used
    code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    assert code == 2 and "not a PLY file" in err


def test_a_mesh_whose_triangles_have_no_area_is_an_error_not_a_blank_image(tmp_path, capsys):
    path = tmp_path / "collinear.obj"
    path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
    code, err = run_cli(capsys, "render", str(path), "-o", str(tmp_path / "out.png"))
    line = one_line_error(code, err, "collinear.obj", "area")
    with pytest.raises(MeshError) as error:
        load_mesh(path)
    assert line == f"wgpu-shading: error: {error.value}"


def test_a_file_with_no_mesh_says_it_has_no_triangles(tmp_path):
    """trimesh's models/empty.ply and emptyIO/ply_empty_bin.ply: the message said
    "expected one mesh, found 0"."""
    (tmp_path / "empty.stl").write_text("solid empty\nendsolid empty\n")
    with pytest.raises(MeshError, match=r"empty.stl': contains no triangles"):
        load_mesh(tmp_path / "empty.stl")
