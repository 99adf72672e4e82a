"""The before/after sheet of issue 19's maps and colours (docs/real-world-files.md): small
glTF and OBJ files built here, rendered by the renderer before (a `git archive` of BEFORE,
run with this Python), now, and by f3d 4.0 as a second opinion.

    python docs/make_maps_sheet.py [--f3d /tmp/f3d/bin/python] [-o docs/images/maps_before_after.png]

f3d's set-up is in ../shared/tools/f3d-render.py (or any f3d script taking MESH OUT.png).
"""

from __future__ import annotations

import argparse
import base64
import io
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
BEFORE = "3a196a6"  # main before issue 19's maps and colours
SIZE = 200

from wgpu_shading.scene import uv_sphere  # noqa: E402
from wgpu_shading.scene.maps import height_to_normal  # noqa: E402


def _png(pixels: np.ndarray) -> str:
    buffer = io.BytesIO()
    Image.fromarray(np.asarray(pixels, np.uint8)).save(buffer, format="PNG")
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode()


def write_sphere(path: Path, material: dict | None, images: list[np.ndarray] = ()) -> Path:
    """A uv sphere (positions, normals, uvs; glTF's v runs down the image) with one material."""
    mesh = uv_sphere(1.0, 64, 32)
    arrays = [np.asarray(mesh.positions, np.float32), np.asarray(mesh.normals, np.float32),
              np.stack([mesh.uvs[:, 0], 1.0 - mesh.uvs[:, 1]], axis=1).astype(np.float32),
              np.asarray(mesh.indices, np.uint32).reshape(-1)]
    blob, views, accessors = b"", [], []
    for array, kind in zip(arrays, ("VEC3", "VEC3", "VEC2", "SCALAR")):
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": array.nbytes})
        accessor = {"bufferView": len(views) - 1, "componentType": 5125 if kind == "SCALAR" else 5126, "count": len(array), "type": kind}
        if len(views) == 1:
            accessor |= {"min": array.min(axis=0).tolist(), "max": array.max(axis=0).tolist()}
        accessors.append(accessor)
        blob += array.tobytes()
    primitive = {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3}
    document = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [primitive | ({"material": 0} if material is not None else {})]}],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": views, "accessors": accessors,
    }
    if material is not None:
        document["materials"] = [material]
        if "KHR_materials_unlit" in material.get("extensions", {}):
            document["extensionsUsed"] = ["KHR_materials_unlit"]
    if images:
        document["images"] = [{"uri": _png(image)} for image in images]
        document["textures"] = [{"source": index} for index in range(len(images))]
    path.write_text(json.dumps(document))
    return path


def dimples(size: int = 512, cells: int = 16) -> np.ndarray:
    """A golf ball's height field: round dimples on a grid."""
    i, j = np.meshgrid(np.arange(size), np.arange(size))
    cell = size / cells
    distance = np.hypot((i % cell) - cell / 2, (j % cell) - cell / 2) / (cell / 2)
    height = np.where(distance < 0.8, 1.0 - np.sqrt(np.clip(1 - (distance / 0.8) ** 2, 0, 1)) * 0.6, 1.0)
    return np.round(np.repeat(height[:, :, None], 3, axis=2) * 255).astype(np.uint8)


def hud(size: int = 256) -> np.ndarray:
    """An emissive pattern: bright bars and a ring on black."""
    image = np.zeros((size, size, 3), np.uint8)
    i, j = np.meshgrid(np.arange(size), np.arange(size))
    image[(j // 16) % 4 == 0] = (40, 255, 120)
    ring = np.abs(np.hypot(i - size / 2, j - size / 2) - size / 3) < 4
    image[ring] = (255, 200, 40)
    return image


def stripes(size: int = 256) -> np.ndarray:
    """Metallic-roughness texture: metal smooth stripes (B 255, G 60) on rough dielectric (G 255)."""
    image = np.zeros((size, size, 3), np.uint8)
    metal = (np.arange(size) // 32) % 2 == 0
    image[:, metal] = (0, 60, 255)
    image[:, ~metal] = (0, 255, 0)
    return image


def build(folder: Path) -> list[tuple[str, Path]]:
    golf = height_to_normal(dimples(), 6.0)[:, :, :3]
    bump_obj = folder / "golf.obj"
    Image.fromarray(golf).save(folder / "golf_normal.png")
    (folder / "golf.mtl").write_text("newmtl ball\nKd 0.9 0.9 0.9\nKs 0.3 0.3 0.3\nNs 30\nmap_Bump golf_normal.png\n")
    mesh = uv_sphere(1.0, 64, 32)
    lines = ["mtllib golf.mtl"] + [f"v {x} {y} {z}" for x, y, z in mesh.positions] + [f"vt {u} {v}" for u, v in mesh.uvs]
    lines += [f"vn {x} {y} {z}" for x, y, z in mesh.normals] + ["usemtl ball"]
    lines += [f"f {a + 1}/{a + 1}/{a + 1} {b + 1}/{b + 1}/{b + 1} {c + 1}/{c + 1}/{c + 1}" for a, b, c in mesh.indices]
    bump_obj.write_text("\n".join(lines) + "\n")
    return [
        ("unlit base colour (1, 0.2176, 0): f3d shows (255, 128, 0)",
         write_sphere(folder / "orange.gltf", {"pbrMetallicRoughness": {"baseColorFactor": [1, 0.2176, 0, 1]}, "extensions": {"KHR_materials_unlit": {}}})),
        ("no material: the glTF default (white)", write_sphere(folder / "default.gltf", None)),
        ("pbrMetallicRoughness {}: rough metal", write_sphere(folder / "rough_metal.gltf", {"pbrMetallicRoughness": {}})),
        ("normalTexture: a golf ball's dimples",
         write_sphere(folder / "golf.gltf", {"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.4},
                                            "normalTexture": {"index": 0}}, [golf])),
        ("emissiveTexture: a glowing pattern",
         write_sphere(folder / "hud.gltf", {"pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.1, 0.1, 1], "metallicFactor": 0.0},
                                           "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0}}, [hud()])),
        ("metallicRoughnessTexture: smooth metal stripes",
         write_sphere(folder / "stripes.gltf", {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.3, 1],
                                                                         "metallicRoughnessTexture": {"index": 0}}}, [stripes()])),
        ("OBJ map_Bump naming a normal map", bump_obj),
    ]


def render(command: list[str], env: dict | None = None) -> np.ndarray:
    with tempfile.TemporaryDirectory() as scratch:
        out = Path(scratch) / "out.png"
        # cwd elsewhere: `python -m` puts the working directory first on sys.path.
        subprocess.run(command + [str(out)], check=True, env=env, capture_output=True, cwd=scratch)
        return np.asarray(Image.open(out).convert("RGB").resize((SIZE, SIZE)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--f3d", default="/tmp/f3d/bin/python", help="a Python with f3d installed")
    parser.add_argument("-o", "--output", default=str(REPO / "docs/images/maps_before_after.png"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        folder, before = Path(scratch), Path(scratch) / "before"
        before.mkdir()
        archive = subprocess.run(["git", "-C", str(REPO), "archive", BEFORE], check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", str(before)], input=archive, check=True)
        # pyproject maps wgsl/ into the package; a plain source tree needs it in place
        (before / "wgsl").rename(before / "wgpu_shading" / "wgsl")
        old_env = os.environ | {"PYTHONPATH": str(before)}
        rows = []
        for label, path in build(folder):
            cli = [sys.executable, "-m", "wgpu_shading.cli.main", "render", str(path), "--size", str(SIZE), "-o"]
            pictures = [
                render(cli, old_env),
                render(cli),
                render([args.f3d, str(REPO.parent / "shared/tools/f3d-render.py"), str(path), "--size", str(SIZE)]),
            ]
            rows.append((label, pictures))
    sheet = Image.new("RGB", (3 * SIZE + 20, len(rows) * (SIZE + 22) + 24), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    for column, title in enumerate((f"before ({BEFORE})", "now", "f3d 4.0")):
        draw.text((10 + column * SIZE + 4, 4), title, fill=(0, 0, 0))
    for row, (label, pictures) in enumerate(rows):
        top = 24 + row * (SIZE + 22)
        draw.text((10, top), label, fill=(0, 0, 0))
        for column, picture in enumerate(pictures):
            sheet.paste(Image.fromarray(picture), (10 + column * SIZE, top + 18))
    temporary = Path(args.output).with_suffix(".tmp.png")
    sheet.save(temporary)
    temporary.replace(args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
