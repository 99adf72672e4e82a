"""A PLY's `edge` element (`vertex1 vertex2`, optional `red green blue`), as MeshLab, Open3D's
LineSet, Blender (loose edges) and trimesh write it: drawn as lines, alone or over the
file's faces (docs/primitives.md). Expected segments and colours are the ones written into
each file here; bad edges are one line naming the file."""

from __future__ import annotations

import numpy as np
import pytest

from wgpu_shading import MeshError, load_mesh

SQUARE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
EDGES = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]])
EDGE_COLORS = np.array([[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0], [10, 20, 30]], np.uint8)
FACES = np.array([[0, 1, 2], [0, 2, 3]])


def _ply(path, fmt: str, *, faces: bool = False, colors: bool = False, edge_rows=None) -> None:
    """The square's vertices, [its two faces,] and the edges (with a colour each) in `fmt`:
    ascii, binary_little_endian or binary_big_endian."""
    edge_rows = EDGES if edge_rows is None else edge_rows
    header = ["ply", f"format {fmt} 1.0", "comment VCGLIB generated", "element vertex 4",
              "property float x", "property float y", "property float z"]
    if faces:
        header += [f"element face {len(FACES)}", "property list uchar int vertex_indices"]
    header += [f"element edge {len(edge_rows)}", "property int vertex1", "property int vertex2"]
    if colors:
        header += ["property uchar red", "property uchar green", "property uchar blue"]
    text = "\n".join(header + ["end_header"]) + "\n"
    if fmt == "ascii":
        rows = [" ".join(f"{v:g}" for v in p) for p in SQUARE]
        rows += ["3 " + " ".join(map(str, f)) for f in FACES] if faces else []
        rows += [" ".join(map(str, [*e, *(EDGE_COLORS[k] if colors else ())])) for k, e in enumerate(edge_rows)]
        path.write_text(text + "\n".join(rows) + "\n")
        return
    order = "<" if fmt == "binary_little_endian" else ">"
    body = SQUARE.astype(order + "f4").tobytes()
    if faces:
        face_records = np.zeros(len(FACES), [("n", "u1"), ("v", order + "i4", 3)])
        face_records["n"], face_records["v"] = 3, FACES
        body += face_records.tobytes()
    fields = [("v", order + "i4", 2)] + ([("c", "u1", 3)] if colors else [])
    edge_records = np.zeros(len(edge_rows), fields)
    edge_records["v"] = edge_rows
    if colors:
        edge_records["c"] = EDGE_COLORS
    path.write_bytes(text.encode() + body + edge_records.tobytes())


def _segments(mesh) -> list[tuple]:
    """The mesh's segments as pairs of the file's vertex positions, in order."""
    ends = mesh.world_positions()[mesh.line_indices]
    return [tuple(map(tuple, np.round(pair, 6))) for pair in ends]


EXPECTED = [tuple(map(tuple, SQUARE[e].astype(float))) for e in EDGES]


@pytest.mark.parametrize("fmt", ["ascii", "binary_little_endian", "binary_big_endian"])
def test_a_ply_of_edges_alone_is_its_lines(tmp_path, fmt):
    _ply(tmp_path / "wire.ply", fmt)
    mesh = load_mesh(tmp_path / "wire.ply")
    assert mesh.primitives == {"lines"} and mesh.line_count == len(EDGES)  # no points at the edges' ends
    assert _segments(mesh) == EXPECTED
    assert not mesh.normals.any()  # drawn unlit, in their colour


@pytest.mark.parametrize("fmt", ["ascii", "binary_little_endian"])
def test_edge_colours_colour_their_own_segment(tmp_path, fmt):
    """Open3D's LineSet writes a colour per edge: each segment is that colour at both ends
    (its ends are its own vertices, not blended with the next segment's)."""
    _ply(tmp_path / "lineset.ply", fmt, colors=True)
    mesh = load_mesh(tmp_path / "lineset.ply")
    assert _segments(mesh) == EXPECTED
    colors = mesh.colors[mesh.line_indices]  # (segments, 2 ends, 4)
    expected = np.concatenate([EDGE_COLORS / 255.0, np.ones((len(EDGES), 1))], axis=1)
    np.testing.assert_allclose(colors[:, 0], expected, atol=1e-6)
    np.testing.assert_allclose(colors[:, 1], expected, atol=1e-6)


@pytest.mark.parametrize("fmt", ["ascii", "binary_little_endian"])
def test_faces_and_edges_are_triangles_with_lines_over_them(tmp_path, fmt):
    _ply(tmp_path / "meshlab.ply", fmt, faces=True, colors=True)
    mesh = load_mesh(tmp_path / "meshlab.ply")
    assert mesh.primitives == {"triangles", "lines"}
    assert [(p.primitive, p.count) for p in mesh.parts] == [("triangles", 2), ("lines", len(EDGES))]
    corners = {tuple(p) for p in np.round(mesh.world_positions()[mesh.indices.reshape(-1)], 6)}
    assert corners == {tuple(p) for p in SQUARE.astype(float)}
    assert _segments(mesh) == EXPECTED


def test_a_ply_with_faces_and_an_empty_edge_element_is_its_faces(tmp_path):
    _ply(tmp_path / "m.ply", "ascii", faces=True, edge_rows=np.zeros((0, 2), int))
    mesh = load_mesh(tmp_path / "m.ply")
    assert mesh.primitives == {"triangles"} and mesh.triangle_count == 2


@pytest.mark.parametrize("fmt", ["ascii", "binary_little_endian"])
def test_bad_edges_are_one_line_naming_the_file(tmp_path, capsys, fmt):
    from cli_errors import one_line_error, run_cli

    _ply(tmp_path / "bad.ply", fmt, edge_rows=np.array([[0, 1], [2, 7]]))
    code, err = run_cli(capsys, "render", str(tmp_path / "bad.ply"), "-o", str(tmp_path / "o.png"))
    one_line_error(code, err, "bad.ply", "an edge refers to vertex 7", "4 vertices")
    _ply(tmp_path / "neg.ply", fmt, edge_rows=np.array([[0, -1]]))
    with pytest.raises(MeshError, match="neg.ply.*vertex -1"):
        load_mesh(tmp_path / "neg.ply")
    assert not (tmp_path / "o.png").exists()


def test_an_ascii_file_cut_short_in_its_edges_is_called_truncated(tmp_path):
    # long numbers: the header's minimum size (a digit and a separator a number) is met
    header = ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "element edge 3\nproperty int vertex1\nproperty int vertex2\nend_header\n")
    rows = "0.000000 0.000000 0.000000\n1.000000 0.000000 0.000000\n1.000000 1.000000 0.000000\n0 1\n"
    (tmp_path / "cut.ply").write_text(header + rows)
    with pytest.raises(MeshError, match="cut.ply': truncated: the header declares 3 edges, the file holds 1"):
        load_mesh(tmp_path / "cut.ply")


def test_edges_named_otherwise_are_refused_by_name(tmp_path):
    text = ("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
            "element edge 1\nproperty int v1\nproperty int v2\nend_header\n0 0 0\n1 1 1\n0 1\n")
    (tmp_path / "e.ply").write_text(text)
    with pytest.raises(MeshError, match=r"e.ply.*'edge' has no 'vertex1' and 'vertex2'"):
        load_mesh(tmp_path / "e.ply")


def test_an_edge_count_beyond_the_file_or_the_limit_is_refused_unread(tmp_path):
    """The header's edge count is checked against the file's size and the limit before
    anything is allocated (docs/reliability.md)."""
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
              "element edge {}\nproperty int vertex1\nproperty int vertex2\nend_header\n")
    body = np.zeros(6, "<f4").tobytes() + np.array([0, 1], "<i4").tobytes()
    (tmp_path / "lie.ply").write_bytes(header.format(10_000_000).encode() + body)
    with pytest.raises(MeshError, match="lie.ply.*truncated or damaged"):
        load_mesh(tmp_path / "lie.ply")
    (tmp_path / "huge.ply").write_bytes(header.format(1 << 40).encode() + body)
    with pytest.raises(MeshError, match="huge.ply': declares 1099511627776 edges; at most"):
        load_mesh(tmp_path / "huge.ply")
