"""The A/B measurements of issue #29's small frame (docs/performance.md, "The small torus
frame and its hand-offs"), as they were run.

    python benchmarks/scripts/ab_issue29.py frame-memory --size 512 --frames 300 --runs 3
    python benchmarks/scripts/ab_issue29.py poll --size 512 --rounds 30
    python benchmarks/scripts/ab_issue29.py frame-memory --smoke   # what the benchmark smoke run does

frame-memory: warm frames of the 10K torus in fresh processes, alternately with the
driver's scratch memory kept mapped (render/frame_memory.py) and given back
(WGPU_SHADING_FRAME_MEMORY=0): a process's malloc thresholds depend on what it freed
before, so each variant gets a fresh process that renders nothing else. Per variant and
run: minor page faults, CPU ms of each thread and of the process, and the median wall ms
per frame, with the load average.

poll: in one process, interleaved rounds of 5 frames each: the map waited for on our own
thread (`map_async`, then wgpu-py's `device._poll_wait()`, i.e. wgpuDevicePoll(wait)) and
through wgpu-py's poll thread (map_sync, what the Renderer does), with moderngl beside them
when it is installed; median wall and process CPU ms per frame. The images are compared
first.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))  # the repository (benchmarks/ and the package)


def _one_process(size: int, frames: int, segments: int) -> dict:
    """Run in the child: warm frames of the torus, measured."""
    from benchmarks.measure import thread_cpu_seconds
    from benchmarks.scenes import torus_scene
    from wgpu_shading import Renderer

    scene = torus_scene(size, segments)
    renderer = Renderer()
    for _ in range(10):
        renderer.render(scene)
    walls = []
    threads_before = thread_cpu_seconds()
    faults_before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    cpu_before = time.process_time()
    for _ in range(frames):
        start = time.perf_counter()
        renderer.render(scene)
        walls.append(time.perf_counter() - start)
    cpu = (time.process_time() - cpu_before) / frames
    faults = (resource.getrusage(resource.RUSAGE_SELF).ru_minflt - faults_before) / frames
    threads: dict[str, float] = {}
    for key, seconds in thread_cpu_seconds().items():
        spent = seconds - threads_before.get(key, 0.0)
        if spent > 0:
            role = key.split("#")[0]
            threads[role] = threads.get(role, 0.0) + spent * 1e3 / frames
    return {"wall_ms": statistics.median(walls) * 1e3, "cpu_ms": cpu * 1e3, "faults": faults, "threads": threads}


def frame_memory(size: int, frames: int, runs: int, segments: int) -> None:
    variants = {"kept mapped": "1", "given back": "0"}
    print(f"torus ({segments}×{segments} segments) at {size}², {frames} warm frames a process; "
          f"load average {os.getloadavg()[0]:.2f} at the start")
    for run in range(runs):
        for name, switch in variants.items():
            environment = {**os.environ, "WGPU_SHADING_FRAME_MEMORY": switch}
            result = subprocess.run(
                [sys.executable, __file__, "child", "--size", str(size), "--frames", str(frames), "--segments", str(segments)],
                capture_output=True, text=True, env=environment, cwd=REPO, check=True,
            )
            measured = json.loads(result.stdout.strip().splitlines()[-1])
            threads = ", ".join(f"{role} {ms:.2f}" for role, ms in sorted(measured["threads"].items(), key=lambda kv: -kv[1]))
            print(f"run {run + 1} {name:12s}: {measured['faults']:6.0f} faults, CPU {measured['cpu_ms']:.2f} ms "
                  f"({threads}), wall median {measured['wall_ms']:.2f} ms; load {os.getloadavg()[0]:.2f}")


def poll(size: int, rounds: int, segments: int) -> None:
    import importlib.util

    import wgpu_shading.render.gpu.readback as readback
    from benchmarks.measure import interleaved
    from benchmarks.scenes import geometry_draw, torus_scene
    from wgpu_shading import Renderer

    scene = torus_scene(size, segments)
    renderer = Renderer()
    device = renderer.device
    through_poll_thread = readback.map_for_reading

    def on_our_thread(buffer) -> None:
        promise = buffer.map_async("READ_NOSYNC")
        device._poll_wait()  # wgpuDevicePoll(wait): the map's callback runs here
        promise.sync_wait()

    def ours_polling() -> object:
        readback.map_for_reading = on_our_thread
        return renderer.render(scene)

    def ours_plain() -> object:
        readback.map_for_reading = through_poll_thread
        return renderer.render(scene)

    if not (ours_polling() == ours_plain()).all():
        raise SystemExit("the two waits gave different images")
    contenders = {"map waited for on our thread": ours_polling, "through wgpu-py's poll thread": ours_plain}
    if importlib.util.find_spec("moderngl") is not None:
        from benchmarks.peers import ModernGLPeer

        contenders["moderngl"] = ModernGLPeer(geometry_draw(scene, "torus")).render
    start_load = os.getloadavg()[0]
    timings = interleaved(contenders, rounds=rounds, frames=5)
    readback.map_for_reading = through_poll_thread
    print(f"torus at {size}², {rounds} interleaved rounds of 5 frames; load average {start_load:.2f} → {os.getloadavg()[0]:.2f}")
    for name, timing in timings.items():
        print(f"  {name:32s} wall {timing.median_ms:.2f} ms, CPU {timing.cpu_median_ms:.2f} ms")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("what", choices=("frame-memory", "poll", "child"))
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--rounds", type=int, default=30)
    parser.add_argument("--segments", type=int, default=72)
    parser.add_argument("--smoke", action="store_true", help="a tiny torus at 32², a few frames, one run")
    args = parser.parse_args(argv)
    if args.smoke:
        args.size, args.frames, args.runs, args.segments, args.rounds = 32, 3, 1, 8, 1
    if args.what == "child":
        print(json.dumps(_one_process(args.size, args.frames, args.segments)))
    elif args.what == "poll":
        poll(args.size, args.rounds, args.segments)
    else:
        frame_memory(args.size, args.frames, args.runs, args.segments)
    return 0


if __name__ == "__main__":
    sys.exit(main())
