"""Everything one device keeps between frames, for every pass that draws on it.

The colour pass (passes/color.py) and the extra outputs (passes/extra_outputs.py: normals, object
ids) share one DeviceCache per Renderer: the same pipeline cache, mesh and texture
uploads, samplers, uniform buffers, bind groups and render targets, each bounded as
caches.py documents. Not thread-safe by itself: the Renderer uses it under its lock.

Render targets are lent, not shared: `take_target` hands a frame a target no other frame
in flight uses, and `give_back` returns it once the frame is read. Targets given back wait
for reuse in a pool of at most TARGET_CACHE_ENTRIES, least recently returned dropped first.
"""

from __future__ import annotations

from collections import OrderedDict
from itertools import count
from typing import TYPE_CHECKING

import numpy as np
import wgpu

from ...scene import Mesh, Texture
from ..shaders.bindings import BindingPlan
from .caches import (
    BIND_GROUP_CACHE_ENTRIES,
    MESH_CACHE_BYTES,
    MESH_CACHE_ENTRIES,
    TARGET_CACHE_ENTRIES,
    TEXTURE_CACHE_BYTES,
    TEXTURE_CACHE_ENTRIES,
    SHADOW_MAP_CACHE_ENTRIES,
    UNIFORM_CACHE_ENTRIES,
    LruCache,
    ObjectCache,
)
from ..device import uses_direct_upload
from .pipelines import PipelineCache
from ..shaders.uniforms import finite_uniform_bytes
from .bind_groups import cached_bind_group
from .cluster_builds import ClusterBuilds
from .frame_plans import FramePlans
from .mesh_uploads import OPTIONAL_ATTRIBUTES, GpuMesh, asks_for_clusters, upload_attribute, upload_mesh
from .samplers import create_sampler
from .targets import Target, check_target_size, new_target
from .texture_uploads import GpuTexture, upload_texture
from .uniform_buffers import uniform_buffer
from .vertex_order import SharedOrders

if TYPE_CHECKING:  # imported where used: scenes without shadows or strokes never load them
    from .shadow_maps import ShadowMaps
    from .stroke_uploads import GpuPoints, GpuSegments


class DeviceCache:
    """Pipelines, uploads, uniform buffers, bind groups and targets of one wgpu device."""

    def __init__(self, device, shared_orders: SharedOrders | None = None, cluster_builds: ClusterBuilds | None = None):
        self.device = device
        # vertex-cache orders shared with the other devices of one renderer (render_many)
        self.shared_orders = shared_orders
        # the worker that builds clusters off the render thread (shared with those devices too)
        self.cluster_builds = cluster_builds if cluster_builds is not None else ClusterBuilds()
        self.pipelines = PipelineCache(device)
        # MAP_WRITE on mesh buffers lets create_buffer_with_data write them in place (no
        # staging copy) where the device allows it: see device.DIRECT_UPLOAD_FEATURE.
        self._mesh_usage = wgpu.BufferUsage.MAP_WRITE if uses_direct_upload(device) else 0
        self.meshes: ObjectCache[GpuMesh] = ObjectCache(MESH_CACHE_ENTRIES, MESH_CACHE_BYTES, lambda m: m.nbytes)
        # Every texture upload, in whatever format it is stored, is an entry of this one
        # cache (keyed (texture, format)): TEXTURE_CACHE_BYTES bounds them all together.
        self.textures: ObjectCache[GpuTexture] = ObjectCache(TEXTURE_CACHE_ENTRIES, TEXTURE_CACHE_BYTES, lambda t: t.nbytes)
        self.uniform_buffers: LruCache[list] = LruCache(UNIFORM_CACHE_ENTRIES)  # [buffer, bytes last written]
        self.bind_groups: LruCache[object] = LruCache(BIND_GROUP_CACHE_ENTRIES)
        # Made by the first frame with shadows: a scene without them never imports their modules (cold start).
        self._shadow_maps: LruCache[ShadowMaps] | None = None
        self._comparison_sampler = None
        self._samplers: dict[tuple[bool, tuple[str, str]], object] = {}  # (nearest, wrap): at most 18
        self._free_targets: OrderedDict[int, tuple[tuple, Target]] = OrderedDict()  # serial → (key, target)
        self._serial = count()
        # What passes prepared for a scene object, while the caches its draws use are unchanged.
        self.frame_plans: FramePlans = FramePlans(self._upload_changes)

    def _upload_changes(self) -> int:
        """How often the caches a frame plan's draws name have changed (frame_plans.py)."""
        return self.meshes.changes + self.textures.changes + self.pipelines.changes

    # ------------------------------------------------------------------ uploads

    def gpu_mesh(
        self, mesh: Mesh, plan: BindingPlan | None = None, in_order: frozenset[int] = frozenset(), clusters: bool = False,
    ) -> GpuMesh:
        """The mesh's upload, with the optional attributes `plan` binds (uvs, colors).
        `in_order`: parts whose triangles must keep their order (blended ones); an upload
        that reordered one of them is replaced (the same mesh drawn with other materials).
        `clusters`: the frame could leave out clusters turned away: an upload without them
        starts their build when mesh_uploads.asks_for_clusters says so, and is replaced by
        one with them at the first such frame after the build is done (cluster_builds.py).
        An upload replaced for `in_order` starts without clusters and counts its frames anew."""
        gpu_mesh = self.meshes.get(mesh)
        if gpu_mesh is not None and gpu_mesh.order is not None and not in_order <= gpu_mesh.order.in_order:
            in_order = in_order | gpu_mesh.order.in_order
            gpu_mesh = None
        elif gpu_mesh is not None and clusters:
            gpu_mesh = self._with_built_clusters(mesh, gpu_mesh)
        if gpu_mesh is None:
            self.meshes.pop(mesh)  # the old upload (if any) goes before the new one is made
            gpu_mesh = self.meshes.put(mesh, upload_mesh(self.device, mesh, self._mesh_usage, in_order, self.shared_orders))
        if plan is not None:
            for name in OPTIONAL_ATTRIBUTES:
                if name in plan:
                    upload_attribute(self.device, gpu_mesh, mesh, name, self._mesh_usage)
        return gpu_mesh

    def _with_built_clusters(self, mesh: Mesh, gpu_mesh: GpuMesh) -> GpuMesh:
        """The upload this frame draws: `gpu_mesh`, its build of clusters started when it
        asks for them, or the clustered upload that replaces it once that build is done
        (a build that made nothing leaves it as it is, asking no more)."""
        if asks_for_clusters(gpu_mesh, mesh):
            gpu_mesh.cluster_build = self.cluster_builds.start(mesh, gpu_mesh.order.in_order, self.shared_orders)
        build = gpu_mesh.cluster_build
        if build is None or not build.done():
            return gpu_mesh
        gpu_mesh.cluster_build = None
        built = build.result()
        if built is None:
            gpu_mesh.cluster_asks = -1
            return gpu_mesh
        try:
            self.meshes.pop(mesh)  # the old upload goes before the new one is made
            return self.meshes.put(mesh, upload_mesh(self.device, mesh, self._mesh_usage, built.order.in_order, built=built))
        finally:
            built.release()

    def gpu_points(self, mesh: Mesh) -> GpuPoints:
        """The mesh's points (stroke_uploads.py), an entry of the mesh cache beside its triangles."""
        gpu_points = self.meshes.get(mesh, "points")
        if gpu_points is None:
            from .stroke_uploads import upload_points  # imported by the scenes that have points (cold start)

            gpu_points = self.meshes.put(mesh, upload_points(self.device, mesh, self._mesh_usage), "points")
        return gpu_points

    def gpu_segments(self, mesh: Mesh, kind: str) -> GpuSegments:
        """The mesh's line segments (kind "lines") or its triangles' edges ("edges", without
        vertex colours: they are drawn in the edge colour), as stroke_uploads.py uploads them."""
        gpu_segments = self.meshes.get(mesh, kind)
        if gpu_segments is None:
            from .stroke_uploads import upload_segments  # imported by the scenes that have lines or edges

            segments = mesh.line_indices if kind == "lines" else mesh.edge_indices
            upload = upload_segments(self.device, mesh, segments, self._mesh_usage, colors=kind == "lines")
            gpu_segments = self.meshes.put(mesh, upload, kind)
        return gpu_segments

    def gpu_texture(self, texture: Texture, srgb: bool = False) -> GpuTexture:
        """The texture's upload; `srgb`: as rgba8unorm-srgb (material_maps.decodes_srgb).
        Both formats are entries of the one texture cache, keyed by the format."""
        stored_as = "rgba8unorm-srgb" if srgb else "rgba8unorm"
        gpu_texture = self.textures.get(texture, stored_as)
        if gpu_texture is None:
            gpu_texture = self.textures.put(texture, upload_texture(self.device, texture, srgb), stored_as)
        return gpu_texture

    def sampler(self, texture: Texture) -> object:
        """Linear filtering with mipmaps by default; glTF samplers may ask for NEAREST (pixel
        art, palettes, labels) and for clamped or mirrored coordinates."""
        key = (texture.nearest, texture.wrap)
        sampler = self._samplers.get(key)
        if sampler is None:
            sampler = self._samplers[key] = create_sampler(self.device, texture.nearest, texture.wrap)
        return sampler

    def shadow_maps(self, size: int, layers: int) -> ShadowMaps:
        """A depth texture of `layers` shadow maps of size × size texels (gpu/shadow_maps.py)."""
        if self._shadow_maps is None:  # the first frame with shadows (their modules load then: cold start)
            from .shadow_maps import MAX_SHADOW_MAP_BYTES

            self._shadow_maps = LruCache(SHADOW_MAP_CACHE_ENTRIES, MAX_SHADOW_MAP_BYTES, lambda m: m.nbytes)
        maps = self._shadow_maps.get((size, layers))
        if maps is None:
            from .shadow_maps import new_shadow_maps

            maps = self._shadow_maps.put((size, layers), new_shadow_maps(self.device, size, layers))
        return maps

    def comparison_sampler(self) -> object:
        if self._comparison_sampler is None:
            from .shadow_maps import create_comparison_sampler

            self._comparison_sampler = create_comparison_sampler(self.device)
        return self._comparison_sampler

    def uniform_buffer(self, role: str, index: int, data: np.ndarray, where: str) -> object:
        """The uniform buffer for (role, index), holding `data` (`where` names it in errors)."""
        payload = finite_uniform_bytes(data, where)
        return uniform_buffer(self.device, self.uniform_buffers, (role, index, data.nbytes), payload)

    def bind_group(self, cache: LruCache | None, layout, resources: tuple) -> object:
        """A bind group, cached in `cache` (the owner of what it binds; None: this cache's)."""
        return cached_bind_group(self.device, self.bind_groups if cache is None else cache, layout, resources)

    # ------------------------------------------------------------------ targets

    def check_size(self, size: tuple[int, int], color_format: str, samples: int = 1) -> None:
        check_target_size(self.device, size, color_format, samples)

    def take_target(self, size: tuple[int, int], color_format: str, samples: int = 1) -> Target:
        """A target no frame in flight uses: a free one of this kind, or a new one."""
        key = (size[0], size[1], color_format, samples)
        for serial, (free_key, target) in reversed(self._free_targets.items()):
            if free_key == key:
                del self._free_targets[serial]
                return target
        self.check_size(size, color_format, samples)
        return new_target(self.device, size[0], size[1], color_format, samples)

    def give_back(self, target: Target) -> None:
        """A target whose frame has been read, kept for the next frame of its kind."""
        key = (target.width, target.height, target.color_format, target.samples)
        self._free_targets[next(self._serial)] = (key, target)
        while len(self._free_targets) > TARGET_CACHE_ENTRIES:
            self._free_targets.popitem(last=False)

    @property
    def free_target_count(self) -> int:
        return len(self._free_targets)
