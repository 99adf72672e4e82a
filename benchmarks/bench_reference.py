"""How long the float64 reference renderer takes on spheres of growing size.

    python benchmarks/bench_reference.py [--size 512] [--triangles 20 5000 100000 1000000]

Prints the wall time of `reference.render_reference` per shading frequency (best of
--repeat runs) and how many pixels the sphere covers. CPU only: no GPU module is used.
"""

from __future__ import annotations

import argparse
import time

from wgpu_shading.study import reference
from wgpu_shading.scene import sphere_for_triangles
from wgpu_shading.scene import DirectionalLight, Material, PositionalLight, Scene, SceneObject, Shading


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=int, default=512, help="image width and height in pixels")
    parser.add_argument("--triangles", type=int, nargs="+", default=[20, 5_000, 100_000, 1_000_000])
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    lights = (DirectionalLight(direction=(-1, -1, -1)), PositionalLight(position=(2, 2, 3), attenuation=(1, 0.1, 0.01)))
    material = Material(specular=(0.8, 0.8, 0.8, 1), shininess=40.0)
    print(f"{'triangles':>10} {'frequency':>9} {'seconds':>8} {'covered':>8}")
    for requested in args.triangles:
        mesh = sphere_for_triangles(requested)
        for frequency in ("flat", "gouraud", "phong"):
            scene = Scene(
                objects=(SceneObject(mesh, material),), lights=lights,
                shading=Shading(frequency=frequency), size=(args.size, args.size),
            )
            best = float("inf")
            for _ in range(args.repeat):
                start = time.perf_counter()
                image = reference.render_reference(scene)
                best = min(best, time.perf_counter() - start)
            print(f"{mesh.triangle_count:>10} {frequency:>9} {best:>8.2f} {int(image.covered.sum()):>8}")


if __name__ == "__main__":
    main()
