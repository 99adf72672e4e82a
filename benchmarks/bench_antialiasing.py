"""What antialiasing costs: one frame with 1 sample vs 4 (MSAA) vs 4 with depth read back.

    python benchmarks/bench_antialiasing.py            # the seed's gold torus and the knot sample, 512², 15 rounds
    python benchmarks/bench_antialiasing.py --smoke    # 64², 1 round: does it still run?

Every variant renders the same scene with a warm Renderer (pipelines and targets made
beforehand), interleaved round by round so machine load hits all alike; the table gives
median milliseconds per frame (render + readback into numpy) and the ratio to 1 sample.
"4 + depth" draws a single-sample depth pass first (multisampled depth cannot be copied
out, so the depth read is the pixel centre's, as without MSAA). Results: docs/performance.md.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--smoke", action="store_true", help="64², one round")
    args = parser.parse_args()
    if args.smoke:
        args.size, args.rounds = 64, 1

    from wgpu_shading import Renderer, load_scene
    from wgpu_shading.assets.mesh_scene import mesh_scene

    renderer = Renderer()
    scenes = {
        "gold torus (example:gold_torus_phong.toml)": replace(load_scene("example:gold_torus_phong.toml"), size=(args.size, args.size)),
        "knot sample, default lights": mesh_scene("example:knot.obj", (args.size, args.size), None),
    }
    variants = {
        "1 sample": lambda scene: renderer.render_frame(scene),
        "4 samples": lambda scene: renderer.render_frame(replace(scene, samples=4)),
        "4 samples + depth": lambda scene: renderer.render_frame(replace(scene, samples=4), depth=True),
    }
    print(f"{args.size}×{args.size}, median of {args.rounds} interleaved warm frames, {renderer.device.adapter.summary}\n")
    print("| scene | " + " | ".join(variants) + " | 4 samples / 1 | CPU ms (" + " / ".join(variants) + ") | CPU 4 samples / 1 |")
    print("|---|" + "---:|" * (len(variants) + 3))
    for label, scene in scenes.items():
        for render in variants.values():
            render(scene)  # pipelines and targets made before timing
        times: dict[str, list[float]] = {name: [] for name in variants}
        cpu: dict[str, list[float]] = {name: [] for name in variants}  # this process, every thread
        for _ in range(args.rounds):
            for name, render in variants.items():
                start, start_cpu = time.perf_counter(), time.process_time()
                render(scene)
                times[name].append(time.perf_counter() - start)
                cpu[name].append(time.process_time() - start_cpu)
        medians = {name: statistics.median(values) * 1e3 for name, values in times.items()}
        cpu_medians = {name: statistics.median(values) * 1e3 for name, values in cpu.items()}
        cells = " | ".join(f"{medians[name]:.1f} ms" for name in variants)
        cpu_cells = " / ".join(f"{cpu_medians[name]:.1f}" for name in variants)
        print(f"| {label} | {cells} | {medians['4 samples'] / medians['1 sample']:.2f}× | {cpu_cells} "
              f"| {cpu_medians['4 samples'] / cpu_medians['1 sample']:.2f}× |")


if __name__ == "__main__":
    main()
