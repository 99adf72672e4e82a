"""The render pass: scene → GPU resources → one frame read back into numpy.

A Renderer owns one wgpu device (the shared default one, or the caller's) and keeps
everything that outlives a frame: pipelines (per feature set), mesh and texture
uploads (per Mesh/Texture object, released when those are garbage-collected), uniform
buffers, render targets and readback buffers (per size and format). Rendering the same
scene again, or the same meshes from another camera, only rewrites uniforms. Every one
of these caches is bounded and evicts the least recently used entry (caches.py).

Threads: a Renderer may be shared. Preparing, submitting and reading back a frame, and
every cache mutation, happen under the renderer's lock (the uniform buffers and render
targets are reused between frames, so two frames must not interleave on one renderer);
validation of the scene and the caller's own work run in parallel. For parallel
rendering, give each thread its own Renderer (docs/reliability.md).
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import Iterable, Iterator

import numpy as np
import wgpu
from pyglm import glm

from ..errors import DeviceError, SceneError
from ..scene import Mesh, Scene, Texture
from ..scene.objects import check_scene_argument
from .caches import (
    BIND_GROUP_CACHE_ENTRIES,
    MESH_CACHE_BYTES,
    MESH_CACHE_ENTRIES,
    TARGET_CACHE_ENTRIES,
    TEXTURE_CACHE_BYTES,
    TEXTURE_CACHE_ENTRIES,
    UNIFORM_CACHE_ENTRIES,
    LruCache,
    ObjectCache,
)
from .device import default_device, lost_device_errors, uses_direct_upload
from .bindings import Binding, BindingPlan
from .features import FeatureSet, object_features
from .material_maps import decodes_srgb
from .pipeline_cache import PipelineCache, PipelineEntry
from .frames_in_flight import render_many
from .resources import (
    GpuMesh,
    GpuTexture,
    Target,
    cached_bind_group,
    check_target_size,
    create_sampler,
    new_target,
    read_buffer,
    uniform_buffer,
    upload_colors,
    upload_mesh,
    upload_texture,
    upload_uvs,
)
from .uniforms import finite_uniform_bytes, frame_uniforms, is_mirrored, linear_depth, object_uniforms


@dataclass(frozen=True)
class Frame:
    """One rendered image.

    color: (height, width, 4) uint8, or float32 in [0, 1] when rendered with float32=True
    depth: (height, width) float64 eye-space distance along the view axis (inf where
           nothing was drawn), when requested
    """

    color: np.ndarray
    depth: np.ndarray | None = None

    def _repr_png_(self) -> bytes:
        """Jupyter (and IPython's display) shows a Frame as its color image."""
        from ..assets.images import png_bytes

        return png_bytes(self.color)



@dataclass
class _Draw:
    """One draw call: one part of one object (a range of its triangles) with its material."""

    entry: PipelineEntry
    draw_index: int  # which object-uniform buffer it uses
    gpu_mesh: GpuMesh
    object_data: np.ndarray
    textures: dict[str, object]  # the plan's *_texture and *_sampler entries: views and samplers
    texture_owner: GpuTexture | None  # whose cache keeps the object bind group (the first texture)
    first_triangle: int
    triangle_count: int



class Renderer:
    """Renders Scenes offscreen. Reuse one Renderer for many frames: it caches pipelines,
    uploads and buffers. Pass `device=` to render on a wgpu device you already have."""

    def __init__(self, device=None, *, adapter: str | None = None):
        if adapter is not None and not isinstance(adapter, str):
            raise DeviceError(f"adapter: expected a selector such as 'lavapipe' or 'gpu', got {type(adapter).__name__}")
        if device is not None and not isinstance(device, wgpu.GPUDevice):
            raise DeviceError(f"device: expected a wgpu.GPUDevice, got {type(device).__name__}")
        self._device = device if device is not None else default_device(adapter)
        # One frame at a time per renderer (reentrant: render_many's helpers and the
        # accuracy study call back into render_frame).
        self._lock = threading.RLock()
        self._pipelines = PipelineCache(self._device)
        # MAP_WRITE on mesh buffers lets create_buffer_with_data write them in place (no
        # staging copy) where the device allows it: see device.DIRECT_UPLOAD_FEATURE.
        self._mesh_usage = wgpu.BufferUsage.MAP_WRITE if uses_direct_upload(self._device) else 0
        self._meshes: ObjectCache[GpuMesh] = ObjectCache(MESH_CACHE_ENTRIES, MESH_CACHE_BYTES, lambda m: m.nbytes)
        self._textures: ObjectCache[GpuTexture] = ObjectCache(TEXTURE_CACHE_ENTRIES, TEXTURE_CACHE_BYTES, lambda t: t.nbytes)
        # The same images stored as rgba8unorm-srgb (colour textures in linear colour space).
        self._srgb_textures: ObjectCache[GpuTexture] = ObjectCache(TEXTURE_CACHE_ENTRIES, TEXTURE_CACHE_BYTES, lambda t: t.nbytes)
        self._targets: LruCache[Target] = LruCache(TARGET_CACHE_ENTRIES)
        self._uniform_buffers: LruCache[list] = LruCache(UNIFORM_CACHE_ENTRIES)  # [buffer, bytes last written]
        self._bind_groups: LruCache[object] = LruCache(BIND_GROUP_CACHE_ENTRIES)
        self._batch_helpers: list[Renderer] = []  # extra devices for render_many (frames_in_flight.py)
        self._samplers: dict[tuple[bool, tuple[str, str]], object] = {}  # (nearest, wrap): at most 18

    def _sampler(self, texture: Texture) -> object:
        """Linear filtering with mipmaps by default; glTF samplers may ask for NEAREST (pixel
        art, palettes, labels) and for clamped or mirrored coordinates."""
        key = (texture.nearest, texture.wrap)
        sampler = self._samplers.get(key)
        if sampler is None:
            sampler = self._samplers[key] = create_sampler(self._device, texture.nearest, texture.wrap)
        return sampler

    @property
    def device(self):
        return self._device

    @property
    def pipeline_count(self) -> int:
        """How many pipelines this renderer has compiled (one per feature set and format)."""
        return len(self._pipelines)

    # ------------------------------------------------------------------ public API

    def render(self, scene: Scene, *, float32: bool = False) -> np.ndarray:
        """The scene's color image: (height, width, 4) uint8, or float32 with float32=True."""
        return self.render_frame(scene, float32=float32).color

    def render_frame(self, scene: Scene, *, float32: bool = False, depth: bool = False) -> Frame:
        """Color and, with depth=True, eye-space depth of one frame. Safe to call from
        several threads: frames on one renderer are serialised (see the module docstring)."""
        check_scene_argument(scene, "render")
        color_format = "float32" if float32 else "rgba8"
        with self._lock, self._device_errors():
            target = self._target(scene.size, color_format, scene.samples)
            self._submit(scene, target, read_depth=depth)
            return self._read(target, scene, read_depth=depth)

    def _device_errors(self):
        """A lost device becomes a DeviceError (and a new Renderer() gets a fresh device)."""
        return lost_device_errors(self._device)

    def render_many(
        self,
        scenes: Iterable[Scene],
        *,
        float32: bool = False,
        depth: bool = False,
        in_flight: int = 2,
        parallel: int | None = None,
    ) -> Iterator[Frame]:
        """Frames of many scenes, in order, each equal to render_frame(scene): faster than a
        loop over render_frame (pipelined; on lavapipe spread over two devices). See frames_in_flight.py."""
        return render_many(self, scenes, float32=float32, depth=depth, in_flight=in_flight, parallel=parallel)

    def _helper_renderers(self, count: int) -> list["Renderer"]:
        """`count` extra renderers, each on its own device of the same adapter, for
        render_many. They belong to this renderer (made on first use, dropped with it)."""
        with self._lock:
            helpers = self._batch_helpers
            while len(helpers) < count:
                # The same features as the primary device (e.g. direct mesh upload on lavapipe).
                helper_device = self._device.adapter.request_device_sync(
                    label=f"wgpu-shading batch helper {len(helpers) + 1}", required_features=sorted(self._device.features)
                )
                helpers.append(Renderer(device=helper_device))
            return helpers[:count]

    def features(self, scene: Scene) -> list[FeatureSet]:
        """The feature set of each object's first part (what `wgpu-shading shader` prints)."""
        return [object_features(scene, obj, index) for index, obj in enumerate(scene.objects)]

    # ------------------------------------------------------------------ resources

    def _check_size(self, size: tuple[int, int], color_format: str, samples: int = 1) -> None:
        check_target_size(self._device, size, color_format, samples)

    def _target(self, size: tuple[int, int], color_format: str, samples: int = 1) -> Target:
        width, height = size
        key = (width, height, color_format, samples)
        target = self._targets.get(key)
        if target is None:
            self._check_size(size, color_format, samples)
            target = self._targets.put(key, self._new_target(width, height, color_format, samples))
        return target

    def _new_target(self, width: int, height: int, color_format: str, samples: int = 1) -> Target:
        return new_target(self._device, width, height, color_format, samples)

    def _gpu_mesh(self, mesh: Mesh, plan: BindingPlan | None = None) -> GpuMesh:
        """The mesh's upload, with the optional attributes `plan` binds (uvs, colors)."""
        gpu_mesh = self._meshes.get(mesh)
        if gpu_mesh is None:
            gpu_mesh = self._meshes.put(mesh, upload_mesh(self._device, mesh, self._mesh_usage))
        if plan is not None and "uvs" in plan:
            upload_uvs(self._device, gpu_mesh, mesh, self._mesh_usage)
        if plan is not None and "colors" in plan:
            upload_colors(self._device, gpu_mesh, mesh, self._mesh_usage)
        return gpu_mesh

    def _gpu_texture(self, texture: Texture, srgb: bool = False) -> GpuTexture:
        cache = self._srgb_textures if srgb else self._textures
        gpu_texture = cache.get(texture)
        if gpu_texture is None:
            gpu_texture = cache.put(texture, upload_texture(self._device, texture, srgb))
        return gpu_texture

    def _uniform_buffer(self, role: str, index: int, data: np.ndarray):
        payload = finite_uniform_bytes(data, "camera and lights" if role == "frame" else f"objects[{index}]")
        return uniform_buffer(self._device, self._uniform_buffers, (role, index, data.nbytes), payload)

    def _group_cache(self, group: tuple[Binding, ...], draw: _Draw) -> LruCache:
        """Who keeps a bind group: the mesh (its storage buffers), else the first texture it
        binds, else the renderer, so a group goes when what it binds is evicted."""
        if any(binding.kind == "storage" for binding in group):
            return draw.gpu_mesh.storage_groups
        if draw.texture_owner is not None and any(binding.kind == "texture" for binding in group):
            return draw.texture_owner.object_groups
        return self._bind_groups

    def _bind_group(self, cache: LruCache, layout, resources: tuple) -> object:
        """A bind group, cached in `cache` (see resources.cached_bind_group)."""
        return cached_bind_group(self._device, cache, layout, resources)

    # ------------------------------------------------------------------ frame

    def _prepare(self, scene: Scene, color_format: str, eye_from_world: glm.dmat4, samples: int = 1) -> list[_Draw]:
        """One draw per (object, part): opaque and masked parts first, in scene order, then
        blended parts back to front (by the eye-space depth of each part's centre), so
        that what lies behind a translucent part is already drawn (SPEC §12)."""
        opaque: list[_Draw] = []
        blended: list[tuple[float, _Draw]] = []
        for index, obj in enumerate(scene.objects):
            model_view = eye_from_world * obj.model_matrix()  # double precision, once per object
            mirrored = is_mirrored(model_view)
            materials = obj.part_materials()
            for part, material in zip(obj.mesh.parts, materials):
                if part.count == 0:
                    continue
                features = object_features(scene, obj, index, material)
                entry = self._pipelines.get(features, color_format, mirrored, samples)
                textures: dict[str, object] = {}
                owner = None
                for sampled in entry.plan.textures:
                    texture = sampled.of_material(material)
                    gpu_texture = self._gpu_texture(texture, sampled.color and decodes_srgb(texture, features))
                    owner = owner or gpu_texture
                    textures[f"{sampled.name}_texture"] = gpu_texture.view
                    textures[f"{sampled.name}_sampler"] = self._sampler(texture)
                draw = _Draw(
                    entry=entry,
                    draw_index=len(opaque) + len(blended),
                    gpu_mesh=self._gpu_mesh(obj.mesh, entry.plan),
                    object_data=object_uniforms(model_view, material, entry.object_dtype),
                    textures=textures,
                    texture_owner=owner,
                    first_triangle=part.first,
                    triangle_count=part.count,
                )
                if features.alpha_mode == "blend":
                    centre = obj.mesh.part_centre(part)
                    depth = (model_view * glm.dvec4(*centre, 1.0)).z  # eye looks along −z: far is very negative
                    blended.append((depth, draw))
                else:
                    opaque.append(draw)
        blended.sort(key=lambda item: item[0])
        return opaque + [draw for _, draw in blended]

    def _submit(self, scene: Scene, target: Target, *, read_depth: bool) -> None:
        device = self._device
        eye_from_world = scene.camera.view_matrix()  # once per frame
        encoder = device.create_command_encoder()
        if target.samples > 1 and read_depth:
            # Multisampled depth cannot be copied out: a single-sample pass first writes the
            # depth that is read (pixel centres, as without MSAA); the MSAA pass then
            # overwrites the color with its resolved, antialiased image.
            single = self._prepare(scene, target.color_format, eye_from_world, 1)
            self._encode_pass(
                encoder, scene, single, eye_from_world, target.color_view, None, target.depth_view, store_depth=True
            )
        if target.samples > 1:
            draws = self._prepare(scene, target.color_format, eye_from_world, target.samples)
            self._encode_pass(
                encoder, scene, draws, eye_from_world, target.msaa_color_view, target.color_view, target.msaa_depth_view
            )
        else:
            draws = self._prepare(scene, target.color_format, eye_from_world)
            self._encode_pass(
                encoder, scene, draws, eye_from_world, target.color_view, None, target.depth_view, store_depth=read_depth
            )
        size = (target.width, target.height, 1)
        encoder.copy_texture_to_buffer(
            {"texture": target.color},
            {"buffer": target.color_readback, "bytes_per_row": target.color_row_bytes, "rows_per_image": target.height},
            size,
        )
        if read_depth:
            encoder.copy_texture_to_buffer(
                {"texture": target.depth, "aspect": wgpu.TextureAspect.depth_only},
                {"buffer": target.depth_readback, "bytes_per_row": target.depth_row_bytes, "rows_per_image": target.height},
                size,
            )
        device.queue.submit([encoder.finish()])

    def _encode_pass(
        self, encoder, scene: Scene, draws: list[_Draw], eye_from_world, color_view, resolve_view, depth_view,
        *, store_depth: bool = False,
    ) -> None:
        """One render pass drawing `draws`; with `resolve_view`, the multisampled color is
        averaged into it at the end of the pass. The depth attachment is kept after the
        pass only with `store_depth` (a frame whose depth is read back): otherwise it is
        scratch, and StoreOp.discard tells the driver it need not write it out."""
        color_attachment = {
            "view": color_view,
            "clear_value": scene.background,
            "load_op": wgpu.LoadOp.clear,
            "store_op": wgpu.StoreOp.store,
        }
        if resolve_view is not None:
            color_attachment["resolve_target"] = resolve_view
        render_pass = encoder.begin_render_pass(
            color_attachments=[color_attachment],
            depth_stencil_attachment={
                "view": depth_view,
                "depth_clear_value": 0.0,  # reversed Z: 0 is the far plane
                "depth_load_op": wgpu.LoadOp.clear,
                "depth_store_op": wgpu.StoreOp.store if store_depth else wgpu.StoreOp.discard,
            },
        )
        if draws:
            # Every object shares the frame uniforms; their layout depends only on scene-level features.
            frame_data = frame_uniforms(scene, draws[0].entry.frame_dtype, eye_from_world)
            uniform_limit = self._device.limits["max-uniform-buffer-binding-size"]
            if frame_data.nbytes > uniform_limit:
                render_pass.end()
                raise SceneError(
                    f"lights: the {len(scene.lights)} lights need {frame_data.nbytes} bytes of uniforms; this adapter "
                    f"binds at most {uniform_limit} (use fewer lights)"
                )
            frame_buffer = self._uniform_buffer("frame", 0, frame_data)
        for draw in draws:
            entry = draw.entry
            assert entry.frame_dtype == frame_data.dtype
            gpu_mesh = draw.gpu_mesh
            render_pass.set_pipeline(entry.pipeline)
            resources = {
                "frame": frame_buffer,
                "object": self._uniform_buffer("object", draw.draw_index, draw.object_data),
                **draw.textures,
            }
            # Every entry of the plan, by name: uniform buffers, textures, else the mesh's buffer.
            for index, (group, layout) in enumerate(zip(entry.plan.groups, entry.bind_group_layouts)):
                bound = tuple(resources[b.name] if b.name in resources else getattr(gpu_mesh, b.name) for b in group)
                render_pass.set_bind_group(index, self._bind_group(self._group_cache(group, draw), layout, bound))
            for vertex_buffer in entry.plan.vertex_buffers:
                render_pass.set_vertex_buffer(vertex_buffer.slot, getattr(gpu_mesh, vertex_buffer.name))
            first_corner, corner_count = 3 * draw.first_triangle, 3 * draw.triangle_count
            if entry.features.frequency == "flat":
                # vertex_index counts from first_vertex: corner k of the whole mesh
                render_pass.draw(corner_count, 1, first_corner, 0)
            else:
                render_pass.set_index_buffer(gpu_mesh.indices, wgpu.IndexFormat.uint32)
                render_pass.draw_indexed(corner_count, 1, first_corner, 0, 0)
        render_pass.end()

    def _read(self, target: Target, scene: Scene, *, read_depth: bool) -> Frame:
        color = read_buffer(
            target.color_readback, target.color_row_bytes, target.height, target.width,
            np.uint8 if target.color_format == "rgba8" else np.float32, 4,
        )
        depth = None
        if read_depth:
            raw = read_buffer(target.depth_readback, target.depth_row_bytes, target.height, target.width, np.float32, 1)
            depth = linear_depth(raw[:, :, 0], scene.camera)
        return Frame(color=color, depth=depth)

