"""Many frames: pipelined rendering over one or more devices.

`render_many` renders a sequence of scenes and yields their frames in order, identical
to calling `render_frame` for each. It is faster in two ways. Frames are pipelined: frame
i+1 is already submitted while frame i is copied out of its readback buffer and handed to
the caller, so the driver never waits for Python. And on lavapipe, frames alternate
between two devices: each lavapipe device does its vertex processing and triangle binning
on a single queue thread and only rasterizes on all cores, so one device leaves a core
idle during binning; a second device fills it. Each frame in flight has its own render
target and readback buffers; pipelines, meshes, bind groups and uniform buffers are
shared per device (`queue.write_buffer` is ordered with submissions, so rewriting a
uniform buffer for the next frame cannot change one already submitted).
"""

from __future__ import annotations

import os
from collections import deque
from typing import TYPE_CHECKING, Iterable, Iterator

from ..scene import Scene
from ..scene.objects import check_scene_argument

if TYPE_CHECKING:  # pragma: no cover
    from .renderer import Frame, Renderer


DEFAULT_IN_FLIGHT = 2


def render_many(
    renderer: "Renderer",
    scenes: Iterable[Scene],
    *,
    float32: bool = False,
    depth: bool = False,
    in_flight: int = DEFAULT_IN_FLIGHT,
    parallel: int | None = None,
) -> Iterator["Frame"]:
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
    workers = [renderer, *renderer._helper_renderers(parallel - 1)]
    color_format = "float32" if float32 else "rgba8"
    free_targets: dict[tuple[int, tuple[int, int], int], list] = {}
    pending: deque = deque()  # (worker, scene, target) submitted but not yet read, oldest first

    def read_oldest() -> "Frame":
        worker, scene, target = pending.popleft()
        with worker._lock, worker._device_errors():
            frame = worker._read(target, scene, read_depth=depth)
        free_targets[(id(worker), scene.size, scene.samples)].append(target)
        return frame

    for index, scene in enumerate(scenes):
        check_scene_argument(scene, f"render_many: scene {index}")
        worker = workers[index % len(workers)]
        worker._check_size(scene.size, color_format, scene.samples)
        if len(pending) >= in_flight * len(workers):
            yield read_oldest()
        slots = free_targets.setdefault((id(worker), scene.size, scene.samples), [])
        target = slots.pop() if slots else worker._new_target(scene.size[0], scene.size[1], color_format, scene.samples)
        # Under the worker's lock: another thread's render_frame on the same renderer must
        # not rewrite the uniform buffers between this frame's writes and its submit.
        with worker._lock, worker._device_errors():
            worker._submit(scene, target, read_depth=depth)
        pending.append((worker, scene, target))
    while pending:
        yield read_oldest()


def default_parallelism(renderer: "Renderer") -> int:
    """2 devices on a CPU adapter (lavapipe) with at least 2 cores, else 1.

    Why: lavapipe runs each device's vertex processing and triangle binning on one queue
    thread, and only the rasterization on all cores; a second device bins frame i+1 while
    the first rasterizes frame i. A GPU gains nothing from this (it has one queue, and
    parallelism inside), so it gets one device.
    """
    is_cpu = renderer.device.adapter.info.get("adapter_type") == "CPU"
    return 2 if is_cpu and (os.cpu_count() or 1) >= 2 else 1
