"""OFF read as a token stream (assets/mesh_formats/off.py): faces over several lines (libigl's writer),
the header forms real tools write (two counts, counts on or glued to the keyword's line),
comments, face colours, COFF/NOFF vertices, bad files."""

from __future__ import annotations

import warnings

from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import MeshError, load_mesh

SQUARE = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
REAL = Path(__file__).parent / "data" / "real"


def _load(tmp_path, text: str, name: str = "m.off"):
    path = tmp_path / name
    path.write_text(text)
    return load_mesh(path)


def test_a_face_spread_over_several_lines_is_one_face(tmp_path):
    # libigl breaks long faces over lines: "4" on one line, the indices on the next ones.
    mesh = _load(tmp_path, "OFF\n4 1 0\n" + SQUARE + "4\n0 1\n2 3\n")
    assert mesh.triangle_count == 2
    assert np.isclose(np.ptp(mesh.world_positions(), axis=0)[:2], 1.0).all()


def test_counts_on_the_keyword_line_comments_and_face_colours(tmp_path):
    text = "OFF 4 2 0 # counts here\n# a comment line\n" + SQUARE + "3 0 1 2 255 0 0\n3 0 2 3 0.5 0.5 0.5 1\n"
    mesh = _load(tmp_path, text)
    assert mesh.triangle_count == 2


def test_a_whole_file_on_one_line_is_read(tmp_path):
    mesh = _load(tmp_path, "OFF 3 1 0 0 0 0 1 0 0 0 1 0 3 0 1 2")
    assert mesh.triangle_count == 1


def test_coff_vertex_colours_and_noff_normals(tmp_path):
    text = "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n"
    mesh = _load(tmp_path, text, "c.off")
    assert mesh.colors is not None and np.allclose(sorted(map(tuple, mesh.colors[:, :3].round(3))), [(0, 0, 1), (0, 1, 0), (1, 0, 0)])
    text = "NOFF\n3 1 0\n0 0 0 0 0 -1\n1 0 0 0 0 -1\n0 1 0 0 0 -1\n3 0 1 2\n"
    assert np.allclose(_load(tmp_path, text, "n.off").normals, [0, 0, -1])


def test_two_counts_without_an_edge_count_as_online3dviewer_writes_them():
    # Issue 27's regression: "4 1" (no edge count) failed with "edge count: expected an
    # integer, got '0.0'" once OFF was read as a token stream. Both files from the viewer's
    # test set, with the colours they carry (Online3DViewer shows them; f3d shows grey).
    faces = load_mesh(REAL / "rectangle_face_colors_int.off")  # "4 0 1 2 3 255 0 0"
    assert faces.triangle_count == 2
    np.testing.assert_allclose(np.ptp(faces.world_positions(), axis=0), [1, 1, 0])
    np.testing.assert_allclose(faces.colors, [[1, 0, 0, 1]] * len(faces.colors))
    vertices = load_mesh(REAL / "rectangle_vertex_colors_float.off")  # "x y z r g b" in a plain OFF
    assert vertices.triangle_count == 2
    by_position = {tuple(p): tuple(c) for p, c in zip(vertices.world_positions().round(6), vertices.colors)}
    assert by_position == {(0, 0, 0): (1, 0, 0, 1), (1, 0, 0): (0, 1, 0, 1), (1, 1, 0): (0, 0, 1, 1), (0, 1, 0): (1, 0, 0, 1)}


def test_trimeshs_whitespace_file_with_its_count_glued_to_the_keyword():
    # trimesh's models/whitespace.off: "\t<71 spaces>OFF8 6 12 # or nah", six quads with RGBA
    # colours: an octahedron-like box of 8 vertices (±1.632993 in x/y, ±1.154701 in z)
    mesh = load_mesh(REAL / "whitespace.off")
    assert mesh.triangle_count == 12
    np.testing.assert_allclose(np.abs(mesh.world_positions()).max(axis=0), [1.632993, 1.632993, 1.154701], atol=1e-6)
    assert (1.0, 0.0, 0.0, 0.75) in set(map(tuple, mesh.colors.round(6)))


@pytest.mark.parametrize("header", [
    "OFF\n4 2\n",  # two counts (Online3DViewer's test files, many scripts)
    "OFF\n4 2 5\n",  # three counts: the edge count is ignored, as by every reader
    "OFF 4 2\n",  # counts on the keyword's line
    "OFF4 2 0\n",  # counts glued to the keyword (how ModelNet's files are written)
    "# written by hand\nOFF\n# counts next\n\n4 2\n",  # comments and blank lines around
    "OFF\n4\n2\n",  # one count per line
])
def test_header_forms_real_tools_write(tmp_path, header):
    # Integer coordinates: "0" right after two counts must not be taken for an edge count.
    mesh = _load(tmp_path, header + SQUARE + "3 0 1 2\n3 0 2 3\n")
    assert mesh.triangle_count == 2
    np.testing.assert_allclose(np.sort(mesh.world_positions(), axis=0)[[0, -1]], [[0, 0, 0], [1, 1, 0]])


def test_face_colours_rgba_floats_and_faces_without_one(tmp_path):
    text = "OFF\n4 2\n" + SQUARE + "3 0 1 2 0 0.5 1 1\n3 0 2 3\n"
    mesh = _load(tmp_path, text)
    assert sorted(map(tuple, mesh.colors.round(3))) == [(0, 0.5, 1, 1)] * 3 + [(1, 1, 1, 1)] * 3


@pytest.mark.parametrize("text, words", [
    ("OFF\n-4 1\n" + SQUARE + "3 0 1 2\n", "vertex count: expected a count, got -4"),
    ("OFF\n4\n", "truncated: the file ends in its header"),
    ("OFF\n4 1 x\n" + SQUARE + "3 0 1 2\n", "line 2: edge count: expected an integer, got 'x'"),
    ("OFF\n4 1\n" + SQUARE + "3 0 1 2 red 0 0\n", "face colour is not a number"),
    ("OFF\n4 1 0\n" + SQUARE + "4 0 1\n", "truncated"),
    ("OFF\n3 1 0\n0 0 0\n1 0 0\n", "truncated"),
    ("OFF\n4 1 0\n" + SQUARE + "3 0 1 9\n", "vertex 9"),
    ("OFF\n4 1 0\n" + SQUARE + "3 0 x 2\n", "integer"),
    ("PLY\n", "not an OFF file"),
])
def test_bad_off_files_are_one_line_errors(tmp_path, text, words):
    with pytest.raises(MeshError, match=words):
        _load(tmp_path, text)


def test_usemtl_without_any_mtllib_is_a_warning(tmp_path):
    path = tmp_path / "plain.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n")
    with pytest.warns(UserWarning, match="usemtl red.*no material library"):
        load_mesh(path)
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_mesh(path)


@pytest.mark.parametrize("corners", [3, 4, 6])
def test_equal_polygons_read_in_one_split_as_the_line_aware_reader_reads_them(tmp_path, corners):
    """A file of equal polygons without colours or comments takes the one-split path; the
    same file with a comment takes the line-aware one: the same vertices (exponents among
    them) and the same fans, in order."""
    from wgpu_shading.assets.mesh_formats.off import read_off

    rng = np.random.default_rng(corners)
    count = 40
    positions = rng.normal(size=(count, 3)) * np.where(rng.random((count, 1)) < 0.3, 1e-6, 1.0)
    lines = [" ".join(f"{value:g}" for value in row) for row in positions]  # %g: exponents for the small ones
    faces = [" ".join(str(i) for i in [corners, *rng.choice(count, corners, replace=False)]) for _ in range(25)]
    body = f"{count} {len(faces)} 0\n" + "\n".join(lines + faces) + "\n"
    split = tmp_path / "split.off"
    split.write_text("OFF\n" + body)
    careful = tmp_path / "careful.off"
    careful.write_text("OFF # a comment: the line-aware reader\n" + body)
    one, other = read_off(split, split.stat().st_size).pieces[0], read_off(careful, careful.stat().st_size).pieces[0]
    assert np.array_equal(one.positions, other.positions) and np.array_equal(one.faces, other.faces)
    assert np.array_equal(one.positions, [[float(word) for word in line.split()] for line in lines])
    assert len(one.faces) == 25 * (corners - 2)


@pytest.mark.parametrize("corners", [3, 4])
@pytest.mark.parametrize("ending, trailer", [("\n", ""), ("\r\n", ""), ("\n", "\n  \n\n")])
def test_a_plain_off_read_a_block_of_lines_at_a_time_is_the_file_read_whole(tmp_path, monkeypatch, corners, ending, trailer):
    """A plain OFF (a vertex a line, then a face a line) is read a block of lines at a time,
    never split into a Python string per number: blocks of a line or a few give the
    vertices and fans the whole-text reading gives, and files it does not take (a face
    over two lines, a comment, a bad index) still read, or fail, as before."""
    from wgpu_shading.assets import files
    from wgpu_shading.assets.files import read_text_bytes
    from wgpu_shading.assets.mesh_formats import off

    rng = np.random.default_rng(corners)
    vertices = rng.uniform(-1, 1, (40, 3))
    polygons = np.array([rng.choice(40, corners, replace=False) for _ in range(30)])
    lines = ["OFF", "40 30 0"] + [f"{x:.6f} {y:.6e} {z:.5f}" for x, y, z in vertices]
    lines += [f"{corners} " + " ".join(map(str, polygon)) for polygon in polygons]
    path = tmp_path / "plain.off"
    path.write_bytes(ending.join(lines).encode() + ending.encode() + trailer.encode())

    def read(block_bytes):
        monkeypatch.setattr(files, "TEXT_BLOCK_BYTES", block_bytes)
        return off.read_off(path, path.stat().st_size).pieces[0]

    whole_reads = []

    def read_whole(*arguments):  # the whole-text readers' way in
        whole_reads.append(arguments)
        return read_text_bytes(*arguments)

    with monkeypatch.context() as whole_text:
        whole_text.setattr(off, "text_line_blocks", lambda *arguments: iter(()))  # no blocks: the whole text
        expected = read(1 << 22)
    monkeypatch.setattr(off, "read_text_bytes", read_whole)
    for block_bytes in (2, 50, 1 << 22):
        piece = read(block_bytes)
        np.testing.assert_array_equal(piece.positions, expected.positions)
        np.testing.assert_array_equal(piece.faces, expected.faces)
    assert not whole_reads
    for changed in (lines[:-1] + [lines[-1].replace(" ", "\n", 2)],  # the last face over lines
                    lines[:5] + ["# a comment"] + lines[5:],
                    lines[:-1] + [f"{corners} 0 1 " + " ".join(["99"] * (corners - 2))]):
        path.write_bytes(ending.join(changed).encode() + ending.encode())
        try:
            read(50)
        except MeshError as error:
            assert "vertex 99" in str(error)
        assert whole_reads
        whole_reads.clear()


@pytest.mark.parametrize("colour_width", [3, 4])
@pytest.mark.parametrize("as_floats", [False, True])
def test_face_colours_of_a_plain_off_are_read_a_block_at_a_time_as_the_token_reader_reads_them(tmp_path, monkeypatch, colour_width, as_floats):
    """Faces with a colour each (`4 a b c d 255 0 0`, as MeshLab writes them, or 0..1 floats,
    as Geomview's examples) are read a block of lines at a time (off_faces.py): the same
    triangles and per-triangle colours as the reader of tokens, which took 34 s for a
    2M-triangle file. An index written as a float still goes to the reader of tokens, which
    refuses it; a face with one colour value more is read in blocks since the twenty-first
    pass (faces of several widths: `_mixed`), its colour none, as that reader reads it."""
    from wgpu_shading.assets.files import read_text_bytes
    from wgpu_shading.assets.mesh_formats import off

    rng = np.random.default_rng(colour_width + 10 * as_floats)
    vertices = rng.uniform(-1, 1, (30, 3))
    lines = ["OFF", "30 40 0"] + [f"{x:.6f} {y:.6f} {z:.6f}" for x, y, z in vertices]
    for _ in range(40):
        colour = [f"{c:.3f}" for c in rng.random(colour_width)] if as_floats else [str(c) for c in rng.integers(0, 256, colour_width)]
        lines.append(" ".join(["4", *map(str, rng.choice(30, 4, replace=False)), *colour]))
    path = tmp_path / "coloured.off"

    def read(text_lines, block_bytes, whole=False):
        return _written_and_read(monkeypatch, path, text_lines, block_bytes, whole, load_mesh)

    expected = read(lines, 1 << 22, whole=True)
    whole_reads = []
    monkeypatch.setattr(off, "read_text_bytes", lambda *arguments: whole_reads.append(arguments) or read_text_bytes(*arguments))
    for block_bytes in (2, 60, 1 << 22):
        mesh = read(lines, block_bytes)
        np.testing.assert_array_equal(mesh.positions, expected.positions)
        np.testing.assert_array_equal(mesh.indices, expected.indices)
        np.testing.assert_array_equal(mesh.colors, expected.colors)
    assert not whole_reads and len(mesh.colors) == 40 * 2 * 3  # a vertex per corner of each face's two triangles
    float_index = lines[:-1] + [lines[-1].replace(" ", " 1.0 ", 1)]
    with pytest.raises(MeshError, match="expected an integer"):
        read(float_index, 60)
    one_more = lines[:-1] + [lines[-1] + " 1"]  # four or five values: no colour there (white)
    np.testing.assert_array_equal(read(one_more, 60).colors, read(one_more, 1 << 22, whole=True).colors)
    assert len(whole_reads) == 2  # the float index, and the whole read of one_more


@pytest.mark.parametrize("keyword, extra", [("COFF", 4), ("NOFF", 3), ("CNOFF", 7), ("STOFF", 2), ("OFF", 3), ("OFF", 4)])
def test_coff_noff_and_coloured_plain_offs_are_read_a_block_at_a_time_as_the_token_reader_reads_them(tmp_path, monkeypatch, keyword, extra):
    """Vertex lines of x y z and what the keyword adds (normals, an RGBA colour, texture
    coordinates), or a plain OFF's x y z r g b [a], are read a block of lines at a time
    (`_plain_in_blocks`): the same positions, normals, colours and uvs as the reader of
    tokens, which took 18.6 s and 35x its arrays for a 2M-triangle COFF."""
    from wgpu_shading.assets import files
    from wgpu_shading.assets.files import read_text_bytes
    from wgpu_shading.assets.mesh_formats import off

    rng = np.random.default_rng(extra + len(keyword))
    rows = rng.uniform(-1, 1, (30, 3 + extra))
    colour_width = 4 if "C" in keyword else extra if keyword == "OFF" else 0  # (the colour comes last here)
    if colour_width:
        rows[:, -colour_width:] = rng.integers(0, 256, (30, colour_width))  # 0..255
    lines = [keyword, "30 20 0"] + [" ".join(f"{v:.6g}" for v in row) for row in rows]
    lines += [" ".join(["3", *map(str, rng.choice(30, 3, replace=False))]) for _ in range(20)]
    path = tmp_path / "vertices.off"
    path.write_text("\n".join(lines) + "\n")

    def read(block_bytes, whole=False):
        monkeypatch.setattr(files, "TEXT_BLOCK_BYTES", block_bytes)
        with monkeypatch.context() as patched:
            if whole:
                patched.setattr(off, "text_line_blocks", lambda *arguments: iter(()))
            return off.read_off(path, path.stat().st_size).pieces[0]

    expected = read(1 << 22, whole=True)
    whole_reads = []
    monkeypatch.setattr(off, "read_text_bytes", lambda *arguments: whole_reads.append(arguments) or read_text_bytes(*arguments))
    for block_bytes in (2, 70, 1 << 22):
        piece = read(block_bytes)
        for name in ("positions", "faces", "normals", "colors", "uvs"):
            ours, theirs = getattr(piece, name), getattr(expected, name)
            assert (ours is None) == (theirs is None), name
            if ours is not None:
                np.testing.assert_array_equal(ours, theirs, err_msg=name)
    assert not whole_reads
    assert (piece.colors is not None) == ("C" in keyword or keyword == "OFF")
    assert (piece.normals is not None) == ("N" in keyword) and (piece.uvs is not None) == (keyword == "STOFF")


def test_a_first_face_of_more_corners_than_vertices_is_refused_before_its_numbers_are_read(tmp_path):
    """A 48 MB OFF of one face of 24M corners over 4 vertices went to the reader of tokens
    (a Python string a number: 520 MB and 1.8 s) to be refused; the block reader says the
    same from the face line's count (0.4 s)."""
    path = tmp_path / "one_face.off"
    path.write_text("OFF\n4 1 0\n" + SQUARE + "2400" + " 0 1 2 3" * 600 + "\n")
    with pytest.raises(MeshError, match=r"face 0 has 2400 vertices \(the file has 4\)"):
        load_mesh(path)


@pytest.mark.parametrize("block_bytes", [2, 50, 1 << 22])
def test_faces_of_several_sizes_are_read_a_block_of_lines_at_a_time_as_the_token_reader_reads_them(tmp_path, monkeypatch, block_bytes):
    """Triangles, quads, a pentagon and faces of fewer than 3 corners (no triangles), as
    quad-dominant exporters write an OFF: each line's numbers counted (off_faces.py), each
    face fanned in file order, the reader of tokens' triangles (it held the whole text: a
    2M-triangle file peaked at 36x its arrays and took 19 s). With colours after some of
    them: the same, with the reader of tokens' colours (10x and 42 s at 2M triangles before
    the twenty-first pass)."""
    from wgpu_shading.assets.files import read_text_bytes
    from wgpu_shading.assets.mesh_formats import off

    rng = np.random.default_rng(4)
    vertices = rng.uniform(-1, 1, (30, 3))
    sizes = [3, 4, 4, 5, 3, 2, 4, 3, 0, 6] * 4
    lines = ["OFF", f"30 {len(sizes)} 0"] + [f"{x:.6f} {y:.6f} {z:.6f}" for x, y, z in vertices]
    lines += [" ".join(map(str, [size, *rng.choice(30, size, replace=False)])) for size in sizes]
    path = tmp_path / "mixed.off"

    def read(text_lines, block, whole=False):
        return _written_and_read(monkeypatch, path, text_lines, block, whole, lambda path: off.read_off(path, path.stat().st_size).pieces[0])

    expected = read(lines, 1 << 22, whole=True)
    whole_reads = []
    monkeypatch.setattr(off, "read_text_bytes", lambda *arguments: whole_reads.append(arguments) or read_text_bytes(*arguments))
    piece = read(lines, block_bytes)
    np.testing.assert_array_equal(piece.positions, expected.positions)
    np.testing.assert_array_equal(piece.faces, expected.faces)
    assert not whole_reads and len(piece.faces) == 4 * (1 + 2 + 2 + 3 + 1 + 2 + 1 + 4)
    for colour in ("255 0 0", "0.5 0.25 1", "0 128 255 64", "0.5 0.5 0.5 0.5", "7"):  # RGB, RGBA, a colour-map index
        coloured = lines[:-1] + [lines[-1] + " " + colour]  # the last face's colour; the others none (white)
        theirs = read(coloured, 1 << 22, whole=True)
        ours = read(coloured, block_bytes)
        np.testing.assert_array_equal(ours.faces, theirs.faces)
        # (face colours: every corner its own vertex once the normals are made, mesh_pieces.assemble)
        assert (ours.face_colors is None) == (theirs.face_colors is None) == (colour == "7")
        assert ours.colors is None and theirs.colors is None
        if ours.face_colors is not None:
            np.testing.assert_array_equal(ours.face_colors, theirs.face_colors)
    mixed_colours = lines[:2 + 30] + [f"{line} {k % 256} {(3 * k) % 256} 9" + (" 200" * (k % 2)) for k, line in enumerate(lines[2 + 30 :])]
    np.testing.assert_array_equal(read(mixed_colours, block_bytes).face_colors, read(mixed_colours, 1 << 22, whole=True).face_colors)
    assert len(whole_reads) == 6  # the whole=True reads only


def _written_and_read(monkeypatch, path, text_lines, block_bytes, whole, load):
    """`text_lines` written to `path`, then load(path) with text blocks of `block_bytes`, or
    (whole) through the reader of tokens."""
    from wgpu_shading.assets import files
    from wgpu_shading.assets.mesh_formats import off

    path.write_text("\n".join(text_lines) + "\n")
    monkeypatch.setattr(files, "TEXT_BLOCK_BYTES", block_bytes)
    with monkeypatch.context() as patched:
        if whole:
            patched.setattr(off, "text_line_blocks", lambda *arguments: iter(()))  # no blocks: the reader of tokens
        return load(path)
