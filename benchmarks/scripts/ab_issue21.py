"""The two in-process A/B measurements of issue #21 (docs/performance.md), as they were run.

    python benchmarks/scripts/ab_issue21.py vertex-order --mesh bunny --size 512 --rounds 20
    python benchmarks/scripts/ab_issue21.py depth --mesh torus --size 512 --rounds 25
    python benchmarks/scripts/ab_issue21.py both --smoke      # what the benchmark smoke run does

vertex-order: the same scene from two Renderers on one device, one uploading the mesh in
its own order (WGPU_SHADING_VERTEX_ORDER=0, read at upload) and one in vertex-cache order.
depth: colour only; colour + eye depth the way it was read before issue #21 (padded rows
copied out of the mapping, then converted with float64 temporaries); and as it is now.
Every round runs each variant for 3 frames, the order rotating between rounds; the medians
of wall and process CPU time per frame are printed, with the load average.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository (benchmarks/ and the package)


def _old_linear_depth(depth: np.ndarray, camera) -> np.ndarray:
    """uniforms.linear_depth before issue #21 (kept here for the A/B only)."""
    near, far = camera.near, camera.far
    depth = depth.astype(np.float64)
    if camera.orthographic:
        distance = far - depth * (far - near)
    else:
        with np.errstate(divide="ignore"):
            distance = near * far / (depth * (far - near) + near)
    return np.where(depth > 0.0, distance, np.inf)


def _interleaved(variants: dict, rounds: int, frames: int = 3) -> dict[str, tuple[float, float]]:
    for call in variants.values():
        call()
        call()
    wall: dict[str, list[float]] = {name: [] for name in variants}
    cpu: dict[str, list[float]] = {name: [] for name in variants}
    names = list(variants)
    for index in range(rounds):
        shift = index % len(names)
        for name in names[shift:] + names[:shift]:
            start, start_cpu = time.perf_counter(), time.process_time()
            for _ in range(frames):
                variants[name]()
            wall[name].append((time.perf_counter() - start) / frames * 1e3)
            cpu[name].append((time.process_time() - start_cpu) / frames * 1e3)
    return {name: (statistics.median(wall[name]), statistics.median(cpu[name])) for name in names}


def _print(title: str, medians: dict[str, tuple[float, float]]) -> None:
    base_wall, base_cpu = next(iter(medians.values()))
    print(f"{title}\n\n| variant | wall ms | process CPU ms | wall ratio | CPU ratio |\n|---|---:|---:|---:|---:|")
    for name, (wall, cpu) in medians.items():
        print(f"| {name} | {wall:.2f} | {cpu:.2f} | {wall / base_wall:.3f}× | {cpu / base_cpu:.3f}× |")
    print(f"\nload average {tuple(round(x, 2) for x in os.getloadavg())}\n")


def vertex_order(scene, rounds: int) -> None:
    from wgpu_shading import Renderer

    device = Renderer().device
    renderers = {}
    for name, setting in (("own order", "0"), ("vertex-cache order", "1")):
        os.environ["WGPU_SHADING_VERTEX_ORDER"] = setting
        renderers[name] = Renderer(device)
        renderers[name].render(scene)  # the upload happens here, with this setting
    os.environ.pop("WGPU_SHADING_VERTEX_ORDER")
    images = [renderer.render(scene) for renderer in renderers.values()]
    assert np.array_equal(*images), "the reorder changed pixels"
    _print("vertex order (same pixels: yes)", _interleaved({n: (lambda r=r: r.render(scene)) for n, r in renderers.items()}, rounds))


def depth(scene, rounds: int) -> None:
    from wgpu_shading import Renderer
    from wgpu_shading.render.passes import color as color_pass
    from wgpu_shading.render.gpu.readback import read_buffer

    current = color_pass.read_color_frame

    def before(target, camera, *, read_depth):
        color, _ = current(target, camera, read_depth=False)
        raw = read_buffer(target.depth_readback, target.depth_row_bytes, target.height, target.width, np.float32, 1)
        return color, _old_linear_depth(raw[:, :, 0], camera)

    renderer = Renderer()

    def with_depth(read):
        def frame():
            color_pass.read_color_frame = read
            try:
                return renderer.render_frame(scene, depth=True)
            finally:
                color_pass.read_color_frame = current

        return frame

    old, new = with_depth(before)(), with_depth(current)()
    same = np.array_equal(old.depth, new.depth) and np.array_equal(old.color, new.color)
    assert same, "the depth conversion changed values"
    variants = {"colour only": lambda: renderer.render(scene), "colour + depth, before": with_depth(before),
                "colour + depth, now": with_depth(current)}
    _print("depth readback (same values: yes)", _interleaved(variants, rounds))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("which", choices=("vertex-order", "depth", "both"))
    parser.add_argument("--mesh", choices=("torus", "bunny", "sphere"), default="torus")
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--rounds", type=int, default=20)
    parser.add_argument("--smoke", action="store_true", help="a tiny torus at 32², 1 round")
    args = parser.parse_args(argv)

    from benchmarks.scenes import bunny_scene, sphere_scene, torus_scene

    if args.smoke:
        scene, rounds = torus_scene(32, 8), 1
    else:
        scene = {"torus": torus_scene, "bunny": bunny_scene, "sphere": sphere_scene}[args.mesh](args.size)
        if scene is None:
            parser.error("the bunny needs ../shared/models/stanford-bunny.obj")
        rounds = args.rounds
    if args.which in ("vertex-order", "both"):
        vertex_order(scene, rounds)
    if args.which in ("depth", "both"):
        depth(scene, rounds)
    return 0


if __name__ == "__main__":
    sys.exit(main())
