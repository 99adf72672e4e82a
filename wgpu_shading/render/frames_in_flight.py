"""Many frames: pipelined rendering over one or more devices.

`render_many` renders a sequence of scenes and yields their frames in order, identical
to calling `render_frame` for each. It is faster in two ways. Frames are pipelined: frame
i+1 is already submitted while frame i is copied out of its readback buffer and handed to
the caller, so the driver never waits for Python. And on lavapipe, frames alternate
between two devices: each lavapipe device does its vertex processing and triangle binning
on a single queue thread and only rasterizes on all cores, so one device leaves a core
idle during binning; a second device fills it. Each frame in flight has its own render
target and readback buffers (Renderer.submit lends them, Renderer.read gives them back);
pipelines, meshes, bind groups and uniform buffers are shared per device
(`queue.write_buffer` is ordered with submissions, so rewriting a uniform buffer for the
next frame cannot change one already submitted). Only the Renderer's public frame API is
used here: `parallel_renderers`, `check_size`, `submit`, `read`.
"""

from __future__ import annotations

import os
from collections import deque
from typing import Iterable, Iterator, Protocol

from ..scene import Scene
from ..scene.objects import check_scene_argument

DEFAULT_IN_FLIGHT = 2


class FrameSource(Protocol):
    """What render_many needs of a Renderer (renderer.py), without importing it."""

    device: object

    def parallel_renderers(self, count: int) -> list: ...
    def check_size(self, size: tuple[int, int], *, float32: bool = False, samples: int = 1) -> None: ...
    def submit(self, scene: Scene, **outputs) -> object: ...
    def read(self, pending) -> object: ...


def render_many(
    renderer: FrameSource,
    scenes: Iterable[Scene],
    *,
    float32: bool = False,
    depth: bool = False,
    normals: str | None = None,
    ids: bool = False,
    color: bool = True,
    in_flight: int = DEFAULT_IN_FLIGHT,
    parallel: int | None = None,
) -> Iterator:
    """Frames of `scenes`, in order, each equal to `renderer.render_frame(scene, ...)`.

    Up to `in_flight` frames per device are submitted before the oldest is read back.
    `parallel` devices take frames in turn (None: `default_parallelism(renderer)`); the
    extra devices are created once per renderer, on its adapter, and keep their own
    pipelines and mesh uploads (each holds one more copy of the meshes it has drawn).
    `scenes` is consumed lazily, so a generator of scenes works and memory stays bounded.
    """
    if in_flight < 1:
        raise ValueError(f"in_flight must be at least 1, got {in_flight}")
    if parallel is None:
        parallel = default_parallelism(renderer)
    if parallel < 1:
        raise ValueError(f"parallel must be at least 1, got {parallel}")
    workers = renderer.parallel_renderers(parallel)
    outputs = {"float32": float32, "depth": depth, "normals": normals, "ids": ids, "color": color}
    pending: deque = deque()  # (worker, PendingFrame) submitted but not yet read, oldest first
    for index, scene in enumerate(scenes):
        check_scene_argument(scene, f"render_many: scene {index}")
        worker = workers[index % len(workers)]
        # Checked before waiting on older frames: a size this adapter cannot render fails here.
        if color or depth:
            worker.check_size(scene.size, float32=float32, samples=scene.samples)
        if normals is not None or ids:
            worker.check_size(scene.size, float32=True)
        if len(pending) >= in_flight * len(workers):
            oldest_worker, oldest = pending.popleft()
            yield oldest_worker.read(oldest)
        pending.append((worker, worker.submit(scene, **outputs)))
    while pending:
        oldest_worker, oldest = pending.popleft()
        yield oldest_worker.read(oldest)


def default_parallelism(renderer: FrameSource) -> int:
    """2 devices on a CPU adapter (lavapipe) with at least 2 cores, else 1.

    Why: lavapipe runs each device's vertex processing and triangle binning on one queue
    thread, and only the rasterization on all cores; a second device bins frame i+1 while
    the first rasterizes frame i. A GPU gains nothing from this (it has one queue, and
    parallelism inside), so it gets one device.
    """
    is_cpu = renderer.device.adapter.info.get("adapter_type") == "CPU"
    return 2 if is_cpu and (os.cpu_count() or 1) >= 2 else 1
