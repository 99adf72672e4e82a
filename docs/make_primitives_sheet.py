"""The points, lines and edges sheet of docs/primitives.md: real files other tools wrote
(../shared/corpora/primitives, SOURCES.md there; the small ones are in tests/data/real/primitives),
a coarse sphere with --edges and as a PLY of faces and red edges, and the triangle-strip
PLY of ../shared/corpora/realworld2, rendered before issue 27 (commit f58829e), now, and by f3d.

    python docs/make_primitives_sheet.py [--f3d-python /tmp/f3d/bin/python] [-o docs/images/primitives_f3d.png]

"now" is `wgpu-shading render FILE --size 200` (plus the row's flags); "before" runs the
old commit's CLI from a `git archive` of it, with this Python; f3d 4.0 runs offscreen with
its defaults (and `render.show_edges` for the edges row), through a small script here
because the shared f3d-render.py cannot set f3d's optional options.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
SHARED = next(folder / "shared" for folder in REPO.parents if (folder / "shared").is_dir())
CORPUS = SHARED / "corpora" / "primitives"
SMALL = REPO / "tests" / "data" / "real" / "primitives"
BEFORE = "f58829e"
SIZE = 200
NEW_FLAGS = ("--point-size", "--line-width", "--edges", "--edge-color", "--edge-width")

_CURRENT = "import sys; from wgpu_shading.cli import main; sys.exit(main(sys.argv[1:]))"
_OLD = "import sys; sys.meta_path = [f for f in sys.meta_path if 'editable' not in repr(f)]; " + _CURRENT.split("; ", 1)[1]
_F3D = """
import sys
import f3d
f3d.Engine.autoload_plugins()
engine = f3d.Engine.create_osmesa()
mesh, out, size, edges = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4] == "1"
if edges:
    engine.options["render.show_edges"] = True
engine.window.size = (size, size)
engine.scene.add(mesh)
engine.window.render_to_image().save(out)
"""


def _ply_with_edges(sphere, path: Path) -> Path:
    """The sphere's triangles and, as a PLY `edge` element in red, its equator and one
    meridian (a MeshLab-style PLY of faces and edges)."""
    import numpy as np

    points = sphere.world_positions()
    segments = []
    for axis, (u, v) in ((1, (0, 2)), (0, (1, 2))):  # the ring in the plane y = 0, then x = 0
        on = np.flatnonzero(np.abs(points[:, axis]) < 1e-6)
        _, first = np.unique(np.round(points[on], 6), axis=0, return_index=True)  # seams repeat vertices
        ring = on[first][np.argsort(np.arctan2(points[on[first], v], points[on[first], u]))]
        segments += list(zip(ring.tolist(), np.roll(ring, -1).tolist()))
    path.write_text(
        f"ply\nformat ascii 1.0\nelement vertex {len(points)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(sphere.indices)}\nproperty list uchar int vertex_indices\n"
        f"element edge {len(segments)}\nproperty int vertex1\nproperty int vertex2\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
        + "".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in points.tolist())
        + "".join(f"3 {a} {b} {c}\n" for a, b, c in sphere.indices.tolist())
        + "".join(f"{a} {b} 255 0 0\n" for a, b in segments))
    return path


def rows(folder: Path) -> list[tuple[str, Path, list[str]]]:
    from wgpu_shading.scene import builtin

    sphere = builtin("builtin:sphere?slices=16&stacks=8")
    obj = folder / "sphere_16x8.obj"
    points = sphere.world_positions()
    obj.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in points.tolist())
                   + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in sphere.indices.tolist()))
    edges = _ply_with_edges(sphere, folder / "sphere_edges.ply")
    return [
        ("PLY scan: 45k points, normals, colours\n(StandardCyborg, ASCII)", CORPUS / "ply" / "sven-ear-to-ear-lo-res_Expected.ply", []),
        ("PLY RGB-D fragment: 113k points,\ncolours, no normals (Open3D)", CORPUS / "ply" / "livingroom1_fragment_002.ply", ["--up=-Y"]),
        ("PLY: 5k points, normals of mixed\nsign, colours (Open3D SLAC)", SMALL / "livingroom1_slac_fragment_000.ply", ["--up=-Y"]),
        ("glTF POINTS with COLOR_0,\n--point-size 2 (Cesium planePoints)", CORPUS / "gltf" / "planePoints.glb", ["--point-size", "2"]),
        ("glTF: the seven modes\n(Khronos MeshPrimitiveModes)", SMALL / "MeshPrimitiveModes.gltf", []),
        ("OBJ `l` with usemtl colours,\n--line-width 3 (Online3DViewer)", SMALL / "lines_colors.obj", ["--line-width", "3"]),
        ("OBJ wireframe (Blender)", SMALL / "obj_wireframe.obj", []),
        ("OFF `54 0 0`: neuron tracing\npoints (surfrecon)", CORPUS / "off" / "surfrecon_points.off", ["--point-size", "5"]),
        ("--edges on a 16×8 sphere", obj, ["--edges", "--edge-color", "1,1,1", "--material", "ruby"]),
        ("PLY faces + `edge` element (red),\n--line-width 2 (MeshLab-style, made here)", edges, ["--line-width", "2"]),
        ("PLY triangle strips: Cyberware's igea\n(common-3d-test-models)", SHARED / "corpora" / "realworld2" / "ply" / "igea_tristrips.ply", []),
        ("XYZ text: 100 points `x y z r g b`,\n--point-size 6 (Agisoft)", SMALL / "points_agisoft.xyz", ["--point-size", "6"]),
    ]


def _existing_flags(options: list[str]) -> list[str]:
    """`options` without the flags issue 27 added (and their values), for the old commit."""
    kept, skip = [], False
    for option in options:
        if skip:
            skip = False
        elif option in NEW_FLAGS:
            skip = option != "--edges"  # the others take a value
        else:
            kept.append(option)
    return kept


def ours(python_path: str, source: Path, options: list[str], output: Path) -> str:
    env = dict(os.environ, PYTHONPATH=python_path)
    now = python_path == str(REPO)
    command = [sys.executable, "-c", _CURRENT if now else _OLD, "render", str(source), "--size", str(SIZE), "-o", str(output), "-q",
               *(options if now else _existing_flags(options))]
    result = subprocess.run(command, env=env, capture_output=True, text=True, cwd=tempfile.gettempdir())
    return "" if result.returncode == 0 else (result.stderr.strip().splitlines() or ["error"])[-1]


def f3d(python: str, source: Path, options: list[str], output: Path) -> str:
    edges = "1" if "--edges" in options else "0"
    result = subprocess.run([python, "-c", _F3D, str(source), str(output), str(SIZE), edges], capture_output=True, text=True)
    return "" if result.returncode == 0 else (result.stderr.strip().splitlines() or ["error"])[-1]


def main() -> None:
    from make_gltf_sheet import draw_sheet, extract_commit

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--f3d-python")
    parser.add_argument("-o", "--output", default=str(REPO / "docs" / "images" / "primitives_f3d.png"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        old = extract_commit(BEFORE, folder)
        columns = [(f"before ({BEFORE})", lambda s, o, p: ours(str(old), s, o, p)), ("now", lambda s, o, p: ours(str(REPO), s, o, p))]
        if args.f3d_python:
            columns.append(("f3d 4.0 (its defaults)", lambda s, o, p: f3d(args.f3d_python, s, o, p)))
        draw_sheet(rows(folder), columns, folder, args.output, 250, SIZE)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
