"""The share of a bare mesh's covered pixels darker than 32/255 with the CLI's default lights
(docs/scene-files.md; tests/test_viewer_lighting.py asserts it for the shipped meshes).

    .venv/bin/python docs/measure_lighting.py [MODELS_FOLDER]   # e.g. ../shared/models
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from wgpu_shading import Renderer
from wgpu_shading.assets.mesh_scene import mesh_scene

SOURCES = ["builtin:torus", "builtin:sphere", "builtin:cube", "builtin:plane", "example:knot.obj", "example:gear.ply"]


def dark_fraction(renderer: Renderer, source: str) -> float:
    frame = renderer.render_frame(mesh_scene(source, (256, 256), None), depth=True)
    covered = np.isfinite(frame.depth)
    luminance = frame.color[:, :, :3].astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])
    return float(np.mean(luminance[covered] < 32))


def main() -> None:
    sources = list(SOURCES)
    if len(sys.argv) > 1:
        sources += sorted(str(p) for p in Path(sys.argv[1]).glob("*.obj"))
    renderer = Renderer()
    print("| mesh (256², default framing and lights) | covered pixels darker than 32/255 |")
    print("|---|---:|")
    for source in sources:
        print(f"| {Path(source).name if '/' in source else source} | {dark_fraction(renderer, source):.1%} |")


if __name__ == "__main__":
    main()
