"""The morph target, animation and camera sheet of docs/animation.md: Khronos samples and the
glTF Asset Generator's files (tests/data/real, with their licences) and f3d's Fox (bevy's
copy, ../shared/corpora/realworld2) drawn by `wgpu-shading render` with the options each row
names, next to f3d 4.0 at the same animation time or camera.

    python docs/make_animation_sheet.py [--f3d-python /tmp/f3d/bin/python] [-o docs/images/animation_f3d.png]

f3d is driven through its Python module (Engine.scene.animation.load_time, the option
scene.camera.index), offscreen; its camera frames the model its own way.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
DATA = REPO / "tests" / "data" / "real"
SHARED = next((p / "shared" for p in REPO.parents if (p / "shared" / "corpora").is_dir()), REPO / "missing")
FOX = SHARED / "corpora" / "realworld2" / "gltf" / "Fox.glb"
SIZE = 200

# (label, file, `render` options, f3d's: time, animation index, camera index, azimuth, elevation)
ROWS = [
    ("MorphPrimitivesTest: mesh weights [0.5]", DATA / "khronos" / "MorphPrimitivesTest.gltf", ["--camera-elevation=-12"], (None, 0, None, 0, 0)),
    ("AnimatedMorphCube at 1.5 s (thin)", DATA / "khronos" / "AnimatedMorphCube.gltf", ["--animation-time", "1.5", "--camera-azimuth", "60"], (1.5, 0, None, 60, 0)),
    ("AnimatedMorphCube at 3 s (ramp)", DATA / "khronos" / "AnimatedMorphCube.gltf", ["--animation-time", "3", "--camera-azimuth", "60"], (3.0, 0, None, 60, 0)),
    ("SimpleSkin at 1 s: joint turned 90°", DATA / "khronos" / "SimpleSkin.gltf", ["--animation-time", "1"], (1.0, 0, None, 0, 0)),
    ("Fox, walk (animation 1) at 0.3 s", FOX, ["--animation-index", "1", "--animation-time", "0.3", "--camera-azimuth", "90"], (0.3, 1, None, 90, 0)),
    ("example:arm.glb at 1 s, through its camera", REPO / "examples" / "arm.glb", ["--animation-time", "1", "--camera-index", "0"], (1.0, 0, 0, 0, 0)),
    ("Asset Generator Node_05: cubic-spline turn, 0.5 s", DATA / "asset_generator" / "Animation_Node_05.gltf", ["--animation-time", "0.5"], (0.5, 0, None, 0, 0)),
]

_F3D = """
import sys, f3d
mesh, out, size, time, index, camera, azimuth, elevation = sys.argv[1:]
f3d.Engine.autoload_plugins()
engine = f3d.Engine.create_osmesa()
engine.options["scene.animation.indices"] = [int(index)]
if camera != "None":
    engine.options["scene.camera.index"] = int(camera)
engine.window.size = (int(size), int(size))
engine.scene.add(mesh)
if time != "None":
    engine.scene.animation.load_time(float(time))
if float(azimuth):
    engine.window.camera.azimuth(float(azimuth))
if float(elevation):
    engine.window.camera.elevation(float(elevation))
if float(azimuth) or float(elevation):
    engine.window.camera.reset_to_bounds()  # frame the pose again from the turned camera
engine.window.render_to_image().save(out)
"""


def ours(source: Path, options: list[str], output: Path) -> str:
    command = [sys.executable, "-c", "import sys; from wgpu_shading.cli import main; sys.exit(main(sys.argv[1:]))",
               "render", str(source), "--size", str(SIZE), "--samples", "4",
               "-o", str(output), "-q", *options]
    result = subprocess.run(command, capture_output=True, text=True)
    return "" if result.returncode == 0 else (result.stderr.strip().splitlines() or ["error"])[-1]


def f3d(python: str, source: Path, settings: tuple, output: Path) -> str:
    result = subprocess.run([python, "-c", _F3D, str(source), str(output), str(SIZE), *map(str, settings)], capture_output=True, text=True)
    return "" if result.returncode == 0 else (result.stderr.strip().splitlines() or ["error"])[-1]


def cameras_row(folder: Path) -> list:
    """Khronos' Cameras sample (CC0, ../shared/corpora/khronos) through each of its cameras."""
    source = SHARED / "corpora" / "khronos" / "Cameras.gltf"
    if not source.exists():
        return []
    return [(f"Cameras.gltf, --camera-index {n} ({kind})", source, ["--camera-index", str(n)], (None, 0, n, 0, 0))
            for n, kind in enumerate(camera["type"] for camera in json.loads(source.read_text())["cameras"])]


def main() -> None:
    from make_gltf_sheet import paste_cell
    from PIL import Image, ImageDraw

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--f3d-python")
    parser.add_argument("-o", "--output", default=str(REPO / "docs" / "images" / "animation_f3d.png"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        rows = [row for row in ROWS if row[1].exists()] + cameras_row(folder)
        columns = [("now", lambda row, out: ours(row[1], row[2], out))]
        if args.f3d_python:
            columns.append(("f3d 4.0", lambda row, out: f3d(args.f3d_python, row[1], row[3], out)))
        label_width = 300
        sheet = Image.new("RGB", (label_width + SIZE * len(columns), 20 + SIZE * len(rows)), "white")
        draw = ImageDraw.Draw(sheet)
        for c, (title, _) in enumerate(columns):
            draw.text((label_width + c * SIZE + 4, 4), title, fill="black")
        for r, row in enumerate(rows):
            draw.text((4, 20 + r * SIZE + SIZE // 2 - 12), row[0], fill="black")
            draw.text((4, 20 + r * SIZE + SIZE // 2 + 4), " ".join(row[2]), fill=(90, 90, 90))
            for c, (_, run) in enumerate(columns):
                picture = folder / f"{r}_{c}.png"
                error = run(row, picture)
                paste_cell(sheet, draw, (label_width + c * SIZE, 20 + r * SIZE), picture, error, SIZE)
        sheet.save(args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
