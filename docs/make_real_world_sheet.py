"""The before/after picture sheet of docs/real-world-files.md: real files other tools wrote,
rendered by the renderer before issue 12 (commit 2961699) and now, with the CLI as a user
runs it.

    python docs/make_real_world_sheet.py CORPUS_DIR [-o docs/images/real_world_before_after.png]

CORPUS_DIR holds the public files listed in FILES (sources and licences: tests/data/real/
LICENCES.md and docs/real-world-files.md); they are not part of the repository. The
"before" renders run the old commit's CLI from a `git archive` of it, with this Python.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
BEFORE = "2961699"
SIZE = 200
# (label, file or scene, options for the current CLI)
FILES = [
    ("CesiumMilkTruck.glb: textured + untextured parts, 2 wheel instances", "CesiumMilkTruck.glb", []),
    ("CesiumMilkTruck_draco.glb: Draco, decoded (draco extra)", "CesiumMilkTruck_draco.glb", []),
    ("cornell_box.obj: usemtl parts (red, green walls)", "cornell_box.toml", []),
    ("TestScene.gltf: 6 materials, one BLEND", "TestScene.gltf", []),
    ("AlphaBlendModeTest.glb: OPAQUE / BLEND / MASK", "AlphaBlendModeTest.glb", []),
    ("teapot.stl: triangle soup, welded + 60° creases", "teapot.stl", []),
    ("featuretype.STL: CAD part, --up +Z, creases", "featuretype.STL", ["--up", "+Z"]),
    ("cubevc.glb: COLOR_0 vertex colours", "cubevc.glb", []),
    ("BoxTextured_unlit.glb: KHR_materials_unlit", "BoxTextured_unlit.glb", []),
    ("cube-vertexcol.obj: v x y z r g b (its .mtl is missing)", "cube-vertexcol.obj", []),
]
CORNELL = """# The Cornell box seen through its open side, lit from under the ceiling light.
[output]
size = [200, 200]
[camera]
eye = [278.0, 273.0, -800.0]
target = [278.0, 273.0, 280.0]
fov_y = 39.0
near = 100.0
far = 3000.0
[[lights]]
type = "positional"
position = [278.0, 500.0, 200.0]
[[objects]]
mesh = "{mesh}"
"""


def render(python_path: str, source: Path, options: list[str], output: Path) -> str:
    env = dict(os.environ, PYTHONPATH=python_path)
    command = [sys.executable, "-c", "import sys; from wgpu_shading.cli import main; sys.exit(main(sys.argv[1:]))",
               "render", str(source), "--size", str(SIZE), "-o", str(output), "-q", *options]
    result = subprocess.run(command, env=env, capture_output=True, text=True, cwd=tempfile.gettempdir())
    return "" if result.returncode == 0 else (result.stderr.strip().splitlines() or ["error"])[-1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("corpus", type=Path)
    parser.add_argument("-o", "--output", type=Path, default=REPO / "docs" / "images" / "real_world_before_after.png")
    args = parser.parse_args()
    from PIL import Image, ImageDraw

    with tempfile.TemporaryDirectory() as folder:
        work = Path(folder)
        before_tree = work / "before"
        before_tree.mkdir()
        archive = subprocess.run(["git", "-C", str(REPO), "archive", BEFORE], capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(before_tree)], input=archive, check=True)
        # pyproject maps wgsl/ into the package; a plain source tree needs it in place
        (before_tree / "wgsl").rename(before_tree / "wgpu_shading" / "wgsl")
        (work / "cornell_box.toml").write_text(CORNELL.format(mesh=(args.corpus / "cornell_box.obj").as_posix()))
        label_height = 28
        sheet = Image.new("RGB", (2 * SIZE + 8, len(FILES) * (SIZE + label_height)), (40, 40, 40))
        draw = ImageDraw.Draw(sheet)
        for row, (label, name, options) in enumerate(FILES):
            source = work / name if name.endswith(".toml") else args.corpus / name
            top = row * (SIZE + label_height)
            draw.text((4, top + 2), label, fill=(255, 255, 255))
            for column, (tree, extra) in enumerate(((before_tree, [o for o in options if o not in ("--up", "+Z")]), (REPO, options))):
                output = work / f"{row}_{column}.png"
                error = render(str(tree), source, extra, output)
                x = column * (SIZE + 8)
                if error:
                    tile = Image.new("RGB", (SIZE, SIZE), (90, 20, 20))
                    ImageDraw.Draw(tile).multiline_text((4, 4), "error:\n" + "\n".join(error[i : i + 30] for i in range(0, min(len(error), 240), 30)), fill=(255, 255, 255))
                else:
                    tile = Image.open(output).convert("RGB")
                sheet.paste(tile, (x, top + label_height))
            draw.text((4, top + 14), "before (2961699)", fill=(200, 200, 200))
            draw.text((SIZE + 12, top + 14), "now", fill=(200, 200, 200))
        args.output.parent.mkdir(parents=True, exist_ok=True)
        sheet.save(args.output)
        print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
