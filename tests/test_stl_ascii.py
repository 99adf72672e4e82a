"""ASCII STL in the plain layout is read a block of lines at a time
(assets/mesh_formats/stl_ascii.py): the same arrays as trimesh's reading, which every
other layout still goes to (docs/performance.md, "Loading a large mesh")."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import load_mesh
from wgpu_shading.assets import files
from wgpu_shading.assets.mesh_formats import stl_ascii
from wgpu_shading.assets.mesh_formats.stl_ascii import read_plain_ascii_stl
from wgpu_shading.assets.mesh_formats.trimesh_reader import read_with_trimesh
from wgpu_shading.errors import MeshError

CORPUS = Path(__file__).parents[2] / "shared" / "corpora" / "realworld2" / "stl"


def _facets(count: int, seed: int = 1) -> np.ndarray:
    """(count, 4, 3): a normal, then three corners, some of them shared between facets."""
    rng = np.random.default_rng(seed)
    pool = rng.normal(size=(max(count, 3), 3))
    pool[0] = [-0.0, 0.0, -0.0]
    corners = pool[rng.integers(0, len(pool), (count, 3))]
    normals = rng.normal(size=(count, 1, 3))
    return np.concatenate([normals, corners], axis=1)


def _text(facets: np.ndarray, number: str = "{:e}", indent: tuple[str, str, str] = ("  ", "    ", "      "),
          newline: str = "\n", name: str = "part") -> str:
    out = [f"solid {name}{newline}"]
    for normal, *corners in facets:
        out.append(f"{indent[0]}facet normal {' '.join(number.format(float(v)) for v in normal)}{newline}{indent[1]}outer loop{newline}")
        out += [f"{indent[2]}vertex {' '.join(number.format(float(v)) for v in corner)}{newline}" for corner in corners]
        out.append(f"{indent[1]}endloop{newline}{indent[0]}endfacet{newline}")
    out.append(f"endsolid {name}{newline}")
    return "".join(out)


def _assert_trimesh_triangles(path: Path) -> None:
    """The file's triangles corner by corner as trimesh reads them (float64, -0.0 as 0.0),
    on distinct vertices: equal corners joined."""
    piece = read_plain_ascii_stl(path, "m")
    assert piece is not None
    expected = read_with_trimesh(path, path.stat().st_size).pieces[0]
    assert piece.positions.dtype == expected.positions.dtype == np.float64
    corners = piece.positions[piece.faces.reshape(-1)]
    expected_corners = expected.positions[expected.faces.reshape(-1)] + 0.0
    assert corners.tobytes() == expected_corners.tobytes()  # bit for bit
    assert len(np.unique(piece.positions, axis=0)) == len(piece.positions)
    assert piece.parts == expected.parts and piece.normals is None and expected.normals is None


STYLES = {
    "Blender (no indent, %f)": dict(number="{:f}", indent=("", "", "")),
    "OpenSCAD (indented, CR LF, %g)": dict(number="{:g}", newline="\r\n"),
    "exponents": dict(number="{:.9e}"),
    "tabs": dict(indent=("\t", "\t\t", "\t\t\t")),
    "long digits (strtod's reading)": dict(number="{!r}"),
}


@pytest.mark.parametrize("style", STYLES)
@pytest.mark.parametrize("block", [(2, 7), (333, 4096), (4 << 20, 16 << 20)])
def test_the_plain_layout_gives_trimesh_triangles_in_blocks_of_any_size(tmp_path, monkeypatch, style, block):
    monkeypatch.setattr(stl_ascii, "BLOCK_BYTES", block[0])
    monkeypatch.setattr(stl_ascii, "JOIN_CORNERS", 30)  # 40 facets: four joins
    monkeypatch.setattr(files, "TEXT_CHUNK", block[1])
    path = tmp_path / "part.stl"
    path.write_bytes(_text(_facets(40), **STYLES[style]).encode())
    _assert_trimesh_triangles(path)


@pytest.mark.parametrize("name", ["Channel9_blender_ascii.stl", "gears_openscad_ascii.stl"])
def test_ascii_files_exporters_wrote_give_trimesh_triangles(name):
    path = CORPUS / name
    if not path.exists():
        pytest.skip(f"{path} is not here (../shared)")
    _assert_trimesh_triangles(path)


def test_a_solid_named_with_keywords_is_read(tmp_path):
    """trimesh splits the whole text at every "vertex", the name's too, and could not read
    this file ("string or file could not be read to its end"); the name is one line here."""
    facets = _facets(4)
    (tmp_path / "plain.stl").write_text(_text(facets))
    (tmp_path / "named.stl").write_text(_text(facets, name="vertex endfacet outer loop 1 2"))
    plain, named = (read_plain_ascii_stl(tmp_path / name, "m") for name in ("plain.stl", "named.stl"))
    assert named.positions.tobytes() == plain.positions.tobytes()
    assert load_mesh(tmp_path / "named.stl").triangle_count == 4


def test_the_end_of_the_file_may_lack_a_newline_or_have_blank_lines(tmp_path):
    facets = _facets(5)
    for ending in ("", "\n\n", "\n  \n\n"):
        path = tmp_path / "end.stl"
        path.write_text(_text(facets).rstrip("\n") + ending)
        _assert_trimesh_triangles(path)


def _moved_number(text: str) -> str:
    """The first normal's last number moved to the end of the first vertex line: twelve
    numbers a facet still, in the wrong places."""
    lines = text.split("\n")
    *head, moved = lines[1].split(" ")
    lines[1], lines[3] = " ".join(head), lines[3] + " " + moved
    return "\n".join(lines)


OTHER_LAYOUTS = {
    "two solids": lambda t: t + t,
    "upper case": lambda t: t.upper(),
    "a blank line": lambda t: t.replace("endloop\n", "endloop\n\n", 1),
    "four vertices": lambda t: t.replace("      vertex", "      vertex 0 0 0\n      vertex", 1),
    "four numbers to a vertex": lambda t: t.replace("vertex ", "vertex 7 ", 1),
    "a number moved from the normal to a vertex": lambda t: _moved_number(t),
    "a word for a number": lambda t: t.replace("vertex ", "vertex x", 1),
    "text after endsolid": lambda t: t + "something\n",
    "an indent of 20": lambda t: t.replace("  facet", " " * 20 + "facet", 1),
    "vertexes": lambda t: t.replace("vertex ", "vertexes ", 1),
    "no facet": lambda t: "solid empty\nendsolid empty\n",
}


@pytest.mark.parametrize("layout", OTHER_LAYOUTS)
def test_other_layouts_go_to_trimesh_as_before(tmp_path, layout):
    path = tmp_path / "other.stl"
    path.write_text(OTHER_LAYOUTS[layout](_text(_facets(6), number="{:.1f}")))
    assert read_plain_ascii_stl(path, "m") is None
    try:
        expected = read_with_trimesh(path, path.stat().st_size)
    except Exception as error:  # noqa: BLE001 - trimesh's own error, as load_mesh gives it
        with pytest.raises(type(error)):
            load_mesh(path)
        return
    mesh = load_mesh(path)
    assert mesh.triangle_count == sum(len(piece.faces) for piece in expected.pieces)


def test_a_file_ending_after_a_whole_facet_without_endsolid_is_read_with_a_warning(tmp_path):
    """VTK's reader (f3d's) draws such a file's facets; trimesh found no solid in it."""
    whole = _text(_facets(6), number="{:.1f}")
    (tmp_path / "whole.stl").write_text(whole)
    (tmp_path / "cut.stl").write_text(whole[: whole.rindex("endsolid")])
    with pytest.warns(UserWarning, match=r"cut.stl': no 'endsolid' line at its end \(cut short\?\); the 6 whole facet\(s\)"):
        cut = load_mesh(tmp_path / "cut.stl")
    expected = load_mesh(tmp_path / "whole.stl")
    for name in ("positions", "indices", "normals", "origin"):
        np.testing.assert_array_equal(getattr(cut, name), getattr(expected, name), err_msg=name)
    # Cut inside a facet: refused, saying where (trimesh said "no mesh in the file").
    (tmp_path / "inside.stl").write_text(whole[: whole.rindex("endloop")])
    with pytest.raises(MeshError, match=r"inside.stl': truncated: it ends inside facet 6, after 5 whole ones"):
        load_mesh(tmp_path / "inside.stl")


def test_a_nan_coordinate_is_named_as_before(tmp_path):
    path = tmp_path / "nan.stl"
    path.write_text(_text(_facets(3), number="{:.3f}").replace("vertex ", "vertex nan ", 1).replace(" 0.000", "", 1))
    piece = read_plain_ascii_stl(path, "m")
    assert piece is not None and np.isnan(piece.positions).sum() == 1
    with pytest.raises(Exception, match="NaN or infinite"):
        load_mesh(path)


def test_a_big_ascii_stl_is_read_in_a_fraction_of_trimesh_memory(tmp_path, monkeypatch):
    """tracemalloc's peak of the reading alone, 20,000 facets (2.6 MB of text) in blocks of
    64 KiB (1 MiB scaled to this file): the corners joined and a block's temporaries,
    against trimesh's lower-cased copy of the text, a string a line and every corner a
    vertex. A 2M-triangle file (448 MB), resident, load and render: 243 MB above the
    baseline, against 3.2 GB; 8M triangles (1.8 GB): 605 MB, 3.15x the mesh's arrays."""
    monkeypatch.setattr(stl_ascii, "BLOCK_BYTES", 1 << 16)
    monkeypatch.setattr(files, "TEXT_CHUNK", 1 << 18)
    path = tmp_path / "big.stl"
    path.write_text(_text(_facets(20_000), number="{:.6f}"))
    peaks = []
    for read in (lambda: read_plain_ascii_stl(path, "m"), lambda: read_with_trimesh(path, path.stat().st_size)):
        read()  # (imports outside the measurement)
        tracemalloc.start()
        try:
            read()
            peaks.append(tracemalloc.get_traced_memory()[1])
        finally:
            tracemalloc.stop()
    corners = 20_000 * 3 * 3 * 8  # (every corner as float64: what trimesh keeps)
    assert peaks[0] < 4 * corners and peaks[0] < peaks[1] / 4, [f"{p / corners:.1f}x" for p in peaks]


def test_corners_equal_but_for_the_sign_of_zero_are_one_vertex(tmp_path):
    path = tmp_path / "zeros.stl"
    facets = np.array([[[0, 0, 1], [0.0, 0.0, 0.0], [1, 0, 0], [0, 1, 0]], [[0, 0, 1], [-0.0, 0.0, -0.0], [0, 1, 0], [-1, 0, 0]]])
    path.write_text(_text(facets, number="{}"))
    piece = read_plain_ascii_stl(path, "m")
    assert len(piece.positions) == 4 and piece.faces[0, 0] == piece.faces[1, 0]
    origin = piece.positions[piece.faces[0, 0]]
    assert not origin.any() and not np.signbit(origin).any()  # (0, 0, 0), not (-0, 0, -0)


def test_a_file_of_long_lines_is_not_read_whole_before_it_is_refused(tmp_path, monkeypatch):
    """No line of the plain layout is long: a line past LONGEST_LINE stops the block reading
    (files.LongLine) instead of holding the line, and a file that is not plain is then
    refused beyond MAX_ASCII_BYTES, as before the block reader."""
    from wgpu_shading.assets.mesh_formats import stl
    from wgpu_shading.errors import MeshError

    monkeypatch.setattr(files, "TEXT_CHUNK", 1 << 12)
    monkeypatch.setattr(stl_ascii, "LONGEST_LINE", 1 << 13)
    monkeypatch.setattr(stl, "MAX_ASCII_BYTES", 1 << 16)
    path = tmp_path / "line.stl"
    path.write_bytes(b"solid line\n" + b"1 " * 50_000)
    assert read_plain_ascii_stl(path, "m") is None
    with pytest.raises(MeshError, match="line.stl': an ASCII STL of 0 MiB, not in the plain layout"):
        load_mesh(path)
