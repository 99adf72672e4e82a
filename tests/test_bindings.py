"""The binding plan (wgpu_shading/render/shaders/bindings.py) is the one source of the WGSL binding
declarations, the pipeline's layouts and what the render pass binds: numbers follow from the
table, the shader declares exactly the plan, and wgpu itself accepts shader and layout
together (an explicit layout that disagrees with the shader fails pipeline creation)."""

from __future__ import annotations

import re
from dataclasses import replace

import pytest

from wgpu_shading.render.shaders import bindings
from wgpu_shading.render.shaders.bindings import SampledTexture, binding_plan
from wgpu_shading.render.features import FeatureSet
from wgpu_shading.render.gpu.pipeline_cache import PipelineCache
from wgpu_shading.render.shaders.shadergen import generate_wgsl

DECLARATION = re.compile(r"@group\((\d+)\) @binding\((\d+)\) var(?:<[^>]*>)? (\w+)")
LOCATION = re.compile(r"@location\((\d+)\) (\w+): (vec\d<f32>),")

CASES = [
    FeatureSet(frequency="phong", directional_lights=1),
    FeatureSet(frequency="gouraud", positional_lights=1, texture_mode="modulate"),
    FeatureSet(frequency="phong", spot_lights=1, vertex_colors=True),
    FeatureSet(frequency="gouraud", directional_lights=1, texture_mode="blend", vertex_colors=True),
    FeatureSet(frequency="flat", directional_lights=1),
    FeatureSet(frequency="flat", directional_lights=1, texture_mode="modulate"),
    FeatureSet(frequency="flat", directional_lights=1, vertex_colors=True),
    FeatureSet(frequency="flat", directional_lights=1, texture_mode="modulate_all", vertex_colors=True),
]


@pytest.mark.parametrize("features", CASES, ids=FeatureSet.describe)
def test_the_shader_declares_exactly_the_plan(features):
    plan = binding_plan(features)
    declared = {(int(g), int(b), name) for g, b, name in DECLARATION.findall(generate_wgsl(features))}
    planned = {(b.group, b.binding, b.variable) for group in plan.groups for b in group}
    assert declared == planned
    for group in plan.groups:  # numbered from 0 without gaps, as the pass binds them
        assert [b.binding for b in group] == list(range(len(group)))
    inputs = [(int(location), field) for location, field, _ in LOCATION.findall(generate_wgsl(features).split("struct Varyings")[0])]
    assert inputs == [(v.slot, v.field) for v in plan.vertex_buffers]


def test_the_entries_by_name():
    """Hand-written expectations: what each kind of draw binds, by name and number."""
    plan = binding_plan(FeatureSet(frequency="phong", texture_mode="modulate", vertex_colors=True))
    assert [[b.name for b in group] for group in plan.groups] == [
        ["frame"], ["object", "base_color_texture", "base_color_sampler"],
    ]
    assert [(v.name, v.slot) for v in plan.vertex_buffers] == [("positions", 0), ("normals", 1), ("uvs", 2), ("colors", 3)]
    plan = binding_plan(FeatureSet(frequency="gouraud", vertex_colors=True))
    assert [(v.name, v.slot) for v in plan.vertex_buffers] == [("positions", 0), ("normals", 1), ("colors", 2)]
    plan = binding_plan(FeatureSet(frequency="flat", vertex_colors=True))
    assert [b.name for b in plan.groups[2]] == ["positions", "indices", "colors"]
    assert plan.vertex_buffers == ()


@pytest.mark.parametrize("features", CASES, ids=FeatureSet.describe)
def test_wgpu_accepts_shader_and_layouts_together(renderer, features):
    """Explicit layouts and vertex buffer layouts from the plan, the shader from shadergen:
    wgpu validates that every binding and location the shader uses is in them."""
    entry = PipelineCache(renderer.device).get(features)
    assert len(entry.bind_group_layouts) == len(entry.plan.groups)


def test_a_new_texture_is_one_table_line(monkeypatch):
    """Adding a SampledTexture gives it a texture and a sampler in the object group, and
    the mesh's uvs, without touching anything else."""
    extra = SampledTexture("detail", lambda f: f.emission, lambda material: None)
    monkeypatch.setattr(bindings, "SAMPLED_TEXTURES", (*bindings.SAMPLED_TEXTURES, extra))
    binding_plan.cache_clear()
    try:
        plan = binding_plan(FeatureSet(frequency="phong", emission=True))
        assert [(b.name, b.binding, b.kind) for b in plan.groups[1]] == [
            ("object", 0, "uniform"), ("detail_texture", 1, "texture"), ("detail_sampler", 2, "sampler"),
        ]
        assert "uvs" in plan and plan.textures == (extra,)
        assert "@group(1) @binding(1) var detail_texture: texture_2d<f32>;" in plan.wgsl()
        flat = binding_plan(replace(FeatureSet(frequency="flat", emission=True)))
        assert [b.name for b in flat.groups[2]] == ["positions", "indices", "uvs"]
    finally:
        binding_plan.cache_clear()
