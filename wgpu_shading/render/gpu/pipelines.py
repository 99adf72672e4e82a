"""Render pipelines: the one key a pipeline is cached by, the descriptor a pass builds for
it, and the cache of compiled pipelines of one device.

A pass (render/passes/) owns one pipeline-descriptor builder: `PipelineKey → PipelineDescriptor`,
everything its pipelines are made of (shader source, binding plan, topology, culling,
depth test and bias, colour target or none). `create_pipeline` below is the only code that
turns a descriptor into wgpu's render pipeline descriptor, so a new pass (a depth-only
shadow map, points or lines) states what differs and writes no wgpu dictionaries.

Creating a pipeline costs 0.2–0.4 s on lavapipe (shader translation and LLVM compilation),
so each is built once per Renderer and reused for every later frame with the same key.
Bind group layouts are explicit (not "auto"), made from the binding plan (shaders/bindings.py),
and shared between pipelines, so a bind group can be used with every pipeline of a scene.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np
import wgpu

from ...errors import SceneError
from ..device import FLOAT32_BLENDING_FEATURE
from ..features import FeatureSet
from ..shaders.bindings import Binding, BindingPlan
from ..shaders.layout import layouts_for
from .caches import PIPELINE_CACHE_ENTRIES, LruCache
from .targets import COLOR_FORMATS, DEPTH_FORMAT


@dataclass(frozen=True, eq=False)
class PassKind:
    """A kind of render pass, as a pipeline key names it: its name and its one
    pipeline-descriptor builder. Compared by identity (each pass module makes one)."""

    name: str
    describe: Callable[["PipelineKey"], "PipelineDescriptor"]

    def __repr__(self) -> str:
        return f"PassKind({self.name!r})"


class PipelineKey(NamedTuple):
    """Everything a render pipeline depends on, as one value: which pass draws with it and
    what varies within that pass. (A NamedTuple: made and looked up once per draw, and
    tuples hash and compare in C.)"""

    render_pass: PassKind
    features: FeatureSet | None  # the draw's feature set (None: a pass whose shader has no variants)
    target_format: str | None = "rgba8"  # COLOR_FORMATS key; None: no colour target (depth only)
    samples: int = 1
    # A mirrored model-view reverses the winding on screen: clockwise is then the front.
    mirrored: bool = False
    cull_back: bool = False


@dataclass(frozen=True)
class PipelineDescriptor:
    """What a pass asks of a render pipeline (WebGPU's GPURenderPipelineDescriptor, typed and
    with this renderer's defaults: triangles, no culling, reversed-Z depth test and writes)."""

    label: str
    source: str  # WGSL with vs_main, and fs_main unless fragment is False
    plan: BindingPlan
    topology: str = wgpu.PrimitiveTopology.triangle_list
    indexed: bool = True  # drawn from the mesh's index buffer (else vertices are pulled: flat shading)
    quads: bool = False  # each instance a quad, a strip of four vertices (points and lines: passes/strokes.py)
    front_face_cw: bool = False
    cull_mode: str = wgpu.CullMode.none
    depth_format: str = DEPTH_FORMAT
    depth_write: bool = True
    depth_compare: str = wgpu.CompareFunction.greater  # reversed Z: 1 near, 0 far
    depth_bias: int = 0
    depth_bias_slope_scale: float = 0.0
    depth_bias_clamp: float = 0.0
    color_format: str | None = "rgba8"  # COLOR_FORMATS key; None: no colour target
    blend: dict | None = None
    samples: int = 1
    fragment: bool = True  # a depth-only pass without discards needs no fragment stage


@dataclass(frozen=True)
class PipelineEntry:
    """A compiled pipeline with what drawing with it needs: its key and descriptor, its bind
    group layouts and the dtypes of its uniform buffers."""

    key: PipelineKey
    descriptor: PipelineDescriptor
    pipeline: object  # wgpu.GPURenderPipeline
    bind_group_layouts: tuple  # one GPUBindGroupLayout per group of the plan
    # The numpy dtype of each uniform buffer of the plan, by binding name ("frame", "object"),
    # from the WGSL struct the plan declares it with (shaders/layout.py).
    uniform_dtypes: dict[str, np.dtype]
    # The descriptor's plan and index mode, at hand for the per-draw loop (passes/draws.py).
    plan: BindingPlan
    indexed: bool


# alphaMode BLEND: "over" compositing (premultiplied by the source alpha), and the
# destination alpha accumulates coverage, so a translucent part over the background
# keeps the background's alpha where nothing opaque is behind it.
BLEND_OVER = {
    "color": {"src_factor": wgpu.BlendFactor.src_alpha, "dst_factor": wgpu.BlendFactor.one_minus_src_alpha, "operation": wgpu.BlendOperation.add},
    "alpha": {"src_factor": wgpu.BlendFactor.one, "dst_factor": wgpu.BlendFactor.one_minus_src_alpha, "operation": wgpu.BlendOperation.add},
}


def create_pipeline(device, descriptor: PipelineDescriptor, group_layouts: tuple):
    """The wgpu render pipeline of a descriptor (the one place wgpu's dictionaries are written)."""
    module = device.create_shader_module(label=descriptor.label, code=descriptor.source)
    fragment = None
    if descriptor.fragment:
        targets = []
        if descriptor.color_format is not None:
            target = {"format": COLOR_FORMATS[descriptor.color_format]}
            targets.append(target | ({"blend": descriptor.blend} if descriptor.blend is not None else {}))
        fragment = {"module": module, "entry_point": "fs_main", "targets": targets}
    return device.create_render_pipeline(
        label=descriptor.label,
        layout=device.create_pipeline_layout(bind_group_layouts=list(group_layouts)),
        vertex={"module": module, "entry_point": "vs_main", "buffers": descriptor.plan.vertex_buffer_layouts()},
        primitive={
            "topology": descriptor.topology,
            "front_face": wgpu.FrontFace.cw if descriptor.front_face_cw else wgpu.FrontFace.ccw,
            "cull_mode": descriptor.cull_mode,
        },
        depth_stencil={
            "format": descriptor.depth_format,
            "depth_write_enabled": descriptor.depth_write,
            "depth_compare": descriptor.depth_compare,
            "depth_bias": descriptor.depth_bias,
            "depth_bias_slope_scale": descriptor.depth_bias_slope_scale,
            "depth_bias_clamp": descriptor.depth_bias_clamp,
        },
        multisample={"count": descriptor.samples},
        fragment=fragment,
    )


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

    @property
    def changes(self) -> int:
        """Pipelines made or evicted so far (frame_plans.py watches it)."""
        return self._pipelines.changes

    def entries(self) -> list[PipelineEntry]:
        """The cached pipelines, least recently used first."""
        return self._pipelines.values()

    def group_layout(self, bindings: tuple[Binding, ...]):
        if bindings not in self._group_layouts:
            self._group_layouts[bindings] = self._device.create_bind_group_layout(
                entries=[binding.layout_entry() for binding in bindings]
            )
        return self._group_layouts[bindings]

    def get(self, key: PipelineKey) -> PipelineEntry:
        """The pipeline of `key`, made by its pass's descriptor builder on first use."""
        entry = self._pipelines.get(key)
        if entry is None:
            entry = self._pipelines.put(key, self._create(key))
        return entry

    def _create(self, key: PipelineKey) -> PipelineEntry:
        descriptor = key.render_pass.describe(key)
        if descriptor.blend is not None and descriptor.color_format == "float32" and FLOAT32_BLENDING_FEATURE not in self._device.features:
            raise SceneError(
                "an alpha-blended material cannot be drawn into the float32 target on this device "
                f"(it lacks WebGPU's {FLOAT32_BLENDING_FEATURE!r} feature): render to the 8-bit target (PNG)"
            )
        group_layouts = tuple(self.group_layout(group) for group in descriptor.plan.groups)
        layouts = layouts_for(descriptor.source)
        uniform_dtypes = {b.name: layouts.dtype(b.wgsl_type) for group in descriptor.plan.groups for b in group if b.kind == "uniform"}
        pipeline = create_pipeline(self._device, descriptor, group_layouts)
        return PipelineEntry(key, descriptor, pipeline, group_layouts, uniform_dtypes, descriptor.plan, descriptor.indexed)
