"""Draws: what every pass records for one object part, and the one loop that encodes them.

A pass prepares its draws (which pipeline, which uniform values, which textures) and hands
them to `encode_draws`, which sets the pipeline and binds every entry of the pipeline's
binding plan by name (shaders/bindings.py): the pass's shared resources (the frame's
uniform buffer, textures earlier passes made), the draw's own uniform buffer ("object"),
its textures, else the mesh upload's buffer of that name.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import wgpu

from ..gpu.caches import LruCache
from ..gpu.device_cache import DeviceCache
from ..gpu.mesh_uploads import GpuMesh
from ..gpu.pipelines import PipelineEntry
from ..gpu.texture_uploads import GpuTexture
from ..shaders.bindings import Binding

if TYPE_CHECKING:  # a scene without points or lines never loads their uploads (cold start)
    from ..gpu.stroke_uploads import GpuPoints, GpuSegments


@dataclass
class Draw:
    """One draw call: one part of one object (a range of its triangles; for a pipeline that
    draws quads, points or line segments, `first_triangle` and `triangle_count` are the
    range of its instances)."""

    entry: PipelineEntry
    draw_index: int  # which "object" uniform buffer of the pass it uses
    gpu_mesh: GpuMesh | GpuPoints | GpuSegments  # the upload whose buffers the plan names
    object_data: np.ndarray  # the "object" uniform block
    first_triangle: int
    triangle_count: int
    textures: dict[str, object]  # the plan's *_texture and *_sampler entries: views and samplers
    texture_owner: GpuTexture | None = None  # whose cache keeps the object bind group (the first texture)
    # (first triangle, count) ranges drawn instead of the whole part: the clusters a frame
    # keeps (gpu/clusters.py); None draws first_triangle .. + triangle_count
    ranges: list[tuple[int, int]] | None = None


def group_cache(group: tuple[Binding, ...], draw: Draw) -> LruCache | None:
    """Who keeps a bind group: the mesh (its storage buffers), else the first texture it
    binds, else the device cache (None), so a group goes when what it binds is evicted."""
    if any(binding.kind == "storage" for binding in group):
        return draw.gpu_mesh.storage_groups
    if draw.texture_owner is not None and any(binding.kind == "texture" for binding in group):
        return draw.texture_owner.object_groups
    return None


def encode_draws(
    cache: DeviceCache, render_pass, draws: list[Draw], shared: dict[str, object], role: str, where: str,
) -> None:
    """Record `draws` into an open render pass. `shared`: resources every draw binds, by
    name; `role`: the pass's name for its per-draw uniform buffers (passes of one frame must
    not share them: each write is seen by the whole submission); `where`: how an error
    names draw k, with {} for k (e.g. "objects[{}]")."""
    for draw in draws:
        entry = draw.entry
        gpu_mesh = draw.gpu_mesh
        render_pass.set_pipeline(entry.pipeline)
        resources = {
            **shared,
            "object": cache.uniform_buffer(role, draw.draw_index, draw.object_data, where.format(draw.draw_index)),
            **draw.textures,
        }
        # Every entry of the plan, by name: uniform buffers, textures, else the mesh's buffer.
        for index, (group, layout) in enumerate(zip(entry.plan.groups, entry.bind_group_layouts)):
            bound = tuple(resources[b.name] if b.name in resources else getattr(gpu_mesh, b.name) for b in group)
            render_pass.set_bind_group(index, cache.bind_group(group_cache(group, draw), layout, bound))
        for vertex_buffer in entry.plan.vertex_buffers:
            render_pass.set_vertex_buffer(vertex_buffer.slot, getattr(gpu_mesh, vertex_buffer.name))
        if entry.descriptor.quads:  # a strip of four vertices (two triangles) an instance: points, segments
            render_pass.draw(4, draw.triangle_count, 0, draw.first_triangle)
            continue
        if entry.indexed:
            render_pass.set_index_buffer(gpu_mesh.indices, wgpu.IndexFormat.uint32)
        for first, count in draw.ranges if draw.ranges is not None else ((draw.first_triangle, draw.triangle_count),):
            if entry.indexed:
                render_pass.draw_indexed(3 * count, 1, 3 * first, 0, 0)
            else:
                # vertex_index counts from first_vertex: corner k of the whole mesh (flat shading pulls it)
                render_pass.draw(3 * count, 1, 3 * first, 0)
