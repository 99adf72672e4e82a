"""Side-by-side timing on a shared, noisy machine.

Every comparison is measured in one process and interleaved: in each round every
contender renders a few frames, and the order of contenders rotates from round to round,
so a burst of load from other processes hits all of them alike. Results are medians;
ratios are ratios of medians. Wall time is the quantity of interest; process CPU time
(all threads) is kept beside it because it is far less disturbed by other processes.
"""

from __future__ import annotations

import os
import statistics
import sys
import time
from dataclasses import dataclass, field
from typing import Callable


@dataclass
class Timing:
    wall: list[float] = field(default_factory=list)  # seconds per frame
    cpu: list[float] = field(default_factory=list)

    @property
    def median_ms(self) -> float:
        return statistics.median(self.wall) * 1000.0 if self.wall else float("nan")

    @property
    def cpu_median_ms(self) -> float:
        return statistics.median(self.cpu) * 1000.0 if self.cpu else float("nan")

    @property
    def spread(self) -> str:
        """Interquartile range of the wall times, as text, to show how noisy a figure is."""
        if len(self.wall) < 4:
            return ""
        q1, _, q3 = statistics.quantiles(self.wall, n=4)
        return f"{q1 * 1000:.1f}–{q3 * 1000:.1f}"


def interleaved(
    contenders: dict[str, Callable[[], object]],
    *,
    rounds: int,
    frames: int | dict[str, int],
    warmup: int = 2,
) -> dict[str, Timing]:
    """Time each callable `frames` times per round for `rounds` rounds, interleaved."""
    for call in contenders.values():
        for _ in range(warmup):
            call()
    timings = {name: Timing() for name in contenders}
    names = list(contenders)
    for round_index in range(rounds):
        shift = round_index % len(names)
        for name in names[shift:] + names[:shift]:
            call = contenders[name]
            count = frames[name] if isinstance(frames, dict) else frames
            for _ in range(count):
                wall, cpu = time.perf_counter(), time.process_time()
                call()
                timings[name].cpu.append(time.process_time() - cpu)
                timings[name].wall.append(time.perf_counter() - wall)
    return timings


def thread_cpu_seconds() -> dict[str, float]:
    """CPU seconds so far of each thread of this process, by a readable role (Linux only)."""
    result: dict[str, float] = {}
    task_dir = "/proc/self/task"
    if not os.path.isdir(task_dir):
        return result
    ticks = os.sysconf("SC_CLK_TCK")
    main = str(os.getpid())
    for tid in os.listdir(task_dir):
        try:
            with open(f"{task_dir}/{tid}/stat") as file:
                fields = file.read().rsplit(")", 1)[1].split()
            with open(f"{task_dir}/{tid}/comm") as file:
                name = file.read().strip()
        except OSError:  # the thread ended meanwhile
            continue
        seconds = (int(fields[11]) + int(fields[12])) / ticks
        role = "main (Python)" if tid == main else name
        result[f"{role}#{tid}"] = seconds
    return result


def _poll_thread_ids() -> set[str]:
    """wgpu-py's per-device poll threads are Python threads; the driver's are not."""
    import threading

    return {str(t.native_id) for t in threading.enumerate() if type(t).__name__ == "PollThread"}


def thread_breakdown(call: Callable[[], object], *, min_frames: int = 5, min_seconds: float = 1.0) -> dict[str, float]:
    """Milliseconds of CPU per frame spent by each thread while `call` runs (long enough for
    the kernel's 10 ms accounting ticks to average out)."""
    before = thread_cpu_seconds()
    start, frames = time.perf_counter(), 0
    while frames < min_frames or time.perf_counter() - start < min_seconds:
        call()
        frames += 1
    after = thread_cpu_seconds()
    pollers = _poll_thread_ids()
    spent: dict[str, float] = {}
    for key, seconds in after.items():
        delta = seconds - before.get(key, 0.0)
        if delta > 0:
            role, tid = key.split("#")
            if tid in pollers:
                role = "wgpu-py poll thread"
            elif role == "python":  # an unnamed native thread: lavapipe's queue thread
                role = "driver queue thread"
            elif role.startswith("llvmpipe-"):
                role = "rasterizer threads"
            spent[role] = spent.get(role, 0.0) + delta * 1000.0 / frames
    return spent


def progress(message: str) -> None:
    print(f"  … {message}", file=sys.stderr, flush=True)


def machine_description() -> str:
    """CPU model, cores, memory, OS, Python, Mesa and wgpu versions (for the docs)."""
    import platform

    cpu = platform.processor() or "?"
    try:
        with open("/proc/cpuinfo") as file:
            for line in file:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    memory = "?"
    try:
        with open("/proc/meminfo") as file:
            kib = int(file.readline().split()[1])
            memory = f"{kib / 2**20:.0f} GiB"
    except (OSError, ValueError, IndexError):
        pass
    os_name = platform.platform()
    try:
        with open("/etc/os-release") as file:
            for line in file:
                if line.startswith("PRETTY_NAME="):
                    os_name = line.split("=", 1)[1].strip().strip('"')
    except OSError:
        pass
    import wgpu

    from wgpu_shading.render.device import default_device, describe_device

    return (
        f"{cpu}, {os.cpu_count()} cores, {memory}; {os_name}; Python {platform.python_version()}; "
        f"wgpu-py {wgpu.__version__}; {describe_device(default_device())}"
    )


@dataclass
class SceneTimings:
    """One scene at one size: each contender's timing (a row of the warm and depth tables)."""

    scene: str
    size: int
    triangles: int
    timings: dict[str, Timing]

    def ratio(self, numerator: str, denominator: str) -> float:
        return self.timings[numerator].median_ms / self.timings[denominator].median_ms
