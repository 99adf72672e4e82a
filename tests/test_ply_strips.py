"""A PLY's triangle strips (`element tristrips`, `vertex_indices` with -1 between strips), as
Cyberware's scans hold their surface: GL_TRIANGLE_STRIP's triangles, each wound like the
strip's first, the degenerate ones that join strips left out (docs/real-world-files.md).
Expected triangles are written out here from the strip rule; the planar strips' normals
all face +z (closed form: every triangle counter-clockwise seen from above)."""

from __future__ import annotations

import numpy as np
import pytest

from wgpu_shading import MeshError, load_mesh

# a zig-zag along x in the z = 0 plane: 0 2 4 ... below, 1 3 5 ... above
ZIGZAG = np.array([[x // 2, x % 2, 0.0] for x in range(8)], np.float32)


def _ply(path, strips: list[int], fmt: str = "ascii") -> None:
    header = (f"ply\nformat {fmt} 1.0\nelement vertex {len(ZIGZAG)}\nproperty float x\nproperty float y\nproperty float z\n"
              "element tristrips 1\nproperty list int int vertex_indices\nend_header\n")
    if fmt == "ascii":
        body = "\n".join(" ".join(f"{v:g}" for v in p) for p in ZIGZAG) + f"\n{len(strips)} " + " ".join(map(str, strips)) + "\n"
        path.write_text(header + body)
    else:
        path.write_bytes(header.encode() + ZIGZAG.astype("<f4").tobytes() + np.array([len(strips), *strips], "<i4").tobytes())


def _triangles(mesh) -> list[tuple]:
    return [tuple(tuple(int(round(c)) for c in mesh.world_positions()[i][:2]) for i in face) for face in mesh.indices]


@pytest.mark.parametrize("fmt", ["ascii", "binary_little_endian"])
def test_strips_are_their_triangles_all_wound_one_way(tmp_path, fmt):
    # strip 0 1 2 3 4 5, then a second strip 6 7 after a restart (too short: no triangle),
    # joined by a repeated vertex (5 5): a degenerate triangle, left out
    _ply(tmp_path / "s.ply", [1, 0, 3, 2, 5, 4, 4, -1, 6, 7], fmt)
    mesh = load_mesh(tmp_path / "s.ply")
    v = lambda k: (int(ZIGZAG[k][0]), int(ZIGZAG[k][1]))  # noqa: E731
    # GL_TRIANGLE_STRIP: (a b c), (c b d), (c d e), (e d f) ...
    expected = [(v(1), v(0), v(3)), (v(3), v(0), v(2)), (v(3), v(2), v(5)), (v(5), v(2), v(4))]
    assert mesh.primitives == {"triangles"}
    found = _triangles(mesh)
    assert len(found) == 4 and all(any(t == e[k:] + e[:k] for k in range(3)) for t, e in zip(found, expected)), found
    positions = mesh.world_positions()
    a, b, c = (positions[mesh.indices[:, k]] for k in range(3))
    assert (np.cross(b - a, c - a)[:, 2] < 0).all() or (np.cross(b - a, c - a)[:, 2] > 0).all()  # one winding


def test_the_scanned_head_of_the_corpus_is_a_closed_surface_facing_out():
    """igea (Cyberware; ../shared/corpora/realworld2/ply): 134,345 vertices in one strip.
    Every triangle wound alike: the signed volume (divergence theorem) is far from zero."""
    from pathlib import Path

    shared = next((p / "shared" for p in Path(__file__).resolve().parents if (p / "shared" / "corpora").is_dir()), None)
    path = None if shared is None else shared / "corpora" / "realworld2" / "ply" / "igea_tristrips.ply"
    if path is None or not path.exists():
        pytest.skip("the shared corpus is not here")
    mesh = load_mesh(path)
    p = mesh.world_positions().astype(np.float64)
    a, b, c = (p[mesh.indices[:, k]] for k in range(3))
    signed = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0
    unsigned = np.abs(np.einsum("ij,ij->i", a - a.mean(0), np.cross(b - a.mean(0), c - a.mean(0)))).sum() / 6.0
    assert mesh.triangle_count > 260_000 and abs(signed) > 0.5 * unsigned


def test_a_strip_naming_a_missing_vertex_is_one_line(tmp_path, capsys):
    from cli_errors import one_line_error, run_cli

    _ply(tmp_path / "bad.ply", [0, 1, 2, 99])
    code, err = run_cli(capsys, "render", str(tmp_path / "bad.ply"), "-o", str(tmp_path / "o.png"))
    one_line_error(code, err, "bad.ply", "a triangle strip refers to vertex 99", "8 vertices")
    _ply(tmp_path / "short.ply", [0, 1])
    with pytest.raises(MeshError, match="short.ply.*hold no triangles"):
        load_mesh(tmp_path / "short.ply")
