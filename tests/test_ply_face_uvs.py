"""PLY meshes (binary and ASCII) whose faces carry a `texcoord` list (MeshLab's and Agisoft
Metashape's textured exports), read a block of faces at a time (assets/mesh_formats/ply_face_uvs.py)
against trimesh's reading of the same file: the same corners (position and uv) and as many
vertices, each vertex split by its corners' uvs; without seams the very same arrays. Every
file is written here."""

from __future__ import annotations

import logging
import tracemalloc
import warnings

import numpy as np
import pytest

from wgpu_shading import MeshError, load_mesh
from wgpu_shading.assets.mesh_formats import ply, ply_face_uvs
from wgpu_shading.assets.mesh_formats.ply_header import read_ply_header


def _write(path, side: int = 12, seam_every: int = 3, order: str = "<", uv_type: str = "float", quality: bool = False,
           unused: int = 0, normals: bool = False, quads: bool = False, bad: str | None = None, ascii: bool = False,
           colors: str = "", face_scalars: tuple = ()):
    """A wavy grid of side² vertices (and `unused` more no face uses), its triangles in a
    shuffled order, each corner's uv its vertex's, except along every seam_every-th column,
    where the left corners take a second uv (a seam: one position, two uvs). normals: each
    vertex's (not the surface's: a reader that keeps them is seen to); colors: "rgb" or
    "rgba", uchar channels; face_scalars: (name, PLY type) properties after the texcoords."""
    rng = np.random.default_rng(side + seam_every + len(order) + len(uv_type) + unused)
    u, v = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    positions = np.stack([u, v, 0.1 * np.sin(5 * u)], -1).reshape(-1, 3).astype(np.float32)
    positions = np.concatenate([positions, rng.normal(size=(unused, 3)).astype(np.float32)])
    grid = np.arange(side * side).reshape(side, side)
    own, second = rng.random((len(positions), 2)), rng.random((len(positions), 2))
    faces, uvs = [], []
    for row in range(side - 1):
        for column in range(side - 1):
            a, b, c, d = grid[row, column], grid[row, column + 1], grid[row + 1, column], grid[row + 1, column + 1]
            polygons = [(a, b, d, c)] if quads else [(a, b, d), (a, d, c)]
            for polygon in polygons:
                faces.append(polygon)
                uvs.append([second[k] if column % seam_every == 0 and k in (a, c) else own[k] for k in polygon])
    faces, uvs = np.array(faces), np.array(uvs).reshape(len(faces), -1)
    shuffled = rng.permutation(len(faces))
    faces, uvs = faces[shuffled], uvs[shuffled]
    properties = [("x", "f4"), ("y", "f4"), ("z", "f4")] + [("quality", "f4")] * quality + [("nx", "f4"), ("ny", "f4"), ("nz", "f4")] * normals
    properties += [(channel, "u1") for channel in ("red", "green", "blue", "alpha")[: len(colors)]]
    vertices = np.zeros(len(positions), np.dtype([(name, order + kind) for name, kind in properties]))
    for column, axis in enumerate("xyz"):
        vertices[axis] = positions[:, column]
    if normals:
        for column, axis in enumerate(("nx", "ny", "nz")):
            vertices[axis] = positions[:, column] * 2 + 0.5
    for channel in ("red", "green", "blue", "alpha")[: len(colors)]:
        vertices[channel] = rng.integers(0, 256, len(positions))
    corners = faces.shape[1]
    uv_kind = "<f4" if uv_type == "float" else "<f8"
    scalar_types = {"int": "i4", "float": "f4", "uchar": "u1"}
    records = np.zeros(len(faces), np.dtype([("n", "u1"), ("i", order + "i4", (corners,)), ("m", "u1"), ("uv", order + uv_kind[1:], (2 * corners,))]
                                            + [(name, order + scalar_types[kind]) for name, kind in face_scalars]))
    records["n"], records["i"], records["m"], records["uv"] = corners, faces, 2 * corners, uvs
    for name, _ in face_scalars:
        records[name] = rng.integers(0, 100, len(faces))
    if bad == "index":
        records["i"][3, 1] = len(positions) + 2
    elif bad == "nan":
        records["uv"][5, 0] = np.nan
    encoding = "ascii" if ascii else "binary_little_endian" if order == "<" else "binary_big_endian"
    header = (f"ply\nformat {encoding} 1.0\ncomment TextureFile grid.png\n"
              f"element vertex {len(positions)}\n" + "".join(f"property {'float' if kind == 'f4' else 'uchar'} {name}\n" for name, kind in properties)
              + f"element face {len(faces)}\nproperty list uchar int vertex_indices\nproperty list uchar {uv_type} texcoord\n"
              + "".join(f"property {kind} {name}\n" for name, kind in face_scalars) + "end_header\n")
    with open(path, "wb") as file:
        file.write(header.encode())
        if ascii:  # every value as a C float prints it (%.9g: float32 round-trips), a record a line
            file.write("".join(" ".join("%.9g" % value for value in row) + "\n" for row in vertices.tolist()).encode())
            file.write("".join("%d %s %d %s%s\n" % (n, " ".join(map(str, i)), m, " ".join("%.9g" % x for x in uv), "".join(f" {x}" for x in more))
                               for n, i, m, uv, *more in records.tolist()).encode())
        else:
            vertices.tofile(file)
            records.tofile(file)
    return path


def _read(path, through_trimesh: bool, monkeypatch):
    with monkeypatch.context() as patched, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        logging.disable(logging.CRITICAL)  # trimesh logs that it cannot find the TextureFile
        try:
            if through_trimesh:
                patched.setattr(ply, "read_face_uvs", lambda *arguments: None)
            return load_mesh(path)
        finally:
            logging.disable(logging.NOTSET)


def _corners(mesh) -> list:
    """Every triangle's corners as (position, normal, uv) rows, sorted: what a render draws,
    whatever the vertex order."""
    corners = mesh.indices.reshape(-1, 3)
    rows = np.concatenate([mesh.world_positions()[corners], mesh.normals[corners], mesh.uvs[corners].astype(np.float64)], axis=2)
    rows = rows.reshape(len(corners), -1)
    return sorted(map(tuple, np.round(rows, 6).tolist()))


@pytest.mark.parametrize("options", [{}, {"order": ">"}, {"uv_type": "double"}, {"quality": True}, {"unused": 5}, {"side": 40, "seam_every": 7},
                                     {"ascii": True}, {"ascii": True, "uv_type": "double", "quality": True}])
def test_corners_and_vertex_counts_are_trimeshs(tmp_path, monkeypatch, options):
    path = _write(tmp_path / "uvs.ply", **options)
    ours, theirs = _read(path, False, monkeypatch), _read(path, True, monkeypatch)
    side = options.get("side", 12)
    assert len(ours.positions) == len(theirs.positions) > side * side  # split at the seams; unused vertices left out
    assert _corners(ours) == _corners(theirs)


@pytest.mark.parametrize("ascii", [False, True])
def test_without_seams_the_arrays_are_trimeshs(tmp_path, monkeypatch, ascii):
    path = _write(tmp_path / "smooth.ply", side=20, seam_every=1000, ascii=ascii)
    ours, theirs = _read(path, False, monkeypatch), _read(path, True, monkeypatch)
    for name in ("positions", "indices", "normals", "uvs"):
        np.testing.assert_array_equal(getattr(ours, name), getattr(theirs, name), err_msg=name)


def test_this_reader_reads_them_and_leaves_the_rest_to_trimesh(tmp_path):
    from wgpu_shading.assets.mesh_formats.ply_header import read_ply_header

    def taken(path) -> bool:
        header = read_ply_header(path, "test")
        return ply_face_uvs.read_face_uvs(path, header, path.stat().st_size, "test") is not None

    assert taken(_write(tmp_path / "plain.ply")) and taken(_write(tmp_path / "ascii.ply", ascii=True))
    assert not taken(_write(tmp_path / "ascii_quads.ply", ascii=True, quads=True))
    assert taken(_write(tmp_path / "normals.ply", normals=True, colors="rgb"))  # (kept: test_normals_and_colours_...)
    assert taken(_write(tmp_path / "texnumber.ply", face_scalars=(("texnumber", "int"), ("quality", "float"))))
    assert taken(_write(tmp_path / "ascii_texnumber.ply", ascii=True, face_scalars=(("texnumber", "int"), ("quality", "float"))))
    colours = (("red", "uchar"), ("green", "uchar"), ("blue", "uchar"))
    assert taken(_write(tmp_path / "face_colours.ply", face_scalars=colours))  # (test_face_colours_...)
    assert not taken(_write(tmp_path / "ascii_face_colours.ply", ascii=True, face_scalars=colours))  # (to trimesh)
    assert not taken(_write(tmp_path / "quads.ply", quads=True))  # trimesh ignores quads' texcoords
    assert not taken(_write(tmp_path / "nan.ply", bad="nan"))
    assert not taken(_write(tmp_path / "index.ply", bad="index"))


@pytest.mark.parametrize("ascii", [False, True])
@pytest.mark.parametrize("bad, words", [("index", "refers to a vertex that does not exist"), ("nan", "NaN or infinite")])
def test_bad_files_are_the_errors_they_were(tmp_path, bad, words, ascii):
    with pytest.raises(MeshError, match=words):
        load_mesh(_write(tmp_path / "bad.ply", bad=bad, ascii=ascii))


def test_reading_holds_a_few_times_the_arrays(tmp_path, monkeypatch):
    """tracemalloc's peak while reading a 60K-triangle file in blocks of 4096 faces: within
    3.5x the piece's arrays (2.7x here; trimesh's reading: 13.5x at 2M triangles, by RSS)."""
    from wgpu_shading.assets.mesh_formats import ply_triangles
    from wgpu_shading.assets.mesh_formats.ply_header import read_ply_header

    path = _write(tmp_path / "big.ply", side=175, seam_every=9)
    header = read_ply_header(path, "test")
    monkeypatch.setattr(ply_face_uvs, "BLOCK_ROWS", 4096)
    tracemalloc.start()
    try:
        piece = ply_face_uvs.read_face_uvs(path, header, path.stat().st_size, "test")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    arrays = sum(array.nbytes for array in (piece.positions, piece.faces, piece.uvs))
    assert ply_triangles.BLOCK_ROWS > 4096 and peak < 3.5 * arrays, peak / arrays


@pytest.mark.parametrize("options", [{}, {"ascii": True}, {"order": ">", "colors": "rgba"}, {"ascii": True, "colors": "rgba"},
                                     {"face_scalars": (("texnumber", "int"), ("flags", "int"))},
                                     {"ascii": True, "face_scalars": (("texnumber", "int"), ("quality", "float"))}])
def test_normals_and_colours_beside_texcoords_are_each_vertexs_own(tmp_path, monkeypatch, options):
    """Agisoft Metashape and MeshLab write a textured mesh's normals and colours per vertex
    beside the faces' texcoords (and Metashape a `texnumber` after them). trimesh drops them
    once it splits vertices at the seams (and held 13.9x the arrays at 2M triangles): here
    every vertex of the split keeps its file vertex's normal and colour, as VTK's reader
    (f3d's) does; the corners (position and uv) and the vertex count are still trimesh's."""
    options = {"normals": True, "colors": "rgb", **options}
    path = _write(tmp_path / "scan.ply", **options)
    ours, theirs = _read(path, False, monkeypatch), _read(path, True, monkeypatch)
    assert len(ours.positions) == len(theirs.positions) > 12 * 12

    def corners(mesh) -> list:
        rows = np.concatenate([mesh.world_positions(), mesh.uvs.astype(np.float64)], axis=1)[mesh.indices.reshape(-1, 3)]
        return sorted(map(tuple, np.round(rows.reshape(len(rows), -1), 6).tolist()))

    assert corners(ours) == corners(theirs)
    file = np.fromfile(path, np.uint8)  # the written vertices, through their positions (distinct on the grid)
    header = read_ply_header(path, "test")
    vertex_row = np.dtype([(name, (">" if header.format == "binary_big_endian" else "<") + ("f4" if kind == "float" else "u1"))
                           for name, kind, _ in header.elements[0].properties])
    if header.format == "ascii":
        lines = path.read_text().split("end_header\n")[1].splitlines()[: header.count("vertex")]
        written = np.array([tuple(float(word) for word in line.split()) for line in lines], vertex_row)
    else:
        written = np.frombuffer(file[header.header_bytes :].tobytes(), vertex_row, header.count("vertex"))
    position_keys = {tuple(row): index for index, row in enumerate(np.round(np.stack([written[a] for a in "xyz"], 1).astype(np.float64), 6).tolist())}
    source = np.array([position_keys[tuple(row)] for row in np.round(ours.world_positions(), 6).tolist()])
    expected_normals = np.stack([written[a] for a in ("nx", "ny", "nz")], 1).astype(np.float64)[source]
    expected_normals /= np.linalg.norm(expected_normals, axis=1, keepdims=True)  # (a Mesh keeps unit normals)
    np.testing.assert_allclose(ours.normals, expected_normals, atol=1e-6)  # the file's own, not the faces'
    channels = [name for name in ("red", "green", "blue", "alpha") if name in written.dtype.names]
    expected_colors = np.stack([written[name] for name in channels], 1)[source]
    np.testing.assert_array_equal(np.round(ours.colors[:, : len(channels)] * 255).astype(np.uint8), expected_colors)


def test_unused_vertices_beside_texcoords_are_not_called_truncated(tmp_path, monkeypatch):
    """A file with normals beside its face texcoords (read by trimesh until issue #29's
    twenty-third pass, which splits vertices by their uvs and leaves out those no face uses:
    fewer vertices than the header declares, which the check for truncated files took for a
    file cut short)."""
    path = _write(tmp_path / "unused.ply", normals=True, unused=4, seam_every=1000)  # (no seams: no vertex more)
    mesh = _read(path, False, monkeypatch)
    assert len(mesh.positions) == 12 * 12 and mesh.triangle_count == 2 * 11 * 11


@pytest.mark.parametrize("vertex_colours", ["", "rgb"])
def test_face_colours_beside_texcoords_are_trimeshs(tmp_path, monkeypatch, vertex_colours):
    """VCGLIB writes a face's colour after its texcoords: every corner its own vertex with its
    face's colour and its uv, as trimesh gives them (also where the vertices have colours,
    as trimesh draws them once it has split the vertices at their seams)."""
    colours = (("red", "uchar"), ("green", "uchar"), ("blue", "uchar"), ("alpha", "uchar"))
    path = _write(tmp_path / "coloured.ply", face_scalars=(("flags", "int"),) + colours, colors=vertex_colours)
    ours, theirs = _read(path, False, monkeypatch), _read(path, True, monkeypatch)
    assert len(ours.positions) == len(theirs.positions) == 3 * ours.triangle_count

    def corners(mesh) -> list:
        rows = np.concatenate([mesh.world_positions(), mesh.uvs.astype(np.float64), mesh.colors.astype(np.float64)], axis=1)
        return sorted(map(tuple, np.round(rows[mesh.indices.reshape(-1, 3)].reshape(mesh.triangle_count, -1), 6).tolist()))

    assert corners(ours) == corners(theirs)
