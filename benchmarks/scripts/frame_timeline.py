"""Where one warm frame goes, thread by thread: the hand-offs of issue #29 (docs/performance.md,
"The small torus frame and its hand-offs"), from the kernel's scheduler events.

    perf record -a -e sched:sched_switch -e sched:sched_wakeup -e syscalls:sys_enter_getppid \\
        -o /tmp/frames.data -- python benchmarks/scripts/frame_timeline.py run --size 512 --frames 200
    perf script -i /tmp/frames.data -F tid,cpu,time,event,trace > /tmp/frames.txt
    python benchmarks/scripts/frame_timeline.py parse /tmp/frames.txt

`run` renders warm frames of the 10K torus and marks four moments of each with a getppid()
system call (a tracepoint perf records): the start, the return of `submit`, the map of the
readback buffer, the end. `parse` reads the events of the whole system (-a: a thread
switched in from idle is recorded on the idle side) and splits each frame into: our
Python until `submit` returns; until lavapipe's queue thread first wakes the rasterizer
threads; until its last wake of them (vertex shading and binning, with the clear that
lavapipe rasterizes in a scene of its own); until a rasterizer wakes the queue thread
(the fragments); until our thread has the map (the texture → buffer copy, the fence,
wgpu-py's poll thread, our wake-up); the copy into numpy. Medians and quartiles over the
frames whose events show that shape (those with a foreign task in between are left out).
`run --smoke` renders a few tiny frames (the benchmark smoke run); `parse` needs perf's dump.
"""

from __future__ import annotations

import argparse
import collections
import os
import re
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository (benchmarks/ and the package)

EVENT = re.compile(r"\s*(\d+)\s+\[(\d+)\]\s+([\d.]+):\s+(\S+):\s*(.*)")
WAKEUP = re.compile(r"comm=(\S+) pid=(\d+)")


def run(size: int, frames: int, segments: int, peer: str) -> None:
    import wgpu_shading.render.gpu.readback as readback
    from benchmarks.scenes import geometry_draw, torus_scene
    from wgpu_shading import Renderer

    scene = torus_scene(size, segments)
    renderer = Renderer()
    if peer == "moderngl":
        run_moderngl(geometry_draw(scene, "torus"), frames)
        return
    for _ in range(10):
        renderer.render(scene)
    mapped = readback.map_for_reading

    def marked_map(buffer) -> None:
        mapped(buffer)
        os.getppid()  # mark: the map is ours

    readback.map_for_reading = marked_map
    for _ in range(frames):
        os.getppid()  # mark: start
        pending = renderer.submit(scene)
        os.getppid()  # mark: submit returned
        renderer.read(pending)
        os.getppid()  # mark: end
        time.sleep(0.002)  # frames apart, so that each one's events stand alone
    readback.map_for_reading = mapped
    print(f"{frames} frames of the torus at {size}²; load average {os.getloadavg()[0]:.2f}")


def run_moderngl(draw, frames: int) -> None:
    """The moderngl peer's frame (benchmarks/peers.py), marked the same way: the start,
    after the draw call (llvmpipe's GL shades vertices and bins in it, on this thread),
    after glReadPixels, the end."""
    import numpy as np

    from benchmarks.peers import ModernGLPeer

    gl = ModernGLPeer(draw)
    for _ in range(10):
        gl.render()
    width, height = gl.size
    for _ in range(frames):
        os.getppid()  # mark: start
        gl.program["mv_matrix"].write(np.ascontiguousarray(draw.eye_from_model.T, dtype="f4").tobytes())
        gl.program["proj_matrix"].write(np.ascontiguousarray(draw.gl_projection().T, dtype="f4").tobytes())
        gl.program["norm_matrix"].write(np.ascontiguousarray(np.linalg.inv(draw.eye_from_model), dtype="f4").tobytes())
        gl.fbo.use()
        gl.ctx.enable(gl.ctx.DEPTH_TEST)
        gl.fbo.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
        gl.vao.render(gl.mode)
        os.getppid()  # mark: drawn ("submit returned")
        pixels = gl.fbo.read(components=4)
        os.getppid()  # mark: read ("mapped")
        np.frombuffer(pixels, dtype=np.uint8).reshape(height, width, 4)[::-1]
        os.getppid()  # mark: end
        time.sleep(0.002)
    print(f"{frames} moderngl frames of the torus; load average {os.getloadavg()[0]:.2f}")


SWITCH = re.compile(r"prev_pid=(\d+) prev_prio=\d+ prev_state=\S+ ==> next_comm=\S+ next_pid=(\d+)")


def parse(path: str) -> None:
    events = []
    with open(path) as dump:
        for line in dump:
            match = EVENT.match(line)
            if match:
                events.append((int(match[1]), int(match[2]), float(match[3]) * 1e3, match[4], match[5]))
    ours = collections.Counter(tid for tid, _, _, name, _ in events if name.endswith("getppid")).most_common(1)
    if not ours:
        raise SystemExit(f"{path}: no getppid marks (record with -e syscalls:sys_enter_getppid)")
    main = ours[0][0]
    wakes = [(tid, t, int(m[2]), m[1]) for tid, _, t, name, trace in events
             if name.endswith("sched_wakeup") and (m := WAKEUP.search(trace))]
    rasterizers = {woken for _, _, woken, comm in wakes if comm.startswith("llvmpipe")}
    # Who hands scenes to the rasterizers: lavapipe's queue thread (ours), the caller's thread (GL).
    queue = collections.Counter(tid for tid, _, woken, _ in wakes if woken in rasterizers and tid not in rasterizers and tid != 0).most_common(1)[0][0]
    runs: dict[int, list[tuple[float, float]]] = collections.defaultdict(list)
    on_cpu: dict[int, tuple[int, float]] = {}
    for _, cpu, t, name, trace in events:
        if name.endswith("sched_switch") and (match := SWITCH.search(trace)):
            previous, following = int(match[1]), int(match[2])
            if cpu in on_cpu and on_cpu[cpu][0] == previous:
                runs[previous].append((on_cpu[cpu][1], t))
            on_cpu[cpu] = (following, t)

    def busy(tids, start: float, end: float) -> float:
        return sum(max(0.0, min(b, end) - max(a, start)) for tid in tids for a, b in runs[tid])

    marks = [t for tid, _, t, name, _ in events if name.endswith("getppid") and tid == main]
    rows = []
    for first in range(0, len(marks) - 3, 4):
        start, submitted, mapped, end = marks[first:first + 4]
        done = [t for tid, t, woken, _ in wakes if submitted <= t <= mapped and tid in rasterizers and woken == queue]
        if not done:
            continue
        rows.append({
            "until submit returns (GL: the draw call)": submitted - start,
            "  of it, that thread's CPU": busy([main], start, submitted),
            "until the rasterizers' last wake of the queue thread": done[-1] - submitted,
            "  of it, queue thread's CPU (vertices, binning)": busy([queue], submitted, done[-1]) if queue != main else 0.0,
            "  of it, rasterizers' CPU (both threads)": busy(rasterizers, submitted, done[-1]),
            "until the map is ours (copy, fence, poll, wake)": mapped - done[-1],
            "copy into numpy (GL: the read's tail)": end - mapped,
            "the whole frame": end - start,
        })
    if len(rows) < 4:
        raise SystemExit(f"{path}: {len(rows)} frames with the expected events")
    print(f"{len(rows)} of {len(marks) // 4} frames; ms: median (quartiles)")
    for phase in rows[0]:
        values = [row[phase] for row in rows]
        low, _, high = statistics.quantiles(values, n=4)
        print(f"  {phase:54s} {statistics.median(values):6.3f}  ({low:.3f}–{high:.3f})")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("what", choices=("run", "parse"))
    parser.add_argument("dump", nargs="?", help="parse: the output of perf script")
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--frames", type=int, default=200)
    parser.add_argument("--segments", type=int, default=72)
    parser.add_argument("--peer", choices=("ours", "moderngl"), default="ours",
                        help="run: moderngl's frame instead (its own thread bins: the queue thread's phases are its own)")
    parser.add_argument("--smoke", action="store_true", help="run: a tiny torus at 32², a few frames")
    args = parser.parse_args(argv)
    if args.what == "parse":
        if not args.dump:
            parser.error("parse needs the output of perf script")
        parse(args.dump)
    elif args.smoke:
        run(32, 3, 8, "ours")
    else:
        run(args.size, args.frames, args.segments, args.peer)
    return 0


if __name__ == "__main__":
    sys.exit(main())
