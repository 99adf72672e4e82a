"""Regenerate the pictures in docs/images/ (run through `./run docs`).

Renders every scene in examples/ with one Renderer and composes labelled contact sheets.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import imageio.v3 as iio
from wgpu_shading import Renderer, SceneError, load_scene
from wgpu_shading.study.accuracy.pictures import contact_sheet
from wgpu_shading.testing.golden import diff_image

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
        rendered[path.stem] = renderer.render(replace(scene, samples=4))  # documentation images are antialiased (docs/conventions.md#projection-pixels-and-depth)
        iio.imwrite(IMAGES / f"{path.stem}.png", rendered[path.stem])
        print(f"wrote docs/images/{path.stem}.png")
    modes = [("Flat", "gold_torus_flat"), ("Gouraud", "gold_torus_gouraud"), ("Phong", "gold_torus_phong"), ("Blinn-Phong (k = 3)", "gold_torus_blinn_phong")]
    sheet = contact_sheet([[(label, rendered[name][96:416, 16:496]) for label, name in modes]])
    iio.imwrite(IMAGES / "gold_torus_modes.png", sheet)
    print("wrote docs/images/gold_torus_modes.png")
    gallery = [(name.replace("_", " "), image[::2, ::2]) for name, image in rendered.items() if not name.startswith("gold_torus")]
    iio.imwrite(IMAGES / "examples.png", contact_sheet([gallery[i : i + 4] for i in range(0, len(gallery), 4)]))
    print("wrote docs/images/examples.png")
    iio.imwrite(IMAGES / "golden_failure.png", golden_failure(renderer))
    print("wrote docs/images/golden_failure.png")
    iio.imwrite(IMAGES / "bare_meshes.png", bare_meshes(renderer))
    print("wrote docs/images/bare_meshes.png")
    return 0


def bare_meshes(renderer: Renderer):
    """The README's viewer picture: sample meshes as `wgpu-shading render MESH` draws them
    (framing from the up axis, key light plus headlight), with the flags shown, MSAA 4."""
    from wgpu_shading.cli.arguments import scene_from_args
    from wgpu_shading.cli.main import build_parser

    views = [  # (label, input, flags)
        ("knot.obj", "example:knot.obj", ()),
        ("gear.ply --up +Z", "example:gear.ply", ("--up", "+Z")),
        ("+ --camera-orthographic", "example:gear.ply", ("--up", "+Z", "--camera-orthographic", "--camera-elevation-angle", "25")),
        ("torus, one warm --light", "builtin:torus", ("--camera-azimuth-angle", "30", "--light", "directional:dir=-1,-0.5,-1:color=1,0.85,0.7")),
    ]
    row = []
    for label, source, flags in views:
        scene = scene_from_args(build_parser().parse_args(["render", source, "--size", "256", "--samples", "4", *flags]))
        row.append((label, renderer.render(scene)))
    return contact_sheet([row])


def golden_failure(renderer: Renderer):
    """docs/golden-tests.md's failure picture: `check --reflection blinn-phong
    --blinn-exponent-scale 1` against a Phong reference of the gold torus."""
    expected_scene = replace(load_scene(ROOT / "examples" / "gold_torus_phong.toml"), size=(288, 288))
    actual_scene = replace(
        expected_scene, shading=replace(expected_scene.shading, reflection="blinn-phong", blinn_exponent_scale=1.0)
    )
    expected, actual = renderer.render(expected_scene), renderer.render(actual_scene)
    crop = (slice(40, 248), slice(0, 288))
    return contact_sheet(
        [
            [
                ("actual: Blinn-Phong, k = 1", actual[crop]),
                ("expected: Phong", expected[crop]),
                ("diff (log scale: 1/255 shows as 32/255)", diff_image(actual, expected)[crop]),
            ]
        ]
    )


if __name__ == "__main__":
    sys.exit(main())
