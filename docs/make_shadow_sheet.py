"""The exact shadows of docs/shadows.md#the-hard-cases, as a picture: for each light
elevation (60°, 30°, 10°, 2°) the sphere over a plane seen by the case's camera (float64
reference, shadows ray-cast against the same triangles), then the plane seen from straight
below with the closed-form ellipse (semi-axes r and r/sin(elevation)) drawn over the
ray-cast shadow in red; and the rest of the catalogue below.

    python docs/make_shadow_sheet.py [-o docs/images/shadow_cases.png]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from wgpu_shading.assets.image_writers import write_image  # noqa: E402
from wgpu_shading.study import reference as ref  # noqa: E402
from wgpu_shading.study.shadows import ELEVATIONS, SHADOW_CASE_NAMES, ground_view, plane_points, shadow_case  # noqa: E402

SIZE = 200


def _pixels(image) -> np.ndarray:
    return np.round(np.clip(image.color[..., :3], 0, 1) * 255).astype(np.uint8)


def _labelled(pixels: np.ndarray, text: str) -> Image.Image:
    picture = Image.fromarray(pixels).resize((SIZE, SIZE * pixels.shape[0] // pixels.shape[1]) if pixels.shape[1] != SIZE else pixels.shape[1::-1], Image.NEAREST)
    canvas = Image.new("RGB", (SIZE, SIZE + 16), "white")
    canvas.paste(picture.crop((0, 0, SIZE, min(SIZE, picture.height))), (0, 16))
    ImageDraw.Draw(canvas).text((3, 2), text, fill="black")
    return canvas


def _ellipse_over_shadow(case) -> np.ndarray:
    scene, _ = ground_view(case, SIZE)
    scene = scene.__class__(**{**scene.__dict__, "size": (SIZE, SIZE)})
    image = ref.render_reference(scene)
    pixels = _pixels(image).copy()
    inside = np.zeros(image.covered.shape, bool)
    inside[image.covered] = case.ellipse.contains(plane_points(scene)[image.covered])
    edge = inside & ~(np.roll(inside, 1, 0) & np.roll(inside, -1, 0) & np.roll(inside, 1, 1) & np.roll(inside, -1, 1))
    pixels[edge] = (230, 30, 30)
    return pixels


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", default=str(REPO / "docs" / "images" / "shadow_cases.png"))
    out = Path(parser.parse_args().output)
    tiles = []
    for elevation in ELEVATIONS:
        case = shadow_case(f"sphere_over_plane_{elevation:g}", (SIZE, SIZE))
        tiles.append(_labelled(_pixels(ref.render_reference(case.scene)), f"light at {elevation:g} deg"))
        tiles.append(_labelled(_ellipse_over_shadow(case), f"from below; red: exact ellipse"))
    others = [n for n in SHADOW_CASE_NAMES if not n.startswith("sphere_over")]
    for name in others:
        case = shadow_case(name, (SIZE, SIZE))
        tiles.append(_labelled(_pixels(ref.render_reference(case.scene)), name.replace("_", " ")))
    columns = 4
    rows = -(-len(tiles) // columns)
    sheet = Image.new("RGB", (columns * SIZE, rows * (SIZE + 16)), "white")
    for index, tile in enumerate(tiles):
        sheet.paste(tile, ((index % columns) * SIZE, (index // columns) * (SIZE + 16)))
    write_image(out, np.asarray(sheet))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
