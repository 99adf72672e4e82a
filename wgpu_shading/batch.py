"""Many frames: pipelined rendering, turntable scenes, animation files.

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

import math
import os
import queue
import threading
from collections import deque
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Iterable, Iterator

import numpy as np

from .errors import SceneError
from .scene import DirectionalLight, PositionalLight, Scene, SpotLight, output_path

if TYPE_CHECKING:  # pragma: no cover
    from .renderer import Frame, Renderer

DEFAULT_IN_FLIGHT = 2
ANIMATION_SUFFIXES = (".gif", ".mp4")


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
    workers = [renderer, *_helpers(renderer, parallel - 1)]
    color_format = "float32" if float32 else "rgba8"
    free_targets: dict[tuple[int, tuple[int, int]], list] = {}
    pending: deque = deque()  # (worker, scene, target) submitted but not yet read, oldest first

    def read_oldest() -> "Frame":
        worker, scene, target = pending.popleft()
        frame = worker._read(target, scene, read_depth=depth)
        free_targets[(id(worker), scene.size)].append(target)
        return frame

    for index, scene in enumerate(scenes):
        worker = workers[index % len(workers)]
        worker._check_size(scene.size, color_format)
        if len(pending) >= in_flight * len(workers):
            yield read_oldest()
        slots = free_targets.setdefault((id(worker), scene.size), [])
        target = slots.pop() if slots else worker._new_target(scene.size[0], scene.size[1], color_format)
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


def _helpers(renderer: "Renderer", count: int) -> list["Renderer"]:
    """`count` extra renderers, each on its own device of the same adapter. They belong to
    `renderer` (made on first use, kept with it, dropped with it)."""
    from .renderer import Renderer

    helpers = renderer._batch_helpers
    device = renderer.device
    while len(helpers) < count:
        # The same features as the primary device (e.g. direct mesh upload on lavapipe).
        helper_device = device.adapter.request_device_sync(
            label=f"wgpu-shading batch helper {len(helpers) + 1}", required_features=sorted(device.features)
        )
        helpers.append(Renderer(device=helper_device))
    return helpers[:count]


# --------------------------------------------------------------------------- turntable


def _rotation_about(axis: np.ndarray, degrees: float) -> np.ndarray:
    """Right-handed rotation matrix (float64) about a unit axis."""
    x, y, z = axis
    angle = math.radians(degrees)
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return np.array(
        [
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
        ]
    )


def spun(scene: Scene, degrees: float) -> Scene:
    """The scene as if every object were turned by `degrees` about the camera's up axis
    through the camera target (a turntable), with camera and lights left where they are.

    Implemented as the equivalent rigid motion of the viewer: camera and lights orbit by
    −degrees. Objects keep their own transforms, so this works for any scene.
    """
    camera = scene.camera
    axis = np.asarray(camera.up, dtype=np.float64)
    axis = axis / np.linalg.norm(axis)
    rotation = _rotation_about(axis, -degrees)
    pivot = np.asarray(camera.target, dtype=np.float64)

    def point(p) -> tuple[float, float, float]:
        return tuple(float(v) for v in rotation @ (np.asarray(p) - pivot) + pivot)

    def direction(d) -> tuple[float, float, float]:
        return tuple(float(v) for v in rotation @ np.asarray(d))

    lights = []
    for light in scene.lights:
        if isinstance(light, DirectionalLight):
            lights.append(replace(light, direction=direction(light.direction)))
        elif isinstance(light, SpotLight):
            lights.append(replace(light, position=point(light.position), direction=direction(light.direction)))
        elif isinstance(light, PositionalLight):
            lights.append(replace(light, position=point(light.position)))
        else:  # pragma: no cover - Scene validates its lights
            raise SceneError(f"cannot turn a {type(light).__name__}")
    return replace(scene, camera=replace(camera, eye=point(camera.eye)), lights=tuple(lights))


def turntable(scene: Scene, frames: int, degrees: float = 360.0) -> list[Scene]:
    """`frames` views of the scene turning by `degrees` in equal steps (the first is the
    scene itself; a full turn does not repeat the first view at the end, so it loops)."""
    if frames < 1:
        raise SceneError(f"turntable: frames must be at least 1, got {frames}")
    return [scene if i == 0 else spun(scene, degrees * i / frames) for i in range(frames)]


# --------------------------------------------------------------------------- animation files


def check_animation_path(path: Path) -> None:
    """One-line errors for what write_animation cannot do, before any rendering starts."""
    output_path(path, ANIMATION_SUFFIXES)
    if path.suffix.lower() == ".mp4":
        try:
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            raise SceneError(
                f"output {str(path)!r}: writing MP4 needs imageio-ffmpeg "
                "(pip install 'wgpu-shading[video]'), or write a .gif"
            ) from None


def write_animation(
    path: str | os.PathLike[str],
    frames: Iterable[np.ndarray],
    *,
    fps: float = 30.0,
    progress: Callable[[int], None] | None = None,
) -> int:
    """Write RGBA or RGB uint8 frames to an animated GIF (looping) or an MP4 (H.264).

    Frames are encoded on a worker thread while the next ones are rendered: GIF palette
    quantization (Pillow) and the H.264 encoder (a separate ffmpeg process) both run
    outside the GIL. Returns the number of frames written.
    """
    path = Path(path)
    check_animation_path(path)
    encoder = _GifEncoder(path, fps) if path.suffix.lower() == ".gif" else _Mp4Encoder(path, fps)
    work: queue.Queue = queue.Queue(maxsize=4)  # bounded: rendering may run ahead only a little
    failure: list[BaseException] = []

    def worker() -> None:
        while (frame := work.get()) is not None:
            if not failure:
                try:
                    encoder.add(frame)
                except BaseException as error:  # reported on the main thread
                    failure.append(error)

    thread = threading.Thread(target=worker, name="wgpu-shading-encoder", daemon=True)
    thread.start()
    count = 0
    try:
        for frame in frames:
            if failure:
                break
            work.put(np.asarray(frame)[:, :, :3])  # no alpha: GIF and H.264 are opaque
            count += 1
            if progress is not None:
                progress(count)
    finally:
        work.put(None)
        thread.join()
    if failure:
        raise failure[0]
    encoder.close()
    return count


class _GifEncoder:
    def __init__(self, path: Path, fps: float):
        self.path = path
        self.duration_ms = 1000.0 / fps
        self.images: list = []

    def add(self, rgb: np.ndarray) -> None:
        from PIL import Image

        # An adaptive palette per frame (fast octree): smooth shading keeps its gradients,
        # unlike a fixed web palette.
        self.images.append(Image.fromarray(np.ascontiguousarray(rgb)).quantize(256, method=Image.Quantize.FASTOCTREE))

    def close(self) -> None:
        if not self.images:
            raise SceneError(f"{self.path}: no frames to write")
        first, *rest = self.images
        first.save(self.path, save_all=True, append_images=rest, duration=self.duration_ms, loop=0, optimize=False)


class _Mp4Encoder:
    def __init__(self, path: Path, fps: float):
        import imageio.v2 as imageio

        # yuv420p needs even sides; ffmpeg pads odd ones (macro_block_size=2) instead of scaling.
        self.writer = imageio.get_writer(
            path, format="FFMPEG", mode="I", fps=fps, codec="libx264", quality=8, macro_block_size=2
        )

    def add(self, rgb: np.ndarray) -> None:
        self.writer.append_data(rgb)

    def close(self) -> None:
        self.writer.close()
