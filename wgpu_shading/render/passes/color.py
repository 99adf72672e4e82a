"""The colour pass: a scene's draws (one per object part, with the pipeline, uploads and
textures its binding plan names), encoded into a render target of the device cache.

The renderer calls `encode_color_frame` under its lock and `read_color_frame` once the
GPU is done; every resource comes from the DeviceCache (device_cache.py), by name.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu
from pyglm import glm

from ...errors import SceneError
from ...scene import Camera, Scene
from ..shaders.bindings import Binding
from ..gpu.caches import LruCache
from ..gpu.device_cache import DeviceCache
from ..features import object_features
from ..shaders.material_maps import decodes_srgb
from ..gpu.pipeline_cache import PipelineEntry
from ..gpu.mesh_uploads import GpuMesh
from ..gpu.readback import read_buffer, read_mapped_rows
from ..gpu.targets import Target
from ..gpu.texture_uploads import GpuTexture
from ..shaders.uniforms import frame_uniforms, is_mirrored, linear_depth, object_uniforms


@dataclass
class Draw:
    """One draw call: one part of one object (a range of its triangles) with its material."""

    entry: PipelineEntry
    draw_index: int  # which object-uniform buffer it uses
    gpu_mesh: GpuMesh
    object_data: np.ndarray
    textures: dict[str, object]  # the plan's *_texture and *_sampler entries: views and samplers
    texture_owner: GpuTexture | None  # whose cache keeps the object bind group (the first texture)
    first_triangle: int
    triangle_count: int


def group_cache(group: tuple[Binding, ...], draw: Draw) -> LruCache | None:
    """Who keeps a bind group: the mesh (its storage buffers), else the first texture it
    binds, else the device cache (None), so a group goes when what it binds is evicted."""
    if any(binding.kind == "storage" for binding in group):
        return draw.gpu_mesh.storage_groups
    if draw.texture_owner is not None and any(binding.kind == "texture" for binding in group):
        return draw.texture_owner.object_groups
    return None


def prepare_draws(cache: DeviceCache, scene: Scene, color_format: str, eye_from_world: glm.dmat4, samples: int = 1) -> list[Draw]:
    """One draw per (object, part): opaque and masked parts first, in scene order, then
    blended parts back to front (by the eye-space depth of each part's centre), so
    that what lies behind a translucent part is already drawn (docs/conventions.md)."""
    opaque: list[Draw] = []
    blended: list[tuple[float, Draw]] = []
    for index, obj in enumerate(scene.objects):
        model_view = eye_from_world * glm.dmat4(obj.world_from_model())  # double precision, once per object
        mirrored = is_mirrored(model_view)
        materials = obj.part_materials()
        # Blended parts keep their triangle order in the upload (they blend in index order).
        blended_parts = frozenset(k for k, m in enumerate(materials) if m.alpha_mode == "blend")
        for part, material in zip(obj.mesh.parts, materials):
            if part.count == 0:
                continue
            features = object_features(scene, obj, index, material)
            entry = cache.pipelines.get(features, color_format, mirrored, samples)
            textures: dict[str, object] = {}
            owner = None
            for sampled in entry.plan.textures:
                texture = sampled.of_material(material)
                gpu_texture = cache.gpu_texture(texture, sampled.color and decodes_srgb(texture, features))
                owner = owner or gpu_texture
                textures[f"{sampled.name}_texture"] = gpu_texture.view
                textures[f"{sampled.name}_sampler"] = cache.sampler(texture)
            draw = Draw(
                entry=entry,
                draw_index=len(opaque) + len(blended),
                gpu_mesh=cache.gpu_mesh(obj.mesh, entry.plan, blended_parts),
                object_data=object_uniforms(model_view, material, entry.object_dtype, scene),
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


def encode_color_frame(cache: DeviceCache, encoder, scene: Scene, target: Target, *, read_depth: bool) -> None:
    """The colour pass of `scene` into `target`, and the copies into its readback buffers."""
    eye_from_world = glm.dmat4(scene.camera.eye_from_world())  # double precision, once per frame
    if target.samples > 1 and read_depth:
        # Multisampled depth cannot be copied out: a single-sample pass first writes the
        # depth that is read (pixel centres, as without MSAA); the MSAA pass then
        # overwrites the color with its resolved, antialiased image.
        single = prepare_draws(cache, scene, target.color_format, eye_from_world, 1)
        encode_pass(
            cache, encoder, scene, single, eye_from_world, target.color_view, None, target.depth_view, store_depth=True
        )
    if target.samples > 1:
        draws = prepare_draws(cache, scene, target.color_format, eye_from_world, target.samples)
        encode_pass(
            cache, encoder, scene, draws, eye_from_world, target.msaa_color_view, target.color_view, target.msaa_depth_view
        )
    else:
        draws = prepare_draws(cache, scene, target.color_format, eye_from_world)
        encode_pass(
            cache, encoder, scene, draws, eye_from_world, target.color_view, None, target.depth_view, store_depth=read_depth
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


def encode_pass(
    cache: DeviceCache, encoder, scene: Scene, draws: list[Draw], eye_from_world, color_view, resolve_view, depth_view,
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
        uniform_limit = cache.device.limits["max-uniform-buffer-binding-size"]
        if frame_data.nbytes > uniform_limit:
            render_pass.end()
            raise SceneError(
                f"lights: the {len(scene.lights)} lights need {frame_data.nbytes} bytes of uniforms; this adapter "
                f"binds at most {uniform_limit} (use fewer lights)"
            )
        frame_buffer = cache.uniform_buffer("frame", 0, frame_data, "camera and lights")
    for draw in draws:
        entry = draw.entry
        assert entry.frame_dtype == frame_data.dtype
        gpu_mesh = draw.gpu_mesh
        render_pass.set_pipeline(entry.pipeline)
        resources = {
            "frame": frame_buffer,
            "object": cache.uniform_buffer("object", draw.draw_index, draw.object_data, f"objects[{draw.draw_index}]"),
            **draw.textures,
        }
        # Every entry of the plan, by name: uniform buffers, textures, else the mesh's buffer.
        for index, (group, layout) in enumerate(zip(entry.plan.groups, entry.bind_group_layouts)):
            bound = tuple(resources[b.name] if b.name in resources else getattr(gpu_mesh, b.name) for b in group)
            render_pass.set_bind_group(index, cache.bind_group(group_cache(group, draw), layout, bound))
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


def read_color_frame(target: Target, camera: Camera, *, read_depth: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """Colour and (with read_depth) eye-space depth from the target's readback buffers."""
    color = read_buffer(
        target.color_readback, target.color_row_bytes, target.height, target.width,
        np.uint8 if target.color_format == "rgba8" else np.float32, 4,
    )
    depth = None
    if read_depth:
        depth = read_mapped_rows(
            target.depth_readback, target.depth_row_bytes, target.height, target.width, np.float32,
            lambda rows: linear_depth(rows, camera),
        )
    return color, depth

