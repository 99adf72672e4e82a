"""Frame time of the live viewer (`wgpu-shading view`): an orbiting drag over the Stanford
bunny at 800×600, each frame = one pointer move + scene update + render + readback +
present of the bitmap to a rendercanvas canvas.

    python benchmarks/bench_live.py                 # the bunny (/work/shared/models or --mesh), 800×600
    python benchmarks/bench_live.py --smoke         # builtin torus, 64×48, 3 frames: does it still run?
    xvfb-run -a python benchmarks/bench_live.py --window   # also through a real glfw window
    python benchmarks/bench_live.py --pause-only    # only the closed sphere's first frames (below)

The offscreen canvas measures what the viewer itself costs per frame; --window adds
rendercanvas's upload of the bitmap into a glfw window's swap chain (a second wgpu device on
lavapipe). Also timed: the frame after a key that changes the shading frequency (its
pipeline compiled once, then cached). Results: docs/viewer.md.

Then the first frames of a big closed mesh (the 1.3M-triangle sphere at 512², --sphere),
the same drag in a view of its own: the frames during which its clusters turned away are
built (render/gpu/cluster_builds.py) are the ones a user would feel, so the worst frame
is reported beside the median, with the CPU time (every thread of the process) of each.
And how much of such a build holds the GIL: how long a thread waking every millisecond
waits for it while the sphere's clusters are built on the worker, against without a build.
Results: docs/performance.md, "the vertex-bound sphere".
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

BUNNY = Path(os.environ.get("WGPU_SHADING_MODELS", "/work/shared/models")) / "stanford-bunny.obj"


def drag_frames(view, canvas, frames: int, draw) -> tuple[list[float], list[float]]:
    """Seconds per frame of a left drag across the window, one pointer move per frame, and
    the CPU seconds (this process, every thread) of each frame."""
    width, height = view.size()
    view.handle_event({"event_type": "pointer_down", "x": width / 4, "y": height / 2, "button": 1})
    times, cpu = [], []
    for index in range(frames):
        start, start_cpu = time.perf_counter(), time.process_time()
        view.handle_event({"event_type": "pointer_move", "x": width / 4 + 3 * (index + 1), "y": height / 2 + (index % 5)})
        draw()
        times.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    view.handle_event({"event_type": "pointer_up", "x": 0, "y": 0, "button": 1})
    return times, cpu


def sphere_first_frames(offscreen, renderer, triangles: int, size: tuple[int, int], frames: int) -> None:
    """The first `frames` frames of a drag over a closed UV sphere of about `triangles`
    triangles, opened in a view of its own: print the median and the worst frame (wall and
    CPU) and the frame numbers of the slowest."""
    from wgpu_shading.live.canvas import attach
    from wgpu_shading.live.session import LiveView
    from wgpu_shading.scene.geometry.builtins import sphere_for_triangles
    from wgpu_shading.scene.view.options import ViewOptions

    mesh = sphere_for_triangles(triangles)
    name = mesh.name.removeprefix("builtin:sphere(").rstrip(")")
    source = "builtin:sphere?slices={}&stacks={}".format(*name.split("x"))
    view = LiveView(source, ViewOptions(size=size), renderer=renderer, out=lambda text: None)
    canvas = offscreen.RenderCanvas(size=view.size())
    attach(view, canvas)
    canvas.draw()  # the upload and the pipeline: not a frame of the drag
    times, cpu = drag_frames(view, canvas, frames, canvas.draw)
    slowest = sorted(range(frames), key=lambda k: -times[k])[:3]
    print(f"\n{view.scenes()[0].objects[0].mesh.triangle_count:,}-triangle sphere ({source}) at {size[0]}×{size[1]}, "
          f"its first {frames} frames of a drag, load average {os.getloadavg()[0]:.1f}:")
    print(f"  wall ms: median {statistics.median(times) * 1e3:.0f}, worst {max(times) * 1e3:.0f}, all {sum(times):.1f} s "
          f"(frames {', '.join(str(k + 1) for k in slowest)}: {', '.join(f'{times[k] * 1e3:.0f}' for k in slowest)})")
    print(f"  CPU ms (every thread): median {statistics.median(cpu) * 1e3:.0f}, worst {max(cpu) * 1e3:.0f}")
    gil_waits_during_a_build(sphere_for_triangles(triangles))


def gil_waits_during_a_build(mesh) -> None:
    """Print how long a thread that sleeps 1 ms at a time waits beyond it (for the GIL, and
    for a core) while the clusters of `mesh` (a new object: nothing cached) are built on a
    renderer's worker, and for as long without a build."""
    from wgpu_shading.render.gpu.cluster_builds import ClusterBuilds

    def waits(until) -> list[float]:
        found = []
        while not until():
            start = time.perf_counter()
            time.sleep(0.001)
            found.append(time.perf_counter() - start - 0.001)
        return found

    start, cpu = time.perf_counter(), time.process_time()
    build = ClusterBuilds(workers=1).start(mesh, frozenset(), None)
    during = waits(build.done)
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    assert build.result() is not None, "the sphere got no clusters"
    until = time.perf_counter() + wall
    alone = waits(lambda: time.perf_counter() > until)
    print(f"  its clusters built on the worker alone: {wall:.2f} s wall, {cpu:.2f} s CPU; a thread waking every ms waited")
    for label, found in (("during the build", during), ("without it", alone)):
        print(f"    {label}: median {statistics.median(found) * 1e3:.2f} ms, worst {max(found) * 1e3:.1f} ms, "
              f"{sum(found):.2f} s in all over {len(found)} wakes")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mesh", default=str(BUNNY))
    parser.add_argument("--size", default="800x600")
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--window", action="store_true", help="also time a real glfw window (needs a display)")
    parser.add_argument("--smoke", action="store_true", help="builtin torus, 64×48, 3 frames")
    parser.add_argument("--sphere", type=int, default=1_300_000, help="triangles of the closed sphere whose first frames are timed (0: none)")
    parser.add_argument("--sphere-size", default="512x512")
    parser.add_argument("--sphere-frames", type=int, default=60)
    parser.add_argument("--pause-only", action="store_true", help="only the closed sphere's first frames")
    args = parser.parse_args()
    if args.smoke:
        args.mesh, args.size, args.frames = "builtin:torus", "64x48", 3
        args.sphere, args.sphere_size, args.sphere_frames = 20_000, "64x48", 20  # (clusters from 16K triangles)
    elif not args.pause_only and not Path(args.mesh).exists():
        print(f"skipped: {args.mesh} not found (pass --mesh)")
        return 0

    try:
        import rendercanvas.offscreen as offscreen
    except ImportError:
        print("skipped: rendercanvas is not installed (the [view] extra)")
        return 0

    from wgpu_shading import Renderer
    from wgpu_shading.live.canvas import attach
    from wgpu_shading.live.session import LiveView
    from wgpu_shading.scene.view.options import ViewOptions

    renderer = Renderer()
    if args.pause_only:
        sphere_first_frames(offscreen, renderer, args.sphere, _size(args.sphere_size), args.sphere_frames)
        return 0
    width, height = _size(args.size)
    started = time.perf_counter()
    view = LiveView(args.mesh, ViewOptions(size=(width, height)), renderer=renderer, out=lambda text: None)
    canvas = offscreen.RenderCanvas(size=view.size())
    attach(view, canvas)
    canvas.draw()
    opened = time.perf_counter() - started
    triangles = view.scenes()[0].objects[0].mesh.triangle_count
    print(f"{Path(args.mesh).name}: {triangles:,} triangles, {width}×{height}, {renderer.device.adapter.summary}, "
          f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}")
    print(f"open (read the mesh, first frame, pipeline): {opened:.2f} s\n")
    rows = []
    rows.append(("orbit drag, offscreen canvas", *drag_frames(view, canvas, args.frames, canvas.draw)))
    # The floor: the same scene rendered and read back with nothing around it, interleaved
    # with nothing (the machine's load hits both runs alike only roughly: compare medians).
    scene = view.scenes()[0]
    floor = []
    floor_cpu = time.process_time()
    for _ in range(args.frames):
        start = time.perf_counter()
        renderer.render_frame(scene)
        floor.append(time.perf_counter() - start)
    rows.append(("Renderer.render_frame alone (the floor)", floor, [time.process_time() - floor_cpu]))
    start = time.perf_counter()
    view.press("f")  # flat: a pipeline not compiled yet
    canvas.draw()
    first_flat = time.perf_counter() - start
    for _ in range(2):
        view.press("f")
        canvas.draw()
    start = time.perf_counter()
    view.press("f")  # flat again: from the cache
    canvas.draw()
    cached_flat = time.perf_counter() - start
    view.press("f")
    view.press("f")  # back to Phong
    if args.window:
        from wgpu_shading.live.window import glfw_backend, open_window

        backend = glfw_backend()
        window = open_window(view)

        def window_draw():
            window.force_draw()
            backend.poll_glfw_briefly(0.0)

        window_draw()
        rows.append(("orbit drag, glfw window", *drag_frames(view, window, args.frames, window_draw)))
        window.close()
    print("| frames | median ms | p90 ms | worst ms | frames/s (median) | CPU ms a frame (mean) |")
    print("|---|---:|---:|---:|---:|---:|")
    for label, values, cpu in rows:
        median = statistics.median(values)
        p90 = sorted(values)[int(0.9 * (len(values) - 1))]
        print(f"| {label} ({len(values)}) | {median * 1e3:.1f} | {p90 * 1e3:.1f} | {max(values) * 1e3:.1f} | {1 / median:.1f} "
              f"| {sum(cpu) / len(values) * 1e3:.1f} |")
    print(f"\nkey F to a new frequency: {first_flat * 1e3:.0f} ms the first time (pipeline compiled), "
          f"{cached_flat * 1e3:.0f} ms later (cached); pipelines: {renderer.pipeline_count}")
    if args.sphere:
        sphere_first_frames(offscreen, renderer, args.sphere, _size(args.sphere_size), args.sphere_frames)
    return 0


def _size(text: str) -> tuple[int, int]:
    width, height = (int(v) for v in text.split("x"))
    return width, height


if __name__ == "__main__":
    sys.exit(main())
