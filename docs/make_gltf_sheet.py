"""The glTF/OFF geometry and lights sheet of docs/real-world-files.md: small files built
here (sparse accessor, triangle fan, skin, hidden node, doubleSided, KHR_lights_punctual,
a libigl-style OFF), rendered before issue 19 (commit 1f7eeb0), now, and by f3d.

    python docs/make_gltf_sheet.py [--f3d-python /tmp/f3d/bin/python] [-o docs/images/gltf_geometry_f3d.png]

The files are written by tests/gltf_builder.py (every number is in this
script). "before" runs the old commit's CLI from a `git archive` of it, with this Python;
f3d runs through ../shared/tools/f3d-render.py when --f3d-python is given.
"""

from __future__ import annotations

import argparse
import io
import math
import os
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "tests"))
BEFORE = "1f7eeb0"
SIZE = 200
F3D_SCRIPT = next(folder / "shared" for folder in REPO.parents if (folder / "shared").is_dir()) / "tools" / "f3d-render.py"


def build(folder: Path) -> list[tuple[str, Path, list[str]]]:
    from gltf_builder import USHORT, Doc, quad, write_gltf

    rows = []
    # sparse: a flat 2×7 strip whose sparse values raise three peaks (Khronos' SimpleSparseAccessor idea)
    doc = Doc()
    base = np.array([[x, y, 0] for y in (0, 1) for x in range(7)], np.float32)
    position = doc.accessor(base)
    doc.accessors[position]["sparse"] = {"count": 6, "indices": {"bufferView": doc.view(np.array([1, 3, 5, 8, 10, 12], np.uint16)), "componentType": USHORT},
                                         "values": {"bufferView": doc.view(np.array([[1, 0, 2], [3, 0, 2], [5, 0, 2], [1, 1, 2], [3, 1, 2], [5, 1, 2]], np.float32))}}
    doc.accessors[position] |= {"min": [0, 0, 0], "max": [6, 1, 2]}
    indices = sum(([i, i + 1, i + 8, i, i + 8, i + 7] for i in range(6)), [])
    rows.append(("sparse accessor: three peaks", doc.write(folder / "sparse.gltf", [[{"attributes": {"POSITION": position}, "indices": doc.accessor(np.array(indices, np.uint16), USHORT)}]],
                                                           [{"mesh": 0, "rotation": [-0.5, 0, 0, 0.8660254]}]), []))
    # triangle fan: a hexagon
    doc = Doc()
    hexagon = np.array([[0, 0, 0]] + [[math.cos(a), math.sin(a), 0] for a in np.linspace(0, 2 * math.pi, 7)], np.float32)
    rows.append(("TRIANGLE_FAN hexagon", doc.write(folder / "fan.gltf", [[{"attributes": {"POSITION": doc.accessor(hexagon)}, "mode": 6}]], [{"mesh": 0}]), []))
    # skin: a bar bent 60° at its middle joint (weights blend over y 0.75..1.25)
    doc = Doc()
    vertices, joints, weights = [], [], []
    for y in np.linspace(0, 2, 9):
        for x in (-0.2, 0.2):
            for z in (-0.2, 0.2):
                w = float(np.clip((y - 0.75) / 0.5, 0, 1))
                vertices.append([x, y, z]), joints.append([0, 1, 0, 0]), weights.append([1 - w, w, 0, 0])
    faces = []
    for k in range(8):
        ring = [0, 1, 3, 2]
        for i in range(4):
            a, b = k * 4 + ring[i], k * 4 + ring[(i + 1) % 4]
            faces += [a, b, b + 4, a, b + 4, a + 4]
    faces += [0, 2, 3, 0, 3, 1, 32, 33, 35, 32, 35, 34]
    inverse_bind = np.stack([np.eye(4), np.array([[1, 0, 0, 0], [0, 1, 0, -1], [0, 0, 1, 0], [0, 0, 0, 1]])]).transpose(0, 2, 1).reshape(2, 16)
    half = math.radians(60) / 2
    primitive = {"attributes": {"POSITION": doc.accessor(np.array(vertices, np.float32)), "JOINTS_0": doc.accessor(np.array(joints, np.uint16), USHORT),
                                "WEIGHTS_0": doc.accessor(np.array(weights, np.float32))}, "indices": doc.accessor(np.array(faces, np.uint16), USHORT)}
    nodes = [{"mesh": 0, "skin": 0}, {"children": [2]}, {"translation": [0, 1, 0], "rotation": [0, 0, math.sin(half), math.cos(half)], "_child": True}]
    rows.append(("skin: bar bent by its joint", doc.write(folder / "skin.gltf", [[primitive]], nodes,
                                                          skins=[{"joints": [1, 2], "inverseBindMatrices": doc.accessor(inverse_bind.astype(np.float32))}]), []))
    # a hidden (scale 0) instance next to a visible one
    positions, square = quad(-0.5, -0.5)
    rows.append(("node scaled to 0 is hidden", write_gltf(folder / "hidden.gltf", [[{"positions": positions, "indices": square}]],
                                                          nodes=[{"mesh": 0}, {"mesh": 0, "scale": [0, 0, 0], "translation": [2, 0, 0]}]), []))
    # doubleSided: a quad seen from behind, single-sided (left, culled) and double-sided (right)
    left, _ = quad(-1.5, -0.5)
    right, _ = quad(0.5, -0.5)
    normals = np.tile([0.0, 0.0, -1.0], (4, 1))
    rows.append(("backs: single-sided (culled) | doubleSided", write_gltf(folder / "sides.gltf", [[
        {"positions": left, "indices": square[:, ::-1], "normals": normals, "material": 0},
        {"positions": right, "indices": square[:, ::-1], "normals": normals, "material": 1}]],
        materials=[{"pbrMetallicRoughness": {"metallicFactor": 0.0}}, {"pbrMetallicRoughness": {"metallicFactor": 0.0}, "doubleSided": True}]), []))
    # lights: a floor lit by a white spot from above and a red point light
    n = 20
    xs = np.linspace(-2, 2, n + 1)
    grid = np.array([[x, 0, z] for z in xs[::-1] for x in xs], np.float32)
    cells = sum(([[r * (n + 1) + c, r * (n + 1) + c + 1, (r + 1) * (n + 1) + c + 1], [r * (n + 1) + c, (r + 1) * (n + 1) + c + 1, (r + 1) * (n + 1) + c]]
                 for r in range(n) for c in range(n)), [])
    down = [math.sin(-math.pi / 4), 0, 0, math.cos(-math.pi / 4)]
    lights = [{"type": "spot", "intensity": 8, "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.5}}, {"type": "point", "intensity": 1, "color": [1, 0.2, 0.2]}]
    rows.append(("KHR_lights_punctual: spot + red point", write_gltf(
        folder / "lights.gltf", [[{"positions": grid, "indices": np.array(cells), "normals": np.tile([0, 1, 0], (len(grid), 1)), "material": 0}]],
        materials=[{"pbrMetallicRoughness": {"metallicFactor": 0.0}, "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}],
        nodes=[{"mesh": 0}, {"translation": [0, 2, 0], "rotation": down, "extensions": {"KHR_lights_punctual": {"light": 0}}},
               {"translation": [1.5, 0.5, 1.0], "extensions": {"KHR_lights_punctual": {"light": 1}}}],
        extra={"extensions": {"KHR_lights_punctual": {"lights": lights}}}), ["--camera-position", "0,4,5", "--camera-focal-point", "0,0,0"]))
    # OFF with a face over several lines, as libigl writes long faces
    off = folder / "libigl.off"
    off.write_text("OFF\n6 1 0\n" + "".join(f"{math.cos(a):.6f} {math.sin(a):.6f} 0\n" for a in np.linspace(0, 2 * math.pi, 7)[:6]) + "6\n0 1 2\n3 4 5\n")
    rows.append(("OFF face over 3 lines (libigl)", off, []))
    return rows


# An editable install maps wgpu_shading (and its wgsl/ folder) onto this checkout: the old
# commit's package is imported from PYTHONPATH with that finder removed.
_CURRENT = "import sys; from wgpu_shading.cli import main; sys.exit(main(sys.argv[1:]))"
_OLD = "import sys; sys.meta_path = [f for f in sys.meta_path if 'editable' not in repr(f)]; " + _CURRENT.split("; ", 1)[1]


def ours(python_path: str, source: Path, options: list[str], output: Path) -> str:
    env = dict(os.environ, PYTHONPATH=python_path)
    command = [sys.executable, "-c", _CURRENT if python_path == str(REPO) else _OLD,
               "render", str(source), "--size", str(SIZE), "-o", str(output), "-q", *options]
    result = subprocess.run(command, env=env, capture_output=True, text=True, cwd=tempfile.gettempdir())
    return "" if result.returncode == 0 else (result.stderr.strip().splitlines() or ["error"])[-1]


def f3d(python: str, source: Path, options: list[str], output: Path) -> str:
    extra = []
    if "--camera-position" in options:
        extra = ["--position", *options[1].split(","), "--focal-point", *options[3].split(",")]
    result = subprocess.run([python, str(F3D_SCRIPT), str(source), str(output), "--size", str(SIZE), *extra], capture_output=True, text=True)
    return "" if result.returncode == 0 else (result.stderr.strip().splitlines() or ["error"])[-1]


def paste_cell(sheet, draw, corner: tuple[int, int], picture: Path, error: str, size: int) -> None:
    """One cell of a sheet: the picture, or the error that replaced it, in red on grey."""
    from PIL import Image

    x, y = corner
    if error:
        draw.rectangle([x, y, x + size - 1, y + size - 1], fill=(235, 235, 235))
        for k in range(0, len(error), 34):
            draw.text((x + 4, y + 4 + 12 * (k // 34)), error[k : k + 34], fill="red")
    else:
        sheet.paste(Image.open(picture).convert("RGB").resize((size, size)), (x, y))


def extract_commit(commit: str, folder: Path) -> Path:
    """The package at `commit`, from a `git archive` of it, importable from the folder returned."""
    old = folder / "before"
    archive = subprocess.run(["git", "-C", str(REPO), "archive", commit], capture_output=True, check=True).stdout
    tarfile.open(fileobj=io.BytesIO(archive)).extractall(old, filter="data")
    if (old / "wgsl").is_dir() and not (old / "wgpu_shading" / "wgsl").exists():
        (old / "wgpu_shading" / "wgsl").symlink_to(old / "wgsl")  # where the package reads them
    return old


def draw_sheet(rows: list, columns: list, folder: Path, output: str, label_width: int, size: int = SIZE) -> None:
    """A sheet of `rows` (label, source, options) × `columns` (title, run(source, options, picture) → error text)."""
    from PIL import Image, ImageDraw

    sheet = Image.new("RGB", (label_width + size * len(columns), 20 + size * len(rows)), "white")
    draw = ImageDraw.Draw(sheet)
    for c, (title, _) in enumerate(columns):
        draw.text((label_width + c * size + 4, 4), title, fill="black")
    for r, (label, source, options) in enumerate(rows):
        draw.multiline_text((4, 20 + r * size + size // 2 - 6 * label.count("\n")), label, fill="black")
        for c, (_, run) in enumerate(columns):
            picture = folder / f"{r}_{c}.png"
            error = run(source, options, picture)
            paste_cell(sheet, draw, (label_width + c * size, 20 + r * size), picture, error, size)
    sheet.save(output)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--f3d-python")
    parser.add_argument("-o", "--output", default=str(REPO / "docs" / "images" / "gltf_geometry_f3d.png"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        old = extract_commit(BEFORE, folder)
        rows = build(folder)
        columns = [("before (1f7eeb0)", lambda s, o, p: ours(str(old), s, o, p)), ("now", lambda s, o, p: ours(str(REPO), s, o, p))]
        if args.f3d_python:
            columns.append(("f3d 4.0", lambda s, o, p: f3d(args.f3d_python, s, o, p)))
        draw_sheet(rows, columns, folder, args.output, 260)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
