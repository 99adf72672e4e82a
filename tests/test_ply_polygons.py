"""PLY meshes of polygons of several sizes (assets/mesh_formats/ply_polygons.py, and
ply_ascii_triangles.py for ASCII ones), as Blender writes them: trimesh's binary reader
refuses them ("PLY is unexpected length!"), so the reference is trimesh's reading of the
same mesh written as ASCII, which it reads whole and cuts into triangles
(trimesh.geometry.triangulate_quads)."""

from __future__ import annotations

import tracemalloc
from pathlib import Path
from unittest import mock

import numpy as np
import pytest

from ply_reference import assert_same_mesh, through_trimesh, vertex_bytes
from wgpu_shading import load_mesh
from wgpu_shading.assets.mesh_formats import ply, ply_polygons, ply_triangles
from wgpu_shading.assets.mesh_formats.ply_header import PLY_TYPES
from wgpu_shading.errors import MeshError

# A square of 3 × 3 vertices (and one more off it), faces of every kind: triangles, quads,
# a pentagon, a hexagon, and a two-corner face (left out, as trimesh leaves it out)
POSITIONS = np.array([[x, y, 0.25 * x * y] for y in range(3) for x in range(3)] + [[3.0, 1.0, 0.5]], np.float32) * 0.37
FACES = [[0, 1, 4, 3], [1, 2, 4], [2, 5, 4], [3, 4, 7, 6], [4, 5, 9, 8, 7], [0, 3], [5, 2, 9], [1, 2, 5, 9, 8, 4]]


def _vertex_columns(normals: bool, colors: bool, uvs: str | None):
    columns = [("x", "float"), ("y", "float"), ("z", "float")]
    columns += [("nx", "float"), ("ny", "float"), ("nz", "float")] if normals else []
    columns += [(uvs[0], "float"), (uvs[1], "float")] if uvs else []
    columns += [("red", "uchar"), ("green", "uchar"), ("blue", "uchar")] if colors else []
    rng = np.random.default_rng(3)
    values = {name: POSITIONS[:, "xyz".index(name)] for name in "xyz"}
    unit = POSITIONS / np.maximum(np.linalg.norm(POSITIONS, axis=1, keepdims=True), 1e-6)
    values |= {name: unit[:, k] for k, name in enumerate(("nx", "ny", "nz"))}
    values |= {name: rng.random(len(POSITIONS)).astype(np.float32) for name in (uvs or ())}
    values |= {name: rng.integers(0, 256, len(POSITIONS)) for name in ("red", "green", "blue")}
    return columns, values


def write_mesh(path: Path, *, ascii=False, order="<", count="uchar", index="int", normals=False, colors=False,
               uvs: str | None = None, faces=FACES, counts=None, tail=b"") -> Path:
    """The square's mesh as a PLY (binary, or ASCII with every float written exactly)."""
    columns, values = _vertex_columns(normals, colors, uvs)
    header = (f"ply\nformat {'ascii' if ascii else 'binary_little_endian' if order == '<' else 'binary_big_endian'} 1.0\n"
              f"comment Created by Blender\nelement vertex {len(POSITIONS)}\n"
              + "".join(f"property {kind} {name}\n" for name, kind in columns)
              + f"element face {len(faces)}\nproperty list {count} {index} vertex_indices\nend_header\n")
    if ascii:
        rows = [" ".join(repr(float(values[name][i])) if kind == "float" else str(int(values[name][i])) for name, kind in columns)
                for i in range(len(POSITIONS))]
        body = ("\n".join(rows + [" ".join(map(str, [len(face), *face])) for face in faces]) + "\n").encode()
    else:
        body = vertex_bytes(columns, values, len(POSITIONS), order)
        for number, face in enumerate(faces):
            body += np.array(len(face) if counts is None else counts[number], order + PLY_TYPES[count]).tobytes()
            body += np.array(face, order + PLY_TYPES[index]).tobytes()
    path.parent.mkdir(exist_ok=True)
    path.write_bytes(header.encode() + bytes(body) + tail)
    return path


LAYOUTS = {
    "little-endian": {},
    "big-endian, normals": {"order": ">", "normals": True},
    "RGB, int counts, uint indices": {"colors": True, "count": "int", "index": "uint"},
    "ushort counts and indices": {"count": "ushort", "index": "ushort"},
    "Blender's s and t": {"uvs": ("s", "t"), "normals": True},
    "texture_u and texture_v, big-endian": {"uvs": ("texture_u", "texture_v"), "order": ">"},
}


@pytest.mark.parametrize("block_bytes", [5, 64, 8 << 20])
@pytest.mark.parametrize("options", LAYOUTS.values(), ids=LAYOUTS.keys())
def test_mixed_polygons_give_trimeshs_mesh_of_the_same_file_in_ascii(tmp_path, monkeypatch, options, block_bytes):
    monkeypatch.setattr(ply_polygons, "BLOCK_BYTES", block_bytes)  # records cut across blocks
    binary = write_mesh(tmp_path / "mesh.ply", **options)
    with pytest.raises(MeshError, match="unexpected length"):  # what users got before
        through_trimesh(binary)
    expected = through_trimesh(write_mesh(tmp_path / "ascii" / "mesh.ply", ascii=True, **options))  # (the same name: the part's)
    mesh = load_mesh(binary)
    assert_same_mesh(mesh, expected)
    assert mesh.triangle_count == 3 + 2 * 2 + 3 + 4  # three triangles, two quads, a pentagon and a hexagon
    if "uvs" in options and options.get("normals"):  # (the file's normals: no vertex split, the file's order)
        columns, values = _vertex_columns(False, False, options["uvs"])
        np.testing.assert_array_equal(mesh.uvs, np.stack([values[name] for name in options["uvs"]], 1))


@pytest.mark.parametrize("faces", [
    [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7], [2, 9, 8, 5]],
    [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7], [5, 9, 8]],
], ids=["quads", "triangles"])
def test_faces_of_one_size_with_texture_coordinates_give_trimeshs_mesh(tmp_path, faces):
    """Texture coordinates sent a binary PLY to trimesh: now they are read here (the same mesh)."""
    path = write_mesh(tmp_path / "mesh.ply", uvs=("u", "v"), faces=faces)
    assert_same_mesh(load_mesh(path), through_trimesh(path))


@pytest.mark.parametrize("options, message", [
    ({"tail": b"\0\0\0"}, "bytes after its 8 faces"),
    ({"faces": FACES + [[0, 1, 2]], "tail": b""}, None),  # (the same mesh, one more face declared: written below)
], ids=["bytes after the faces", "file ends inside a face"])
def test_a_file_of_the_wrong_length_is_refused_naming_why(tmp_path, options, message):
    path = write_mesh(tmp_path / "mesh.ply", **options)
    if message is None:  # cut inside the last face's indices
        path.write_bytes(path.read_bytes()[:-6])
        message = "ends inside its faces"
    with pytest.raises(MeshError, match=message):
        load_mesh(path)


def test_counts_out_of_range_are_refused_from_the_count(tmp_path, monkeypatch):
    negative = write_mesh(tmp_path / "negative.ply", count="char", counts=[4, 3, 3, 4, 5, 2, 3, -6])
    with pytest.raises(MeshError, match="face 7 has a negative corner count"):
        load_mesh(negative)
    monkeypatch.setattr(ply_polygons, "MAX_TRIANGLES", 13)  # before any array is made
    with pytest.raises(MeshError, match="its 8 faces make 14 triangles; at most 13 are supported"):
        load_mesh(write_mesh(tmp_path / "many.ply"))
    monkeypatch.setattr(ply_polygons, "MAX_FACE_CORNERS", 5)
    with pytest.raises(MeshError, match="face 7 has 6 corners; at most 5 are supported"):
        load_mesh(write_mesh(tmp_path / "big.ply"))


def test_reading_a_big_mesh_of_mixed_polygons_takes_little_more_than_its_arrays(tmp_path, monkeypatch):
    """A grid of quads with every seventh as two triangles, read in blocks of 64 KiB: the
    peak is the arrays kept and one block's records (faces of one size, ply_triangles.py's
    bound: 1.25x). trimesh could not read it at all."""
    side = 300
    grid = np.arange(side * side).reshape(side, side)
    quads = np.stack([grid[:-1, :-1], grid[:-1, 1:], grid[1:, 1:], grid[1:, :-1]], -1).reshape(-1, 4)
    positions = np.stack([*np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side)), np.zeros((side, side))], -1)
    positions = positions.reshape(-1, 3).astype("<f4")
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(positions)}\nproperty float x\nproperty float y\n"
              f"property float z\nelement face {len(quads) + len(quads[::7])}\nproperty list uchar uint vertex_indices\nend_header\n")
    body = bytearray(positions.tobytes())
    quad_row, triangle_row = np.dtype([("n", "u1"), ("c", "<u4", (4,))]), np.dtype([("n", "u1"), ("c", "<u4", (3,))])
    for number, quad in enumerate(quads):
        if number % 7:
            body += np.array((4, quad), quad_row).tobytes()
        else:
            body += np.array([(3, quad[:3]), (3, quad[[0, 2, 3]])], triangle_row).tobytes()
    path = tmp_path / "grid.ply"
    path.write_bytes(header.encode() + bytes(body))
    monkeypatch.setattr(ply_polygons, "BLOCK_BYTES", 1 << 16)
    monkeypatch.setattr(ply_triangles, "BLOCK_ROWS", 1 << 14)  # (the vertices' blocks, as in tests/test_ply_triangles.py)
    tracemalloc.start()
    try:
        piece = ply.read_ply(path, path.stat().st_size).pieces[0]
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    arrays = piece.positions.nbytes + piece.faces.nbytes
    assert len(piece.faces) == 2 * len(quads)
    assert peak < 1.25 * arrays, f"peak {peak / arrays:.2f}x the arrays"


@pytest.mark.parametrize("block_bytes", [2, 40, 1 << 22])
@pytest.mark.parametrize("faces", [FACES, [[0, 3], *FACES], [FACES[1]] * 3 + FACES], ids=["mixed", "a two-corner face first", "triangles first"])
def test_ascii_mixed_polygons_are_read_in_blocks_of_lines_as_trimesh_reads_them(tmp_path, monkeypatch, faces, block_bytes):
    """Two passes over the lines: the faces' kinds counted, then cut (trimesh held the
    whole text: a 2M-triangle ASCII PLY of mixed polygons peaked at 22x its arrays)."""
    from wgpu_shading.assets import files
    from wgpu_shading.assets.mesh_formats import ply_ascii_triangles
    from wgpu_shading.assets.mesh_formats.ply_header import read_ply_header

    path = write_mesh(tmp_path / "ascii.ply", ascii=True, normals=True, colors=True, faces=faces)
    monkeypatch.setattr(files, "TEXT_BLOCK_BYTES", block_bytes)
    assert ply_ascii_triangles.read_ascii_triangles(path, read_ply_header(path, "mesh"), "mesh") is not None
    assert_same_mesh(load_mesh(path), through_trimesh(path))


def test_ascii_faces_whose_lines_do_not_hold_their_counts_go_to_trimesh(tmp_path):
    from wgpu_shading.assets.mesh_formats import ply_ascii_triangles
    from wgpu_shading.assets.mesh_formats.ply_header import read_ply_header

    path = write_mesh(tmp_path / "ascii.ply", ascii=True)
    text = path.read_text().replace("\n4 0 1 4 3\n", "\n4 0 1 4\n3\n")  # a face cut over two lines
    path.write_text(text)
    assert ply_ascii_triangles.read_ascii_triangles(path, read_ply_header(path, "mesh"), "mesh") is None
