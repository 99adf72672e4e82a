"""Feature set → compiled render pipeline, cached per device.

One pipeline per (feature set, color format, front face). Creating one costs 0.2–0.4 s
on lavapipe (shader translation and LLVM compilation), so each is built once per
Renderer and reused for every later frame with the same features. Bind group layouts
are explicit (not "auto"), made from the feature set's binding plan (bindings.py), and
shared between pipelines, so the per-frame bind group can be used with every pipeline of
a scene.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu

from ..shaders.bindings import Binding, BindingPlan, binding_plan, extra_outputs_plan
from .caches import PIPELINE_CACHE_ENTRIES, LruCache
from ..features import FeatureSet
from ..shaders.layout import Layouts, layouts_for
from ..shaders.shadergen import generate_extra_outputs_wgsl, generate_wgsl
from .targets import COLOR_FORMATS, DEPTH_FORMAT



@dataclass(frozen=True)
class PipelineEntry:
    features: FeatureSet | None  # None: the extra outputs pass
    pipeline: object  # wgpu.GPURenderPipeline
    plan: BindingPlan  # what each bind group and vertex buffer holds, by name
    bind_group_layouts: tuple  # one GPUBindGroupLayout per group of the plan
    source: str
    frame_dtype: np.dtype | None
    object_dtype: np.dtype  # the per-draw uniform block (ExtraUniforms for the extra outputs)


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

    def group_layout(self, bindings: tuple[Binding, ...]):
        if bindings not in self._group_layouts:
            self._group_layouts[bindings] = self._device.create_bind_group_layout(
                entries=[binding.layout_entry() for binding in bindings]
            )
        return self._group_layouts[bindings]

    def get(self, features: FeatureSet, color_format: str = "rgba8", mirrored: bool = False, samples: int = 1) -> PipelineEntry:
        key = (features, color_format, mirrored, samples)
        entry = self._pipelines.get(key)
        if entry is None:
            entry = self._pipelines.put(key, self._create(features, color_format, mirrored, samples))
        return entry

    def extra_outputs(self, cull_back: bool = False, mirrored: bool = False) -> PipelineEntry:
        """The normals-and-ids pipeline (extra_outputs.py), cached with the others;
        `cull_back` for the parts the lit pass culls (glTF doubleSided false)."""
        key = ("extra outputs", cull_back, mirrored and cull_back)
        entry = self._pipelines.get(key)
        if entry is None:
            entry = self._pipelines.put(key, self._create_extra_outputs(*key[1:]))
        return entry

    def _create_extra_outputs(self, cull_back: bool = False, mirrored: bool = False) -> PipelineEntry:
        source = generate_extra_outputs_wgsl()
        plan = extra_outputs_plan()
        group_layouts = tuple(self.group_layout(group) for group in plan.groups)
        module = self._device.create_shader_module(label="extra outputs", code=source)
        pipeline = self._device.create_render_pipeline(
            label="extra outputs",
            layout=self._device.create_pipeline_layout(bind_group_layouts=list(group_layouts)),
            vertex={"module": module, "entry_point": "vs_main", "buffers": plan.vertex_buffer_layouts()},
            primitive={"topology": wgpu.PrimitiveTopology.triangle_list,
                       "front_face": wgpu.FrontFace.cw if mirrored else wgpu.FrontFace.ccw,
                       "cull_mode": wgpu.CullMode.back if cull_back else wgpu.CullMode.none},
            depth_stencil={"format": DEPTH_FORMAT, "depth_write_enabled": True, "depth_compare": wgpu.CompareFunction.greater},
            multisample={"count": 1},
            fragment={"module": module, "entry_point": "fs_main", "targets": [{"format": COLOR_FORMATS["float32"]}]},
        )
        dtype = layouts_for(source).dtype("ExtraUniforms")
        return PipelineEntry(None, pipeline, plan, group_layouts, source, frame_dtype=None, object_dtype=dtype)

    def _create(self, features: FeatureSet, color_format: str, mirrored: bool, samples: int) -> PipelineEntry:
        source = generate_wgsl(features)
        layouts: Layouts = layouts_for(source)
        plan = binding_plan(features)
        group_layouts = tuple(self.group_layout(group) for group in plan.groups)
        module = self._device.create_shader_module(label=features.describe(), code=source)
        pipeline = self._device.create_render_pipeline(
            label=features.describe(),
            layout=self._device.create_pipeline_layout(bind_group_layouts=list(group_layouts)),
            vertex={"module": module, "entry_point": "vs_main", "buffers": plan.vertex_buffer_layouts()},
            primitive={
                "topology": wgpu.PrimitiveTopology.triangle_list,
                # A mirrored model-view reverses the winding on screen; flip what counts as
                # front so `front_facing` still means "the outward side faces the viewer".
                "front_face": wgpu.FrontFace.cw if mirrored else wgpu.FrontFace.ccw,
                # No culling, like OpenGL's default: open meshes show their inside; a glTF
                # material with doubleSided false culls its back faces (glTF 2.0 §3.9.6).
                "cull_mode": wgpu.CullMode.back if features.cull_back else wgpu.CullMode.none,
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
            plan=plan,
            bind_group_layouts=group_layouts,
            source=source,
            frame_dtype=layouts.dtype("FrameUniforms"),
            object_dtype=layouts.dtype("ObjectUniforms"),
        )
