"""Feature set → compiled render pipeline, cached per device.

One pipeline per (feature set, color format, front face). Creating one costs 0.2–0.4 s
on lavapipe (shader translation and LLVM compilation), so each is built once per
Renderer and reused for every later frame with the same features. Bind group layouts
are explicit (not "auto") and shared between pipelines, so the per-frame bind group
can be used with every pipeline of a scene.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu

from .caches import PIPELINE_CACHE_ENTRIES, LruCache
from .features import FeatureSet
from .layout import Layouts, layouts_for
from .shadergen import generate_wgsl

DEPTH_FORMAT = wgpu.TextureFormat.depth32float
COLOR_FORMATS = {"rgba8": wgpu.TextureFormat.rgba8unorm, "float32": wgpu.TextureFormat.rgba32float}

_UNIFORM = {"type": wgpu.BufferBindingType.uniform}
_STORAGE = {"type": wgpu.BufferBindingType.read_only_storage}
_VERTEX_AND_FRAGMENT = wgpu.ShaderStage.VERTEX | wgpu.ShaderStage.FRAGMENT
# Group 1 bindings of each material map's texture (its sampler is the next one): wgsl/bindings.wgsl.
MAP_BINDINGS = {
    "normal_map": 3, "bump_map": 5, "specular_map": 7, "shininess_map": 9, "emissive_map": 11, "occlusion_map": 13, "alpha_map": 15,
}


@dataclass(frozen=True)
class PipelineEntry:
    features: FeatureSet
    pipeline: object  # wgpu.GPURenderPipeline
    bind_group_layouts: tuple  # one GPUBindGroupLayout per group
    source: str
    frame_dtype: np.dtype
    object_dtype: np.dtype


def bind_group_entries(features: FeatureSet) -> list[tuple[tuple, ...]]:
    """Layout entries per bind group, as hashable tuples (binding, visibility, kind, settings)."""
    groups: list[tuple[tuple, ...]] = [
        ((0, _VERTEX_AND_FRAGMENT, "buffer", "uniform"),),
    ]
    object_group = [(0, _VERTEX_AND_FRAGMENT, "buffer", "uniform")]
    if features.texture_mode is not None:
        object_group += [(1, wgpu.ShaderStage.FRAGMENT, "texture", "float"), (2, wgpu.ShaderStage.FRAGMENT, "sampler", "filtering")]
    for name in features.map_flags:
        binding = MAP_BINDINGS[name]
        object_group += [(binding, _VERTEX_AND_FRAGMENT, "texture", "float"), (binding + 1, _VERTEX_AND_FRAGMENT, "sampler", "filtering")]
    groups.append(tuple(object_group))
    if features.frequency == "flat":
        mesh_group = [(0, wgpu.ShaderStage.VERTEX, "buffer", "storage"), (1, wgpu.ShaderStage.VERTEX, "buffer", "storage")]
        if features.uses_uvs:
            mesh_group.append((2, wgpu.ShaderStage.VERTEX, "buffer", "storage"))
        if features.vertex_colors:
            mesh_group.append((len(mesh_group), wgpu.ShaderStage.VERTEX, "buffer", "storage"))
        groups.append(tuple(mesh_group))
    return groups


def _layout_entry(binding: int, visibility: int, kind: str, setting: str) -> dict:
    entry: dict = {"binding": binding, "visibility": visibility}
    if kind == "buffer":
        entry["buffer"] = _UNIFORM if setting == "uniform" else _STORAGE
    elif kind == "texture":
        entry["texture"] = {"sample_type": wgpu.TextureSampleType.float, "view_dimension": "2d"}
    else:
        entry["sampler"] = {"type": wgpu.SamplerBindingType.filtering}
    return entry


def vertex_buffer_layouts(features: FeatureSet) -> list[dict]:
    """Separate (non-interleaved) buffers, so one upload serves every feature set."""
    if features.frequency == "flat":
        return []  # flat shading pulls vertices from storage buffers
    layouts = [
        {"array_stride": 12, "attributes": [{"format": wgpu.VertexFormat.float32x3, "offset": 0, "shader_location": 0}]},
        {"array_stride": 12, "attributes": [{"format": wgpu.VertexFormat.float32x3, "offset": 0, "shader_location": 1}]},
    ]
    if features.uses_uvs:
        layouts.append(
            {"array_stride": 8, "attributes": [{"format": wgpu.VertexFormat.float32x2, "offset": 0, "shader_location": 2}]}
        )
    if features.vertex_colors:
        layouts.append(
            {"array_stride": 16, "attributes": [{"format": wgpu.VertexFormat.float32x4, "offset": 0, "shader_location": 3}]}
        )
    return layouts


# alphaMode BLEND: "over" compositing (premultiplied by the source alpha), and the
# destination alpha accumulates coverage, so a translucent part over the background
# keeps the background's alpha where nothing opaque is behind it.
_BLEND_OVER = {
    "color": {"src_factor": wgpu.BlendFactor.src_alpha, "dst_factor": wgpu.BlendFactor.one_minus_src_alpha, "operation": wgpu.BlendOperation.add},
    "alpha": {"src_factor": wgpu.BlendFactor.one, "dst_factor": wgpu.BlendFactor.one_minus_src_alpha, "operation": wgpu.BlendOperation.add},
}


class PipelineCache:
    """Pipelines and bind group layouts of one device. Pipelines are evicted least recently
    used beyond `max_entries` (caches.PIPELINE_CACHE_ENTRIES); the few distinct bind group
    layouts are kept (they are shared by every pipeline)."""

    def __init__(self, device, max_entries: int = PIPELINE_CACHE_ENTRIES):
        self._device = device
        self._pipelines: LruCache[PipelineEntry] = LruCache(max_entries)
        self._group_layouts: dict[tuple, object] = {}

    def __len__(self) -> int:
        return len(self._pipelines)

    def group_layout(self, entries: tuple[tuple, ...]):
        if entries not in self._group_layouts:
            self._group_layouts[entries] = self._device.create_bind_group_layout(
                entries=[_layout_entry(*entry) for entry in entries]
            )
        return self._group_layouts[entries]

    def get(self, features: FeatureSet, color_format: str = "rgba8", mirrored: bool = False, samples: int = 1) -> PipelineEntry:
        key = (features, color_format, mirrored, samples)
        entry = self._pipelines.get(key)
        if entry is None:
            entry = self._pipelines.put(key, self._create(features, color_format, mirrored, samples))
        return entry

    def _create(self, features: FeatureSet, color_format: str, mirrored: bool, samples: int) -> PipelineEntry:
        source = generate_wgsl(features)
        layouts: Layouts = layouts_for(source)
        group_layouts = tuple(self.group_layout(entries) for entries in bind_group_entries(features))
        module = self._device.create_shader_module(label=features.describe(), code=source)
        pipeline = self._device.create_render_pipeline(
            label=features.describe(),
            layout=self._device.create_pipeline_layout(bind_group_layouts=list(group_layouts)),
            vertex={"module": module, "entry_point": "vs_main", "buffers": vertex_buffer_layouts(features)},
            primitive={
                "topology": wgpu.PrimitiveTopology.triangle_list,
                # A mirrored model-view reverses the winding on screen; flip what counts as
                # front so `front_facing` still means "the outward side faces the viewer".
                "front_face": wgpu.FrontFace.cw if mirrored else wgpu.FrontFace.ccw,
                # No culling, like OpenGL's default: open meshes show their inside.
                "cull_mode": wgpu.CullMode.none,
            },
            depth_stencil={
                "format": DEPTH_FORMAT,
                # Blended parts are drawn after the opaque ones, back to front, and do not
                # hide each other (they still hide behind opaque parts).
                "depth_write_enabled": features.alpha_mode != "blend",
                "depth_compare": wgpu.CompareFunction.greater,  # reversed Z
            },
            multisample={"count": samples},
            fragment={
                "module": module,
                "entry_point": "fs_main",
                "targets": [
                    {"format": COLOR_FORMATS[color_format]}
                    | ({"blend": _BLEND_OVER} if features.alpha_mode == "blend" else {})
                ],
            },
        )
        return PipelineEntry(
            features=features,
            pipeline=pipeline,
            bind_group_layouts=group_layouts,
            source=source,
            frame_dtype=layouts.dtype("FrameUniforms"),
            object_dtype=layouts.dtype("ObjectUniforms"),
        )
