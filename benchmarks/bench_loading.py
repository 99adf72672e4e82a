"""Loading a big mesh file: trimesh alone vs load_mesh (weld + crease normals) vs load + render.

    python benchmarks/bench_loading.py                 # 1.62M-triangle torus, PLY/STL/OBJ, 5 rounds
    python benchmarks/bench_loading.py --smoke         # a 2K-triangle torus, 1 round: does it still run?

Issue 12's target: a 1.6M-triangle mesh loads, welds, creases and renders in at most 1.5×
the time trimesh alone takes to load it. Every variant is timed in the same process,
interleaved round by round (so machine load hits all of them alike); the table gives
medians and the ratio to `trimesh.load(path)` (trimesh's defaults: process=True merges
vertices, the fair "trimesh loads it" baseline) and to `trimesh.load(path, process=False)`.
"load + render" uses a warm Renderer (device, pipeline and targets made beforehand): it
measures the file's own cost, upload and a 512² frame included.
Results and the command that produced them: docs/real-world-files.md.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sections", type=int, default=900, help="torus sections per ring (900: 1.62M triangles)")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--formats", default="ply,stl,obj")
    parser.add_argument("--smoke", action="store_true", help="tiny mesh, one round")
    args = parser.parse_args()
    if args.smoke:
        args.sections, args.rounds = 32, 1
    from wgpu_shading.assets.disk_cache import CACHE_VARIABLE

    os.environ[CACHE_VARIABLE] = "off"  # every round parses the file, not the mesh cache's entry

    import trimesh

    from wgpu_shading import Camera, Renderer, Scene, SceneObject, load_mesh
    from wgpu_shading.scene import PositionalLight, material

    torus = trimesh.creation.torus(major_radius=1.0, minor_radius=0.3, major_sections=args.sections, minor_sections=args.sections)
    renderer = Renderer()
    gold = material("gold")

    def scene_of(mesh):
        return Scene(objects=(SceneObject(mesh, gold),), lights=(PositionalLight(position=(3, 3, 3)),),
                     camera=Camera(eye=(0, 1.5, 3.5)), size=(512, 512))

    renderer.render(scene_of(load_mesh("builtin:torus")))  # device, pipeline and target made once
    print(f"torus: {len(torus.faces)} triangles, {len(torus.vertices)} vertices; {args.rounds} rounds\n")
    print("| format | trimesh.load (process=True) | trimesh.load (process=False) | load_mesh | load_mesh + render | (load + render) / trimesh.load "
          "| / trimesh process=False | CPU s: trimesh.load / load_mesh + render | CPU ratio |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for suffix in args.formats.split(","):
            path = Path(folder) / f"torus.{suffix}"
            torus.export(path)
            variants = {
                "trimesh": lambda: trimesh.load(str(path)),
                "trimesh_raw": lambda: trimesh.load(str(path), process=False),
                "load": lambda: load_mesh(path),
                "render": lambda: renderer.render(scene_of(load_mesh(path))),
            }
            times: dict[str, list[float]] = {name: [] for name in variants}
            cpu: dict[str, list[float]] = {name: [] for name in variants}  # this process, every thread
            for _ in range(args.rounds):
                for name, run in variants.items():
                    start, start_cpu = time.perf_counter(), time.process_time()
                    run()
                    times[name].append(time.perf_counter() - start)
                    cpu[name].append(time.process_time() - start_cpu)
            median = {name: statistics.median(values) for name, values in times.items()}
            cpu_median = {name: statistics.median(values) for name, values in cpu.items()}
            print(
                f"| {suffix.upper()} | {median['trimesh']:.3f} s | {median['trimesh_raw']:.3f} s | {median['load']:.3f} s "
                f"| {median['render']:.3f} s | {median['render'] / median['trimesh']:.2f}× | {median['render'] / median['trimesh_raw']:.1f}× "
                f"| {cpu_median['trimesh']:.3f} / {cpu_median['render']:.3f} | {cpu_median['render'] / cpu_median['trimesh']:.2f}× |"
            )


if __name__ == "__main__":
    main()
