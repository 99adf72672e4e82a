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
from wgpu_shading.render.gpu.pipelines import PipelineCache
from wgpu_shading.render.passes.color import color_key
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
    entry = PipelineCache(renderer.device).get(color_key(features))
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


# A shadow lookup's resources: depth textures (2D, 2D array, cube) read through a
# comparison sampler. The shader compares a reference depth with each texture's stored
# depth (textureSampleCompare, WGSL §16.7.11); a wrong layout entry, declaration or bind
# group entry fails pipeline or bind group creation, and a wrong texture gives other values.
DEPTH_LOOKUP_WGSL = """
struct Reference {
    left: f32,
    right: f32,
}

#BINDINGS

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let corner = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(corner * 2.0 - 1.0, 0.5, 1.0);
}

@fragment
fn fs_main(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let reference = select(lookup_reference.left, lookup_reference.right, position.x > 2.0);
    let uv = vec2<f32>(0.5, 0.5);
    return vec4<f32>(
        textureSampleCompare(shadow_2d, shadow_sampler, uv, reference),
        textureSampleCompare(shadow_layers, shadow_sampler, uv, 1, reference),
        textureSampleCompare(shadow_cube, shadow_sampler, vec3<f32>(1.0, 0.2, 0.1), reference),
        1.0,
    );
}
"""


def test_depth_textures_and_comparison_samplers_compile_and_bind(renderer):
    import numpy as np
    import wgpu

    from wgpu_shading.render.gpu.bind_groups import cached_bind_group
    from wgpu_shading.render.gpu.caches import LruCache
    from wgpu_shading.render.gpu.pipelines import PipelineDescriptor, create_pipeline
    from wgpu_shading.render.gpu.readback import read_buffer
    from wgpu_shading.render.shaders.bindings import Binding, make_plan

    fragment = bindings.FRAGMENT
    plan = make_plan(None, [
        Binding("reference", 0, "uniform", "lookup_reference", "Reference", fragment),
        Binding("shadow_2d", 0, "texture", "shadow_2d", "texture_depth_2d", fragment),
        Binding("shadow_layers", 0, "texture", "shadow_layers", "texture_depth_2d_array", fragment),
        Binding("shadow_cube", 0, "texture", "shadow_cube", "texture_depth_cube", fragment),
        Binding("shadow_sampler", 0, "sampler", "shadow_sampler", "sampler_comparison", fragment),
    ], [])
    declarations = plan.wgsl()
    assert "var shadow_layers: texture_depth_2d_array;" in declarations
    assert "var shadow_sampler: sampler_comparison;" in declarations
    device = renderer.device
    layout = device.create_bind_group_layout(entries=[b.layout_entry() for b in plan.groups[0]])
    descriptor = PipelineDescriptor("depth lookup", DEPTH_LOOKUP_WGSL.replace("#BINDINGS", declarations), plan,
                                    depth_write=False, depth_compare=wgpu.CompareFunction.always)
    pipeline = create_pipeline(device, descriptor, (layout,))

    def depth_texture(layers: int, stored: list[float]):
        """A depth32float texture whose layer k is cleared to stored[k] (depth textures
        cannot be written from the CPU)."""
        texture = device.create_texture(size=(2, 2, layers), format=wgpu.TextureFormat.depth32float,
                                        usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.TEXTURE_BINDING)
        encoder = device.create_command_encoder()
        for layer in range(layers):
            view = texture.create_view(dimension="2d", base_array_layer=layer, array_layer_count=1)
            encoder.begin_render_pass(color_attachments=[], depth_stencil_attachment={
                "view": view, "depth_clear_value": stored[layer], "depth_load_op": "clear", "depth_store_op": "store",
            }).end()
        device.queue.submit([encoder.finish()])
        return texture

    shadow_2d = depth_texture(1, [0.25]).create_view()
    shadow_layers = depth_texture(2, [0.9, 0.75]).create_view(dimension="2d-array")
    shadow_cube = depth_texture(6, [0.3] * 6).create_view(dimension="cube")
    # passes where reference < stored
    sampler = device.create_sampler(compare=wgpu.CompareFunction.less)
    reference = device.create_buffer_with_data(data=np.array([0.1, 0.5], np.float32), usage=wgpu.BufferUsage.UNIFORM)
    group = cached_bind_group(device, LruCache(4), layout, (reference, shadow_2d, shadow_layers, shadow_cube, sampler))

    target = device.create_texture(size=(4, 1, 1), format=wgpu.TextureFormat.rgba8unorm,
                                   usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC)
    depth = device.create_texture(size=(4, 1, 1), format=wgpu.TextureFormat.depth32float, usage=wgpu.TextureUsage.RENDER_ATTACHMENT)
    readback = device.create_buffer(size=256, usage=wgpu.BufferUsage.MAP_READ | wgpu.BufferUsage.COPY_DST)
    encoder = device.create_command_encoder()
    render_pass = encoder.begin_render_pass(
        color_attachments=[{"view": target.create_view(), "load_op": "clear", "store_op": "store", "clear_value": (0, 0, 0, 0)}],
        depth_stencil_attachment={"view": depth.create_view(), "depth_clear_value": 0.0, "depth_load_op": "clear", "depth_store_op": "discard"},
    )
    render_pass.set_pipeline(pipeline)
    render_pass.set_bind_group(0, group)
    render_pass.draw(3)
    render_pass.end()
    encoder.copy_texture_to_buffer({"texture": target}, {"buffer": readback, "bytes_per_row": 256}, (4, 1, 1))
    device.queue.submit([encoder.finish()])
    pixels = read_buffer(readback, 256, 1, 4, np.uint8, 4)[0]
    # left (reference 0.1): below every stored depth; right (0.5): below layer 1's 0.75 only
    assert pixels[:2].tolist() == [[255, 255, 255, 255]] * 2
    assert pixels[2:].tolist() == [[0, 255, 0, 255]] * 2
