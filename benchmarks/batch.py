"""Batch: a turntable of the bunny through the library, naive loop vs render_many.

    naive                    for scene in views: renderer.render(scene)  (render, wait, read back)
    render_many, one device  renderer.render_many(views, parallel=1)     (pipelined only)
    render_many              renderer.render_many(views)  (pipelined, two lavapipe devices)

Both run in the same process, alternating, after a warm-up; frames per second from the
median pass. The per-thread CPU of one naive frame gives the ceiling any overlap can
reach on this machine: a naive frame's wall time is its serial chain (Python, then the
driver's queue thread binning triangles, then the rasterizer threads), while a perfectly
overlapped one needs total CPU ÷ cores.
"""

from __future__ import annotations

import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wgpu_shading import Renderer
from wgpu_shading.assets.mesh_scene import mesh_scene
from wgpu_shading.scene.view.turntable import turntable

from .measure import progress, thread_breakdown
from .scenes import BUNNY, bunny_scene, torus_scene


@dataclass
class BatchResult:
    scene: str
    frames: int
    size: int
    seconds: dict[str, list[float]]  # mode -> seconds per pass over all frames
    identical: bool
    threads: dict[str, float]  # thread role -> ms CPU per naive frame
    cli_seconds: float | None
    cli_frames_written: int | None
    cpu_seconds: dict[str, list[float]] = field(default_factory=dict)  # mode -> process CPU per pass
    idle: dict[str, list[float]] = field(default_factory=dict)  # mode -> the machine's idle share per pass

    def cores_used(self, mode: str) -> float:
        """Cores this process kept busy on average in `mode` (process CPU ÷ wall time)."""
        return statistics.median(c / w for c, w in zip(self.cpu_seconds.get(mode, []), self.seconds[mode]) if w > 0) if self.cpu_seconds.get(mode) else float("nan")

    def idle_cores(self, mode: str) -> float:
        """Cores of the whole machine left idle during `mode` (by anyone), median pass."""
        shares = self.idle.get(mode)
        return statistics.median(shares) * (os.cpu_count() or 1) if shares else float("nan")

    def fps(self, mode: str) -> float:
        return self.frames / statistics.median(self.seconds[mode])

    @property
    def overlap_ceiling(self) -> float:
        """Best possible speed-up from overlap alone on os.cpu_count() cores."""
        serial = sum(v for k, v in self.threads.items() if k != "rasterizer threads")
        raster = self.threads.get("rasterizer threads", 0.0)
        rasterizers = 2  # llvmpipe starts one rasterizer thread per core (2 here)
        naive = serial + raster / rasterizers
        total = serial + raster
        if total == 0:  # too short a sample for the kernel's 10 ms CPU accounting
            return float("nan")
        return naive / (total / (os.cpu_count() or 1))


def run_batch(
    renderer: Renderer,
    frames: int,
    size: int,
    *,
    passes: int,
    tiny: bool = False,
    thread_frames: int = 5,
    thread_seconds: float = 1.0,
) -> BatchResult:
    """tiny: the smoke run's cube instead of the bunny, in the library and through the CLI
    (not the torus: turning about its axis, its GIF frames would be identical and merged);
    thread_frames / thread_seconds: how long the per-thread CPU is sampled."""
    if tiny:
        cli_input = "builtin:cube"
        scene = mesh_scene(cli_input, (size, size), None)  # as the CLI frames it, like the bunny
        label = f"cube {scene.objects[0].mesh.triangle_count}"
    else:
        scene = bunny_scene(size)
        label, cli_input = "bunny 70K", (str(BUNNY) if BUNNY.exists() else None)
        if scene is None:
            scene, label = torus_scene(size), "torus 10K"
    views = list(turntable(scene, frames))  # made up front: the timings are of rendering only
    progress(f"batch: {frames} views of the {label} at {size}², naive vs render_many")
    naive_frames = [renderer.render(view) for view in views[:6]]
    batch_frames = [frame.color for frame in renderer.render_many(views[:6])]
    identical = all(np.array_equal(a, b) for a, b in zip(naive_frames, batch_frames))

    def naive() -> None:
        for view in views:
            renderer.render(view)

    def batched(parallel: int | None) -> None:
        for _ in renderer.render_many(views, parallel=parallel):
            pass

    modes = {
        "naive": naive,
        "render_many, one device": lambda: batched(1),
        "render_many": lambda: batched(None),
    }
    list(renderer.render_many(views[:4]))  # make the helper device and its pipeline: not timed
    seconds: dict[str, list[float]] = {mode: [] for mode in modes}
    cpu_seconds: dict[str, list[float]] = {mode: [] for mode in modes}
    idle: dict[str, list[float]] = {mode: [] for mode in modes}
    names = list(modes)
    for index in range(passes):
        shift = index % len(names)
        for mode in names[shift:] + names[:shift]:
            machine_before = _machine_jiffies()
            cpu_start, start = time.process_time(), time.perf_counter()
            modes[mode]()
            seconds[mode].append(time.perf_counter() - start)
            cpu_seconds[mode].append(time.process_time() - cpu_start)
            machine_after = _machine_jiffies()
            if machine_before and machine_after and machine_after[1] > machine_before[1]:
                idle[mode].append((machine_after[0] - machine_before[0]) / (machine_after[1] - machine_before[1]))
    cycle = iter(views * 100)
    threads = thread_breakdown(lambda: renderer.render(next(cycle)), min_frames=thread_frames, min_seconds=thread_seconds)
    cli_seconds, written = _cli_turntable(cli_input, label.split()[0], frames, size)
    return BatchResult(label, frames, size, seconds, identical, threads, cli_seconds, written, cpu_seconds, idle)


def _machine_jiffies() -> tuple[int, int] | None:
    """(idle, total) CPU time of the whole machine so far, from /proc/stat (Linux; None
    elsewhere): how much CPU nobody used, to tell whether more overlap had room to run."""
    try:
        with open("/proc/stat") as file:
            fields = [int(value) for value in file.readline().split()[1:]]
    except (OSError, ValueError):
        return None
    return fields[3] + fields[4], sum(fields[:8])  # idle + iowait, all but guest time


def _cli_turntable(source: str | None, name: str, frames: int, size: int) -> tuple[float | None, int | None]:
    """`wgpu-shading turntable` end to end (a GIF, with its encoding), in a new process."""
    if source is None:
        return None, None
    progress(f"batch: wgpu-shading turntable {name} -o spin.gif --frames {frames}")
    cli = shutil.which("wgpu-shading", path=str(Path(sys.executable).parent)) or "wgpu-shading"
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "spin.gif"
        start = time.perf_counter()
        subprocess.run(
            [cli, "turntable", source, "-o", str(out), "--frames", str(frames), "--size", str(size), "-q"],
            check=True,
            timeout=1800,
        )
        seconds = time.perf_counter() - start
        from PIL import Image

        with Image.open(out) as gif:
            written = gif.n_frames
    return seconds, written
