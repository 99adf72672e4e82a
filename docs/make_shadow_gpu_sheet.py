"""What the GPU draws next to the exact answer (docs/shadows.md#how-the-gpu-draws-them): for
the sphere over a plane at 60°, 30°, 10° and 2° elevation, and for the rest of the hard-case
catalogue, three pictures side by side — the GPU's frame (`auto` shadow settings), the
float64 reference with ray-cast shadows, and where they disagree (check_shadows' picture:
grey exactly shadowed, white the exact boundary's 2-px band, yellow a wrong state inside it,
red one outside it, magenta a colour off by more than 1/255 away from the boundary).

    python docs/make_shadow_gpu_sheet.py [-o docs/images/shadows_gpu.png]
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from wgpu_shading import Renderer  # noqa: E402
from wgpu_shading.assets.image_writers import write_image  # noqa: E402
from wgpu_shading.study.shadows import SHADOW_CASE_NAMES, ShadowReference, failure_picture, measure_shadows, shadow_case  # noqa: E402

SIZE = 160


def _row(renderer: Renderer, name: str) -> tuple[Image.Image, str]:
    case = shadow_case(name, (SIZE, SIZE))
    image = renderer.render_frame(case.scene, float32=True).color
    shadowless = renderer.render_frame(replace(case.scene, lights=tuple(replace(l, shadows=False) for l in case.scene.lights)),
                                       float32=True).color
    reference = ShadowReference(case.scene)
    report = measure_shadows(reference, image, shadowless, name=name)
    picture = Image.fromarray(failure_picture(reference, image, shadowless))
    canvas = Image.new("RGB", (picture.width, picture.height + 16), "white")
    canvas.paste(picture, (0, 16))
    worst = max((r.displacement_p99 for r in report.lights), default=0.0)
    far = sum(r.wrong_far for r in report.lights)
    text = f"{name.replace('_', ' ')}: GPU | exact | disagreement   ({far} far, p99 {worst:.2f} px)"
    ImageDraw.Draw(canvas).text((3, 2), text, fill="black")
    return canvas, report.summary()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", default=str(REPO / "docs" / "images" / "shadows_gpu.png"))
    out = Path(parser.parse_args().output)
    renderer = Renderer()
    rows = []
    for name in SHADOW_CASE_NAMES:
        row, summary = _row(renderer, name)
        rows.append(row)
        print(summary)
    columns = 2
    width, height = rows[0].width, rows[0].height
    sheet = Image.new("RGB", (columns * width, -(-len(rows) // columns) * height), "white")
    for index, row in enumerate(rows):
        sheet.paste(row, ((index % columns) * width, (index // columns) * height))
    write_image(out, np.asarray(sheet))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
