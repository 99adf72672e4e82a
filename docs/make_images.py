"""Regenerate the pictures in docs/images/ (run through `./run docs`).

Renders every scene in examples/ with one Renderer and composes labelled contact sheets.
"""

from __future__ import annotations

import sys
from pathlib import Path

import imageio.v3 as iio
from wgpu_shading import Renderer, SceneError, load_scene
from wgpu_shading.accuracy import contact_sheet

ROOT = Path(__file__).resolve().parent.parent
IMAGES = ROOT / "docs" / "images"


def main() -> int:
    IMAGES.mkdir(parents=True, exist_ok=True)
    renderer = Renderer()
    rendered = {}
    for path in sorted((ROOT / "examples").glob("*.toml")):
        try:
            scene = load_scene(path)
        except SceneError as error:  # the examples that use ../shared/models, on a machine without it
            print(f"skipped {path.name}: {error}", file=sys.stderr)
            continue
        rendered[path.stem] = renderer.render(scene)
        iio.imwrite(IMAGES / f"{path.stem}.png", rendered[path.stem])
        print(f"wrote docs/images/{path.stem}.png")
    modes = [("Flat", "gold_torus_flat"), ("Gouraud", "gold_torus_gouraud"), ("Phong", "gold_torus_phong"), ("Blinn-Phong (k = 3)", "gold_torus_blinn_phong")]
    sheet = contact_sheet([[(label, rendered[name][96:416, 16:496]) for label, name in modes]])
    iio.imwrite(IMAGES / "gold_torus_modes.png", sheet)
    print("wrote docs/images/gold_torus_modes.png")
    gallery = [(name.replace("_", " "), image[::2, ::2]) for name, image in rendered.items() if not name.startswith("gold_torus")]
    iio.imwrite(IMAGES / "examples.png", contact_sheet([gallery[i : i + 4] for i in range(0, len(gallery), 4)]))
    print("wrote docs/images/examples.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
