"""Point clouds as text (`.xyz`, `.pts`; docs/primitives.md#point-clouds-as-text): every line
a point. Expected values are the numbers written into each file here, or numpy's own
reading of the real Agisoft file (np.loadtxt); bad lines are one error naming file and line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import MeshError, load_mesh
from wgpu_shading.assets.mesh_formats import point_text

REAL = Path(__file__).parent / "data" / "real" / "primitives"
POINTS = np.array([[0.5, 1.0, -2.0], [3.0, 4.25, 5.0], [-1.0, 0.0, 7.5], [2.0, -3.0, 1.0]])
NORMALS = np.array([[0, 0, 1], [0.6, 0.8, 0], [-1, 0, 0], [0, -0.6, 0.8]])
RGB = np.array([[255, 0, 0], [0, 128, 0], [0, 0, 255], [10, 20, 30]])


def _write(path: Path, rows, header: str = "", separator: str = " ") -> Path:
    lines = [separator.join(f"{v:g}" for v in row) for row in rows]
    path.write_text(header + "\n".join(lines) + "\n")
    return path


def _alpha(rgb) -> np.ndarray:
    return np.concatenate([np.asarray(rgb, float), np.ones((len(rgb), 1))], axis=1)


def test_the_agisoft_file_is_its_points_in_their_colours_at_full_precision():
    """trimesh's `points_agisoft.xyz` (UTM metres, ~665 km from the origin: float32
    coordinates would be ~0.06 m off), against numpy's reading of the same text."""
    expected = np.loadtxt(REAL / "points_agisoft.xyz")
    mesh = load_mesh(REAL / "points_agisoft.xyz")
    assert mesh.primitives == {"points"} and mesh.point_count == len(expected) == 100
    np.testing.assert_allclose(mesh.world_positions(), expected[:, :3], rtol=0, atol=1e-5)
    np.testing.assert_allclose(mesh.colors, _alpha(expected[:, 3:] / 255.0), atol=1e-6)
    assert not mesh.normals.any()  # no normals: drawn unlit, in their colour


def test_six_numbers_are_a_normal_when_every_row_is_a_unit_vector_else_a_colour(tmp_path):
    lit = load_mesh(_write(tmp_path / "n.xyz", np.hstack([POINTS, NORMALS])))
    np.testing.assert_allclose(lit.world_positions(), POINTS, atol=1e-6)
    np.testing.assert_allclose(lit.normals, NORMALS, atol=1e-6)
    assert lit.colors is None
    coloured = load_mesh(_write(tmp_path / "c.xyz", np.hstack([POINTS, RGB])))
    np.testing.assert_allclose(coloured.colors, _alpha(RGB / 255.0), atol=1e-6)
    fractions = load_mesh(_write(tmp_path / "f.xyz", np.hstack([POINTS, RGB / 256.0])))  # Open3D's xyzrgb
    np.testing.assert_allclose(fractions.colors, _alpha(RGB / 256.0), atol=1e-6)


def test_nine_numbers_and_cloudcompare_header_and_separators(tmp_path):
    nine = load_mesh(_write(tmp_path / "nine.xyz", np.hstack([POINTS, RGB, NORMALS]), separator=","))
    np.testing.assert_allclose(nine.normals, NORMALS, atol=1e-6)
    np.testing.assert_allclose(nine.colors, _alpha(RGB / 255.0), atol=1e-6)
    # CloudCompare names its columns in a header comment: the order is the header's
    named = load_mesh(_write(tmp_path / "cc.xyz", np.hstack([RGB, POINTS[:, ::-1]]), header="//R;G;B;Z;Y;X\n", separator=";"))
    np.testing.assert_allclose(named.world_positions(), POINTS, atol=1e-6)
    np.testing.assert_allclose(named.colors, _alpha(RGB / 255.0), atol=1e-6)
    scalar = load_mesh(_write(tmp_path / "s.xyz", np.hstack([POINTS, [[1], [2], [3], [4]]]), header="# x y z intensity\n\n"))
    assert scalar.colors is None and scalar.point_count == 4


def test_a_first_line_of_column_names_without_a_comment_mark_names_the_columns(tmp_path):
    """PDAL's text writer: `"X","Y","Z","Intensity","Red","Green","Blue"` (it was "not 7 numbers")."""
    header = '"X","Y","Z","Intensity","Red","Green","Blue"\n'
    named = load_mesh(_write(tmp_path / "pdal.xyz", np.hstack([POINTS, [[5], [6], [7], [8]], RGB]), header=header, separator=","))
    np.testing.assert_allclose(named.world_positions(), POINTS, atol=1e-6)
    np.testing.assert_allclose(named.colors, _alpha(RGB / 255.0), atol=1e-6)
    reordered = load_mesh(_write(tmp_path / "zyx.xyz", POINTS[:, ::-1], header="z y x\n"))
    np.testing.assert_allclose(reordered.world_positions(), POINTS, atol=1e-6)
    with pytest.raises(MeshError, match=r"words.xyz:1: 'x y w': not 3 numbers"):  # (not a header: no z)
        load_mesh(_write(tmp_path / "words.xyz", POINTS, header="x y w\n"))


def test_a_leica_pts_file_skips_its_scans_counts(tmp_path):
    """Leica PTS: a count line, then x y z intensity r g b; a second scan has its own count."""
    rows = np.hstack([POINTS, [[-1000], [0], [5], [2047]], RGB])
    text = "2\n" + "\n".join(" ".join(f"{v:g}" for v in r) for r in rows[:2]) + "\n2\n"
    text += "\n".join(" ".join(f"{v:g}" for v in r) for r in rows[2:]) + "\n"
    (tmp_path / "scan.pts").write_text(text)
    mesh = load_mesh(tmp_path / "scan.pts")
    np.testing.assert_allclose(mesh.world_positions(), POINTS, atol=1e-6)
    np.testing.assert_allclose(mesh.colors, _alpha(RGB / 255.0), atol=1e-6)


@pytest.mark.parametrize("text, words", [
    ("1 2 3\n4 5 x\n", "bad.xyz:2: '4 5 x': not 3 numbers"),
    ("# header\n1 2 3\n4 5 6 7\n", "bad.xyz:3: '4 5 6 7': 4 numbers where the first point has 3"),
    ("1 2 3\nnan 2 3\n", "bad.xyz:2: 'nan 2 3': a NaN or infinite number"),
    ("1 2\n", "bad.xyz:1: '1 2': a point needs x y z"),
    ("# only a comment\n\n", "bad.xyz': holds no points"),
    ("1 2 3 0 0 300\n", "bad.xyz': colour values from 0 to 300"),
    ("1 2 3 4 5\n", "bad.xyz': 5 numbers a line"),
    ("1 2 3\n\x00\x00\n", "bad.xyz:2: a NUL byte"),
])
def test_bad_lines_are_one_error_naming_file_and_line(tmp_path, capsys, text, words):
    from cli_errors import one_line_error, run_cli

    (tmp_path / "bad.xyz").write_bytes(text.encode())
    code, err = run_cli(capsys, "render", str(tmp_path / "bad.xyz"), "-o", str(tmp_path / "o.png"))
    one_line_error(code, err, words)
    assert not (tmp_path / "o.png").exists()


def test_blocks_keep_line_numbers_and_bound_what_is_read(tmp_path, monkeypatch):
    """Read in blocks of lines (here 64 bytes): points across blocks are all kept, an error
    in a later block names its line, a line without end is refused once past 1 MiB, and
    more points than the vertex limit are refused (here a limit of 50)."""
    monkeypatch.setattr(point_text, "_BLOCK_BYTES", 64)
    many = np.arange(3 * 40, dtype=float).reshape(-1, 3)
    mesh = load_mesh(_write(tmp_path / "many.xyz", many))
    np.testing.assert_allclose(mesh.world_positions(), many, atol=1e-5)
    (tmp_path / "late.xyz").write_text("\n".join(["1 2 3"] * 30 + ["1 2 oops"]) + "\n")
    with pytest.raises(MeshError, match="late.xyz:31: '1 2 oops'"):
        load_mesh(tmp_path / "late.xyz")
    (tmp_path / "long.xyz").write_bytes(b"1" * (1 << 20) + b"2" * 200)
    with pytest.raises(MeshError, match="long.xyz:1: a line longer than 1 MiB"):
        load_mesh(tmp_path / "long.xyz")
    # a later block whose lines' widths err both ways (one long, one short) adds up to 3 a
    # line: each line is still its own point, so the long one is refused, naming it
    (tmp_path / "uneven.xyz").write_text("\n".join(["1 2 3"] * 30 + ["1 2 3 4", "1 2"] + ["1 2 3"] * 30) + "\n")
    with pytest.raises(MeshError, match="uneven.xyz:31: '1 2 3 4': 4 numbers where the first point has 3"):
        load_mesh(tmp_path / "uneven.xyz")
    monkeypatch.setattr(point_text, "MAX_VERTICES", 50)
    with pytest.raises(MeshError, match="more than 50 points"):
        load_mesh(_write(tmp_path / "big.xyz", np.zeros((60, 3))))


def test_a_point_cloud_as_text_renders(tmp_path, capsys):
    from cli_errors import run_cli

    code, err = run_cli(capsys, "render", str(REAL / "points_agisoft.xyz"), "-o", str(tmp_path / "p.png"), "--size", "64x64")
    assert code == 0, err
    from PIL import Image

    image = np.asarray(Image.open(tmp_path / "p.png"))
    assert (image[..., :3].max(axis=2) > 0).sum() > 100  # 100 points of 3 × 3 pixels, some overlapping
