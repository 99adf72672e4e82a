"""Extra per-pixel outputs for datasets: surface normals (eye or world space) and object ids.

A second, small render pass (wgsl/extra_outputs.wgsl) into one rgba32float target: normal
in xyz, the segment id in w (1 + the index of the object's part in `segments`; 0 = background).
Every part is drawn opaque: alpha masks and blending of the colour pass do not apply (ids and
normals are of the nearest surface). It shares the Renderer's device and mesh
uploads, and uses the same float32 matrices as the lit pass, so its coverage and depth
order are those of the colour image. Frames are pipelined like render_many: the next
frame is submitted before the previous one is read back.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import TYPE_CHECKING, Iterable, Iterator

import numpy as np
import wgpu
from pyglm import glm

from ..errors import SceneError
from ..scene import Scene, SceneObject
from ..scene.mesh import MeshPart
from .layout import layouts_for
from .pipeline_cache import DEPTH_FORMAT
from .resources import padded_row_bytes, read_buffer
from .shadergen import read_source
from .uniforms import clip_from_eye

if TYPE_CHECKING:  # pragma: no cover
    from .renderer import Renderer

NORMAL_SPACES = ("eye", "world")
_FORMAT = wgpu.TextureFormat.rgba32float


def segments(scene: Scene) -> list[tuple[SceneObject, MeshPart]]:
    """What the ids number: every part of every object, in scene order (objects in order,
    each mesh's parts in file order; a mesh without parts is one part). Id k is entry k-1."""
    return [(obj, part) for obj in scene.objects for part in obj.mesh.parts if part.count > 0]


@dataclass(frozen=True)
class ExtraFrame:
    """normals: (height, width, 3) float32 unit vectors, 0 where nothing was drawn.
    ids: (height, width) uint16, 0 = background, k = segments(scene)[k-1] (object and part)."""

    normals: np.ndarray
    ids: np.ndarray


@dataclass
class _Target:
    width: int
    height: int
    color: object
    color_view: object
    depth_view: object
    readback: object
    row_bytes: int


class ExtraOutputs:
    """Renders normals and ids of scenes on `renderer`'s device (one per Renderer; not
    thread-safe, like the Renderer)."""

    def __init__(self, renderer: "Renderer"):
        self._renderer = renderer
        device = renderer.device
        self._device = device
        source = read_source("extra_outputs.wgsl")
        self._dtype = layouts_for(source).dtype("ExtraUniforms")
        self._group_layout = device.create_bind_group_layout(
            entries=[{"binding": 0, "visibility": wgpu.ShaderStage.VERTEX | wgpu.ShaderStage.FRAGMENT, "buffer": {"type": wgpu.BufferBindingType.uniform}}]
        )
        module = device.create_shader_module(label="extra outputs", code=source)
        vertex_buffers = [
            {"array_stride": 12, "attributes": [{"format": wgpu.VertexFormat.float32x3, "offset": 0, "shader_location": location}]}
            for location in (0, 1)
        ]
        self._pipeline = device.create_render_pipeline(
            label="extra outputs",
            layout=device.create_pipeline_layout(bind_group_layouts=[self._group_layout]),
            vertex={"module": module, "entry_point": "vs_main", "buffers": vertex_buffers},
            primitive={"topology": wgpu.PrimitiveTopology.triangle_list, "cull_mode": wgpu.CullMode.none},
            depth_stencil={"format": DEPTH_FORMAT, "depth_write_enabled": True, "depth_compare": wgpu.CompareFunction.greater},
            multisample={"count": 1},
            fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": _FORMAT}]},
        )
        self._uniforms: dict[int, tuple[object, object]] = {}  # segment id → (buffer, bind group)
        self._free: dict[tuple[int, int], list[_Target]] = {}

    def render(self, scene: Scene, space: str = "eye") -> ExtraFrame:
        return next(iter(self.render_many([scene], space)))

    def render_many(self, scenes: Iterable[Scene], space: str = "eye", in_flight: int = 2) -> Iterator[ExtraFrame]:
        """Normals (in `space`: "eye" or "world") and ids of each scene, in order."""
        if space not in NORMAL_SPACES:
            raise SceneError(f"normals: expected eye or world, got {space!r}")
        pending: deque = deque()
        for scene in scenes:
            if len(pending) >= in_flight:
                yield self._read(pending.popleft())
            slots = self._free.setdefault(scene.size, [])
            target = slots.pop() if slots else self._new_target(*scene.size)
            self._submit(scene, space, target)
            pending.append(target)
        while pending:
            yield self._read(pending.popleft())

    def _new_target(self, width: int, height: int) -> _Target:
        self._renderer._check_size((width, height), "float32")
        usage = wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC
        color = self._device.create_texture(size=(width, height, 1), format=_FORMAT, usage=usage)
        depth = self._device.create_texture(size=(width, height, 1), format=DEPTH_FORMAT, usage=wgpu.TextureUsage.RENDER_ATTACHMENT)
        row_bytes = padded_row_bytes(width, 16)
        readback = self._device.create_buffer(size=row_bytes * height, usage=wgpu.BufferUsage.MAP_READ | wgpu.BufferUsage.COPY_DST)
        return _Target(width, height, color, color.create_view(), depth.create_view(), readback, row_bytes)

    def _object_uniforms(self, index: int, data: np.ndarray):
        entry = self._uniforms.get(index)
        if entry is None:
            buffer = self._device.create_buffer(size=data.nbytes, usage=wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST)
            group = self._device.create_bind_group(
                layout=self._group_layout, entries=[{"binding": 0, "resource": {"buffer": buffer, "offset": 0, "size": data.nbytes}}]
            )
            entry = self._uniforms[index] = (buffer, group)
        self._device.queue.write_buffer(entry[0], 0, data.tobytes())
        return entry[1]

    def _submit(self, scene: Scene, space: str, target: _Target) -> None:
        eye_from_world = scene.camera.view_matrix()
        # The same float64 → float32 values as uniforms.frame_uniforms / object_uniforms.
        clip = clip_from_eye(scene.camera, target.width / target.height).T
        encoder = self._device.create_command_encoder()
        render_pass = encoder.begin_render_pass(
            color_attachments=[
                {"view": target.color_view, "clear_value": (0, 0, 0, 0), "load_op": wgpu.LoadOp.clear, "store_op": wgpu.StoreOp.store}
            ],
            depth_stencil_attachment={
                "view": target.depth_view,
                "depth_clear_value": 0.0,  # reversed Z, like the lit pass
                "depth_load_op": wgpu.LoadOp.clear,
                "depth_store_op": wgpu.StoreOp.discard,
            },
        )
        render_pass.set_pipeline(self._pipeline)
        for segment, (obj, part) in enumerate(segments(scene), 1):
            model = obj.model_matrix()
            model_view = eye_from_world * model
            normal_from_model = glm.inverseTranspose(glm.dmat3(model_view if space == "eye" else model))
            data = np.zeros((), self._dtype)
            data["clip_from_eye"] = clip
            data["eye_from_model"] = np.array(model_view).T
            data["output_normal_from_model"][:, :3] = np.array(normal_from_model).T
            data["object_id"] = segment
            render_pass.set_bind_group(0, self._object_uniforms(segment, data))
            gpu_mesh = self._renderer._gpu_mesh(obj.mesh)
            render_pass.set_vertex_buffer(0, gpu_mesh.positions)
            render_pass.set_vertex_buffer(1, gpu_mesh.normals)
            render_pass.set_index_buffer(gpu_mesh.indices, wgpu.IndexFormat.uint32)
            render_pass.draw_indexed(3 * part.count, 1, 3 * part.first, 0, 0)
        render_pass.end()
        encoder.copy_texture_to_buffer(
            {"texture": target.color},
            {"buffer": target.readback, "bytes_per_row": target.row_bytes, "rows_per_image": target.height},
            (target.width, target.height, 1),
        )
        self._device.queue.submit([encoder.finish()])

    def _read(self, target: _Target) -> ExtraFrame:
        pixels = read_buffer(target.readback, target.row_bytes, target.height, target.width, np.float32, 4)
        self._free.setdefault((target.width, target.height), []).append(target)
        return ExtraFrame(normals=np.ascontiguousarray(pixels[:, :, :3]), ids=pixels[:, :, 3].astype(np.uint16))
