"""The binding plan: every resource a draw binds, by name, derived from its FeatureSet.

The tables below are the one list of what a shader reads outside its own code: uniform
buffers, textures and their samplers, flat shading's storage buffers, and the vertex
buffers of Gouraud and Phong. `binding_plan(features)` keeps the entries a feature set
needs and numbers them (bind group binding numbers and vertex buffer slots, in table
order, never written by hand). Everything else follows from the plan:

- the WGSL declarations (`BindingPlan.wgsl()`; shadergen pastes them where a source says
  `#include "bindings.wgsl"`),
- the bind group layouts and the vertex buffer layouts of a pipeline (gpu/pipelines.py),
- the bind groups and vertex buffers the render pass sets (renderer.py binds each entry by
  its name: uniform buffers "frame" and "object", a GpuMesh buffer of the same name, or a
  texture's view and sampler).

Adding a resource is one line: a texture read by the fragment stage is a `SampledTexture`
(it brings "<name>_texture" and "<name>_sampler" in group 1, the mesh's uvs, and the
upload and binding of `of_material(material)`); a mesh attribute is a `VertexAttribute`
(a vertex buffer for Gouraud/Phong and a storage buffer for flat shading, read from the
GpuMesh attribute of the same name).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Callable

import wgpu

from ...scene import Material, Texture
from ...scene.material import MAX_UV_SET
from ..features import FeatureSet
from .material_maps import bump_normal_texture

VERTEX = wgpu.ShaderStage.VERTEX
FRAGMENT = wgpu.ShaderStage.FRAGMENT
VERTEX_AND_FRAGMENT = VERTEX | FRAGMENT

When = Callable[[FeatureSet], bool]


def always(features: FeatureSet) -> bool:
    return True


def flat(features: FeatureSet) -> bool:
    """Flat shading pulls its vertices from storage buffers (wgsl/flat.wgsl says why)."""
    return features.frequency == "flat"


@dataclass(frozen=True)
class SampledTexture:
    """A texture the fragment stage samples: `<name>_texture` and `<name>_sampler` in the
    object's bind group, filled with `of_material(material)` and its sampler."""

    name: str
    when: When
    of_material: Callable[[Material], Texture | None]
    comment: str = ""
    stages: int = FRAGMENT
    # A colour image: stored as rgba8unorm-srgb (decoded to linear light before filtering)
    # when the draw is in linear colour space and the Texture says "srgb" (material_maps.py).
    color: bool = False


@dataclass(frozen=True)
class VertexAttribute:
    """A per-vertex array of the mesh: GpuMesh attribute `name`, field `field` of the
    vertex input (Gouraud/Phong) or storage array `mesh_<name>` (flat shading)."""

    name: str
    field: str
    wgsl_type: str  # the vertex input's type, e.g. vec3<f32>
    vertex_format: str  # wgpu.VertexFormat
    stride: int  # bytes per vertex
    storage_type: str  # flat shading's storage array, e.g. array<f32> (x, y, z flattened)
    when: When
    comment: str = ""
    step_mode: str = wgpu.VertexStepMode.vertex  # instance: one value per point or segment (a quad)


# ---------------------------------------------------------------------------- the tables

# Textures, in binding order (each one line; the maps add theirs here).
# The material maps (scene/maps.py): occlusion and shininess maps are also read by the
# vertex stage of flat and Gouraud shading (sampled at the vertex or the face centroid).
SAMPLED_TEXTURES: tuple[SampledTexture, ...] = (
    SampledTexture(
        "base_color", lambda f: f.texture_mode is not None, lambda m: m.texture,
        "RGBA8, rows uploaded bottom-up so that v = 0 is the bottom of the image", color=True,
    ),
    SampledTexture("normal_map", lambda f: f.normal_map, lambda m: m.normal_map, "Material maps (scene/maps.py)."),
    SampledTexture("bump_map", lambda f: f.bump_map, lambda m: bump_normal_texture(m.bump_map, m.bump_scale),
                   "The height map as the tangent-space normal map it implies (converted on upload)."),
    SampledTexture("specular_map", lambda f: f.specular_map, lambda m: m.specular_map, color=True),
    SampledTexture("shininess_map", lambda f: f.shininess_map, lambda m: m.shininess_map, stages=VERTEX_AND_FRAGMENT),
    SampledTexture("emissive_map", lambda f: f.emissive_map, lambda m: m.emissive_map, color=True),
    SampledTexture("occlusion_map", lambda f: f.occlusion_map, lambda m: m.occlusion_map, stages=VERTEX_AND_FRAGMENT),
    SampledTexture("alpha_map", lambda f: f.alpha_map, lambda m: m.alpha_map),
)


def textured(features: FeatureSet) -> bool:
    """Some texture is sampled: the mesh's uvs are needed."""
    return any(texture.when(features) for texture in SAMPLED_TEXTURES)


# Mesh attributes, in slot order. Indices are not an attribute: an index buffer for
# Gouraud/Phong, the storage buffer "indices" for flat shading.
VERTEX_ATTRIBUTES: tuple[VertexAttribute, ...] = (
    VertexAttribute("positions", "position", "vec3<f32>", "float32x3", 12, "array<f32>", always, "x, y, z per vertex (model space)"),
    VertexAttribute("normals", "normal", "vec3<f32>", "float32x3", 12, "array<f32>", lambda f: not flat(f)),
    VertexAttribute("uvs", "uv", "vec2<f32>", "float32x2", 8, "array<f32>", textured, "u, v per vertex"),
    VertexAttribute("colors", "color", "vec4<f32>", "float32x4", 16, "array<vec4<f32>>", lambda f: f.vertex_colors, "r, g, b, a per vertex"),
    VertexAttribute("tangents", "tangent", "vec4<f32>", "float32x4", 16, "array<vec4<f32>>", lambda f: f.vertex_tangents, "glTF TANGENT: x, y, z, handedness w"),
    # The mesh's other texture coordinate sets (Mesh.extra_uvs), only where a texture reads them.
    *(VertexAttribute(f"uv_set_{k}", f"uv_{k}", "vec2<f32>", "float32x2", 8, "array<f32>", lambda f, k=k: k in f.extra_uv_sets,
                      f"texture coordinate set {k}") for k in range(1, MAX_UV_SET + 1)),
)


# Points and line segments (docs/primitives.md): quads built by the vertex stage, one
# instance each, so their attributes step per instance (render/gpu/stroke_uploads.py
# uploads them; six vertices of a quad read the same values).
_INSTANCE = wgpu.VertexStepMode.instance
POINT_ATTRIBUTES: tuple[VertexAttribute, ...] = (
    VertexAttribute("positions", "position", "vec3<f32>", "float32x3", 12, "", always, "a point", _INSTANCE),
    VertexAttribute("normals", "normal", "vec3<f32>", "float32x3", 12, "", lambda f: f.point_normals, "zero: none (unlit)", _INSTANCE),
    VertexAttribute("colors", "color", "vec4<f32>", "float32x4", 16, "", lambda f: f.vertex_colors, "", _INSTANCE),
)
SEGMENT_ATTRIBUTES: tuple[VertexAttribute, ...] = (
    VertexAttribute("starts", "start", "vec3<f32>", "float32x3", 12, "", always, "a segment's two ends", _INSTANCE),
    VertexAttribute("ends", "end", "vec3<f32>", "float32x3", 12, "", always, "", _INSTANCE),
    VertexAttribute("start_colors", "start_color", "vec4<f32>", "float32x4", 16, "", lambda f: f.vertex_colors, "", _INSTANCE),
    VertexAttribute("end_colors", "end_color", "vec4<f32>", "float32x4", 16, "", lambda f: f.vertex_colors, "", _INSTANCE),
)


# The bind group layout entry of each WGSL texture and sampler type a plan may declare:
# colour images (filtered floats) and depth textures (a shadow map: 2D, 2D array, cube)
# read through comparison samplers (textureSampleCompare).
TEXTURE_LAYOUTS = {
    "texture_2d<f32>": {"sample_type": wgpu.TextureSampleType.float, "view_dimension": wgpu.TextureViewDimension.d2},
    "texture_depth_2d": {"sample_type": wgpu.TextureSampleType.depth, "view_dimension": wgpu.TextureViewDimension.d2},
    "texture_depth_2d_array": {"sample_type": wgpu.TextureSampleType.depth, "view_dimension": wgpu.TextureViewDimension.d2_array},
    "texture_depth_cube": {"sample_type": wgpu.TextureSampleType.depth, "view_dimension": wgpu.TextureViewDimension.cube},
}
SAMPLER_LAYOUTS = {
    "sampler": {"type": wgpu.SamplerBindingType.filtering},
    "sampler_comparison": {"type": wgpu.SamplerBindingType.comparison},
}


@dataclass(frozen=True)
class Binding:
    """One bind group entry. `kind`: uniform | storage | texture | sampler; a texture's or
    sampler's WGSL type says which (TEXTURE_LAYOUTS, SAMPLER_LAYOUTS). `binding` is
    numbered by `make_plan`, in the order of the entries of each group."""

    name: str
    group: int
    kind: str
    variable: str  # the WGSL variable
    wgsl_type: str
    stages: int
    comment: str = ""
    binding: int = -1

    def wgsl(self) -> str:
        space = {"uniform": "<uniform>", "storage": "<storage, read>"}.get(self.kind, "")
        line = f"@group({self.group}) @binding({self.binding}) var{space} {self.variable}: {self.wgsl_type};"
        return f"// {self.comment}\n{line}" if self.comment else line

    def layout_entry(self) -> dict:
        entry: dict = {"binding": self.binding, "visibility": self.stages}
        if self.kind == "uniform":
            entry["buffer"] = {"type": wgpu.BufferBindingType.uniform}
        elif self.kind == "storage":
            entry["buffer"] = {"type": wgpu.BufferBindingType.read_only_storage}
        elif self.kind == "texture":
            entry["texture"] = TEXTURE_LAYOUTS[self.wgsl_type]
        else:
            entry["sampler"] = SAMPLER_LAYOUTS[self.wgsl_type]
        return entry


@dataclass(frozen=True)
class VertexBuffer:
    """One vertex buffer of the indexed frequencies: GpuMesh attribute `name` in `slot`."""

    name: str
    slot: int
    field: str
    wgsl_type: str
    vertex_format: str
    stride: int
    step_mode: str = wgpu.VertexStepMode.vertex

    def layout(self) -> dict:
        return {
            "array_stride": self.stride,
            "step_mode": self.step_mode,
            "attributes": [{"format": self.vertex_format, "offset": 0, "shader_location": self.slot}],
        }


def _candidate_bindings(features: FeatureSet) -> list[Binding]:
    """Every entry the feature set needs, in binding order within each group."""
    entries = [
        Binding("frame", 0, "uniform", "frame_uniforms", "FrameUniforms", VERTEX_AND_FRAGMENT, "Group 0: one per frame, shared by every object."),
        Binding("object", 1, "uniform", "object_uniforms", "ObjectUniforms", VERTEX_AND_FRAGMENT, "Group 1: one per object (and its textures)."),
    ]
    if features.shadow_lights:  # shadows (passes/shadow.py binds them; wgsl/chunks/shadows/lookup.wgsl reads them)
        entries += [
            Binding("shadow_uniforms", 0, "uniform", "shadow_uniforms", "ShadowUniforms", VERTEX_AND_FRAGMENT,
                    "Shadows: the casting lights' views (docs/shadows.md),"),
            Binding("shadow_maps", 0, "texture", "shadow_maps", "texture_depth_2d_array", FRAGMENT, "their maps, a layer per view,"),
        ]
        if features.shadow_filter != "nearest":  # the nearest texel is loaded, not sampled
            entries.append(Binding("shadow_sampler", 0, "sampler", "shadow_sampler", "sampler_comparison", FRAGMENT,
                                   "and their comparison sampler."))
    for texture in SAMPLED_TEXTURES:
        if texture.when(features):
            entries.append(Binding(f"{texture.name}_texture", 1, "texture", f"{texture.name}_texture", "texture_2d<f32>", texture.stages, texture.comment))
            entries.append(Binding(f"{texture.name}_sampler", 1, "sampler", f"{texture.name}_sampler", "sampler", texture.stages))
    if flat(features):
        comment = "Group 2: the mesh, pulled by flat shading's vertex stage."
        for attribute in VERTEX_ATTRIBUTES:
            if attribute.when(features) and attribute.name != "normals":  # flat shading makes face normals
                entries.append(Binding(attribute.name, 2, "storage", f"mesh_{attribute.name}", attribute.storage_type, VERTEX,
                                       f"{comment} {attribute.comment}" if attribute.name == "positions" else attribute.comment))
            if attribute.name == "positions":
                entries.append(Binding("indices", 2, "storage", "mesh_indices", "array<u32>", VERTEX, "three per triangle"))
    return entries


@dataclass(frozen=True)
class BindingPlan:
    """The bind groups (each a tuple of Bindings, numbered from 0) and vertex buffers of
    one feature set."""

    features: FeatureSet | None  # None: the extra outputs pass (normals and ids)
    groups: tuple[tuple[Binding, ...], ...]
    vertex_buffers: tuple[VertexBuffer, ...]
    textures: tuple[SampledTexture, ...]  # what fills the *_texture/*_sampler entries

    def __post_init__(self) -> None:
        # Asked per draw (which optional mesh attributes to upload): computed once.
        names = frozenset(b.name for group in self.groups for b in group) | {v.name for v in self.vertex_buffers}
        object.__setattr__(self, "_names", names)

    def names(self) -> frozenset[str]:
        return self._names

    def __contains__(self, name: str) -> bool:
        return name in self._names

    def vertex_buffer_layouts(self) -> list[dict]:
        return [buffer.layout() for buffer in self.vertex_buffers]

    def wgsl(self) -> str:
        """The WGSL declarations of every binding, and the vertex input struct."""
        lines = [
            "// Resource bindings, generated from the binding plan (wgpu_shading/render/shaders/bindings.py);",
            "// the pipeline's bind group layouts and the render pass come from the same plan.",
        ]
        for group in self.groups:
            lines += [binding.wgsl() for binding in group]
        if self.vertex_buffers:
            lines.append("\n// Vertex buffers: one per attribute (not interleaved), so one upload serves every feature set.")
            lines.append("struct VertexInput {")
            lines += [f"    @location({v.slot}) {v.field}: {v.wgsl_type}," for v in self.vertex_buffers]
            lines.append("}")
        return "\n".join(lines) + "\n"


def make_plan(
    features: FeatureSet | None, entries: list[Binding], attributes: list[VertexAttribute],
    textures: tuple[SampledTexture, ...] = (),
) -> BindingPlan:
    """A plan of these bind group entries (numbered in order within each group, groups from
    0 without gaps) and vertex buffers (slots in order); `textures`: what fills the
    *_texture/*_sampler entries from a draw's material. Every pass's plan is made here."""
    groups: list[list[Binding]] = [[] for _ in range(1 + max((entry.group for entry in entries), default=-1))]
    for entry in entries:
        groups[entry.group].append(replace(entry, binding=len(groups[entry.group])))
    vertex_buffers = tuple(
        VertexBuffer(a.name, slot, a.field, a.wgsl_type, a.vertex_format, a.stride, a.step_mode) for slot, a in enumerate(attributes)
    )
    return BindingPlan(features, tuple(tuple(group) for group in groups), vertex_buffers, textures)


@lru_cache(maxsize=256)
def binding_plan(features: FeatureSet) -> BindingPlan:
    """The plan for one feature set (cached: a FeatureSet is hashable)."""
    if features.primitive != "triangles":  # points and lines: the two uniform blocks and their instances
        attributes = POINT_ATTRIBUTES if features.primitive == "points" else SEGMENT_ATTRIBUTES
        return make_plan(features, _candidate_bindings(features), [a for a in attributes if a.when(features)])
    attributes = [] if flat(features) else [a for a in VERTEX_ATTRIBUTES if a.when(features)]
    textures = tuple(t for t in SAMPLED_TEXTURES if t.when(features))
    return make_plan(features, _candidate_bindings(features), attributes, textures)


@lru_cache(maxsize=1)
def shadow_map_plan() -> BindingPlan:
    """The shadow pass (passes/shadow.py): one uniform block per caster and view, and the
    mesh's positions."""
    entries = [Binding("object", 0, "uniform", "caster_uniforms", "ShadowCaster", VERTEX, "One per caster and view.")]
    return make_plan(None, entries, [a for a in VERTEX_ATTRIBUTES if a.name == "positions"])


@lru_cache(maxsize=8)
def extra_outputs_plan(strokes: FeatureSet | None = None) -> BindingPlan:
    """The normals-and-ids pass (extra_outputs.py): one uniform block per object part and
    the mesh's positions and normals; for points and lines (`strokes`, their feature set)
    their instances' positions (and a point's normal)."""
    uniforms = "ExtraUniforms" if strokes is None else "PointOutputUniforms" if strokes.primitive == "points" else "LineOutputUniforms"
    entries = [Binding("object", 0, "uniform", "extra_uniforms", uniforms, VERTEX_AND_FRAGMENT, "One per object part.")]
    if strokes is None:
        return make_plan(None, entries, [a for a in VERTEX_ATTRIBUTES if a.name in ("positions", "normals")])
    attributes = POINT_ATTRIBUTES if strokes.primitive == "points" else SEGMENT_ATTRIBUTES
    return make_plan(strokes, entries, [a for a in attributes if a.when(strokes) and "color" not in a.name])
