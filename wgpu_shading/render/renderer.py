"""The frame API: scene → the frame's passes → one frame read back into numpy.

A Renderer owns one wgpu device (the shared default one, or the caller's) and keeps
everything that outlives a frame: pipelines (per PipelineKey), mesh and texture
uploads (per Mesh/Texture object, released when those are garbage-collected), uniform
buffers, render targets and readback buffers (per size and format). Rendering the same
scene again, or the same meshes from another camera, only rewrites uniforms. Every one
of these caches is bounded and evicts the least recently used entry (gpu/caches.py).

The frame API: `submit(scene, ...)` encodes and submits a frame and returns a
PendingFrame at once; `read(pending)` waits for the GPU and returns the Frame. Between the
two the caller may submit more frames (render_many keeps two per device in flight,
frames_in_flight.py). Each pending frame holds its own render targets, lent by the device
cache and given back by `read`. A frame is the list of passes it asks for
(passes/frame.py): the colour pass (passes/color.py) and the normals and ids of datasets
(passes/extra_outputs.py), on the same caches and targets.

Threads: a Renderer may be shared. Submitting and reading back a frame, and every cache
mutation, happen under the renderer's lock (the uniform buffers are reused between
frames, so two frames' uniform writes must not interleave); validation of the scene and
the caller's own work run in parallel. For parallel rendering, give each thread its own
Renderer (docs/reliability.md).
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Iterable, Iterator

import numpy as np
import wgpu

from ..errors import DeviceError
from ..scene import Scene
from ..scene.objects import check_scene_argument
from .device import default_device, lost_device_errors
from .features import FeatureSet
from .stroke_features import part_features
from .frame_memory import keep_frame_memory_mapped
from .frames_in_flight import render_many
from .poll_thread import with_poll_gap
from .gpu.device_cache import DeviceCache
from .gpu.vertex_order import SharedOrders
from .gpu.targets import Target
from .passes.frame import frame_passes
from .passes.frame_context import FrameContext, FramePass


@dataclass(frozen=True)
class Frame:
    """One rendered image.

    color: (height, width, 4) uint8, or float32 in [0, 1] when rendered with float32=True
           (None for a frame submitted with color=False and without depth)
    depth: (height, width) float64 eye-space distance along the view axis (inf where
           nothing was drawn), when requested
    normals: (height, width, 3) float32 unit surface normals (eye or world space, 0 where
           nothing was drawn), when requested (passes/extra_outputs.py)
    ids: (height, width) uint16 object-part ids (0 = background, k = extra_outputs.segments
           (scene)[k-1]), when requested
    """

    color: np.ndarray | None
    depth: np.ndarray | None = None
    normals: np.ndarray | None = None
    ids: np.ndarray | None = None

    def _repr_png_(self) -> bytes:
        """Jupyter (and IPython's display) shows a Frame as its color image."""
        from ..assets.image_writers import png_bytes

        return png_bytes(self.color)


@dataclass(eq=False)
class PendingFrame:
    """A frame submitted to the GPU and not read back yet: give it to Renderer.read, once.
    It holds its render targets until then."""

    renderer: "Renderer"  # the one that submitted it (read on it)
    scene: Scene
    # The frame's passes (passes/frame.py), each with the target lent to it (None: none).
    passes: list[tuple[FramePass, Target | None]]
    done: bool = field(default=False)


class Renderer:
    """Renders Scenes offscreen. Reuse one Renderer for many frames: it caches pipelines,
    uploads and buffers. Pass `device=` to render on a wgpu device you already have."""

    def __init__(self, device=None, *, adapter: str | None = None):
        if adapter is not None and not isinstance(adapter, str):
            raise DeviceError(f"adapter: expected a selector such as 'lavapipe' or 'gpu', got {type(adapter).__name__}")
        if device is not None and not isinstance(device, wgpu.GPUDevice):
            raise DeviceError(f"device: expected a wgpu.GPUDevice, got {type(device).__name__}")
        self._device = device if device is not None else default_device(adapter)
        # The driver's per-frame scratch stays mapped between frames (frame_memory.py).
        keep_frame_memory_mapped()
        # wgpu-py's poll thread pauses after a poll that did not wait, instead of holding
        # up this device's map requests and submits (poll_thread.py).
        with_poll_gap(self._device)
        # One frame at a time per renderer (reentrant: the accuracy study renders from
        # inside its own loops over frames).
        self._lock = threading.RLock()
        self._cache = DeviceCache(self._device)
        self._helpers: list[Renderer] = []  # extra devices for render_many (frames_in_flight.py)

    @property
    def device(self):
        return self._device

    @property
    def device_cache(self) -> DeviceCache:
        """What this renderer keeps between frames (pipelines, mesh and texture uploads,
        render targets; each bounded as render/gpu/caches.py says): for measuring memory and
        compile time, e.g. `device_cache.meshes.nbytes`. Drawing needs none of it."""
        return self._cache

    @property
    def pipeline_count(self) -> int:
        """How many pipelines this renderer keeps compiled (one per PipelineKey: pass, feature set, format, …)."""
        return len(self._cache.pipelines)

    # ------------------------------------------------------------------ one frame

    def render(self, scene: Scene, *, float32: bool = False) -> np.ndarray:
        """The scene's color image: (height, width, 4) uint8, or float32 with float32=True."""
        return self.render_frame(scene, float32=float32).color

    def render_frame(
        self, scene: Scene, *, float32: bool = False, depth: bool = False, normals: str | None = None,
        ids: bool = False, color: bool = True,
    ) -> Frame:
        """Color and, on request, eye-space depth, normals ("eye" or "world") and object ids
        of one frame (see submit). Safe to call from several threads (module docstring)."""
        return self.read(self.submit(scene, float32=float32, depth=depth, normals=normals, ids=ids, color=color))

    def submit(
        self, scene: Scene, *, float32: bool = False, depth: bool = False, normals: str | None = None,
        ids: bool = False, color: bool = True,
    ) -> PendingFrame:
        """Encode and submit one frame; returns without waiting for the GPU. Read it with
        `read(pending)`. `normals` ("eye" or "world") or `ids` add the extra outputs;
        color=False leaves out the colour pass when depth is not asked for either."""
        check_scene_argument(scene, "render")
        if normals is not None:
            from .passes.extra_outputs import check_space  # only frames with normals import that pass

            check_space(normals)
        passes = frame_passes(
            scene, color_format="float32" if float32 else "rgba8", color=color, depth=depth, normals=normals, ids=ids,
        )
        with self._lock, lost_device_errors(self._device):
            cache = self._cache
            lent: list[tuple[FramePass, Target | None]] = []
            try:
                encoder = self._device.create_command_encoder()
                frame = FrameContext.of(scene)
                for render_pass in passes:
                    target = render_pass.take_target(cache, scene)
                    lent.append((render_pass, target))
                    render_pass.encode(cache, encoder, frame, target)
                self._device.queue.submit([encoder.finish()])
            except BaseException:
                self._give_back(lent)
                raise
        return PendingFrame(self, scene, lent)

    def read(self, pending: PendingFrame) -> Frame:
        """Wait for a submitted frame and copy it out (once per PendingFrame)."""
        if pending.renderer is not self:  # submitted on a helper of render_many
            return pending.renderer.read(pending)
        with self._lock, lost_device_errors(self._device):
            if pending.done:
                raise ValueError("this PendingFrame has been read already")
            pending.done = True
            outputs: dict[str, np.ndarray | None] = {"color": None}
            try:
                for render_pass, target in pending.passes:
                    outputs.update(render_pass.read(target, pending.scene))
            finally:
                self._give_back(pending.passes)
        return Frame(**outputs)

    def _give_back(self, lent: list[tuple[FramePass, Target | None]]) -> None:
        for _, target in lent:
            if target is not None:
                self._cache.give_back(target)

    def check_size(self, size: tuple[int, int], *, float32: bool = False, samples: int = 1) -> None:
        """Raise SceneError if this adapter cannot render or read back an output of `size`
        (float32: the float target, which extra outputs also use)."""
        self._cache.check_size(size, "float32" if float32 else "rgba8", samples)

    # ------------------------------------------------------------------ many frames

    def render_many(
        self,
        scenes: Iterable[Scene],
        *,
        float32: bool = False,
        depth: bool = False,
        normals: str | None = None,
        ids: bool = False,
        color: bool = True,
        in_flight: int = 2,
        parallel: int | None = None,
    ) -> Iterator[Frame]:
        """Frames of many scenes, in order, each equal to render_frame(scene): faster than a
        loop over render_frame (pipelined; on lavapipe spread over two devices). See
        frames_in_flight.py."""
        return render_many(
            self, scenes, float32=float32, depth=depth, normals=normals, ids=ids, color=color,
            in_flight=in_flight, parallel=parallel,
        )

    def parallel_renderers(self, count: int) -> list["Renderer"]:
        """This renderer and `count - 1` helpers, each on its own device of the same adapter,
        for render_many. The helpers belong to this renderer (made on first use, reused,
        dropped with it)."""
        with self._lock:
            helpers = self._helpers
            while len(helpers) < count - 1:
                # The same features as the primary device (e.g. direct mesh upload on lavapipe).
                helper_device = self._device.adapter.request_device_sync(
                    label=f"wgpu-shading batch helper {len(helpers) + 1}", required_features=sorted(self._device.features)
                )
                helpers.append(Renderer(device=helper_device))
            if count > 1 and (self._cache.shared_orders is None or self._cache.shared_orders.devices != len(helpers) + 1):
                # One meshoptimizer run per mesh for all the devices (render/gpu/vertex_order.py).
                shared = SharedOrders(len(helpers) + 1)
                for renderer in (self, *helpers):
                    renderer.device_cache.shared_orders = shared
                    # and one worker building clusters for all of them: one big build at a
                    # time (render/gpu/cluster_builds.py)
                    renderer.device_cache.cluster_builds = self._cache.cluster_builds
            return [self, *helpers[: count - 1]]

    def features(self, scene: Scene) -> list[FeatureSet]:
        """The feature set of each object's first part (points and lines: their own, stroke_features.py)."""
        return [part_features(scene, obj, index, obj.mesh.parts[0], obj.part_materials()[0]) for index, obj in enumerate(scene.objects)]
