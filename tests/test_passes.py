"""Render passes (docs/architecture.md#render--the-gpu): a frame is the list of passes it asks
for, each pass builds its pipelines' descriptors, and a pipeline is cached under one named
key. The descriptor builder takes what a pass varies (topology, depth-only, depth bias)
from the pass: shown here with the passes still to come (a depth-only biased pass like a
shadow map, points and lines), drawn on lavapipe and read back."""

from __future__ import annotations

import numpy as np
import pytest
import wgpu

from wgpu_shading import ViewOptions, load_view
from wgpu_shading.render.gpu.pipelines import PipelineDescriptor, PipelineKey, create_pipeline
from wgpu_shading.render.gpu.readback import read_buffer
from wgpu_shading.render.passes.color import COLOR, ColorPass, color_key
from wgpu_shading.render.passes.extra_outputs import EXTRA_OUTPUTS, ExtraOutputsPass
from wgpu_shading.render.passes.frame import frame_passes
from wgpu_shading.render.shaders.bindings import make_plan


@pytest.mark.parametrize(
    "request_, expected",
    [
        ({}, [ColorPass("rgba8", read_depth=False)]),
        ({"depth": True, "color_format": "float32"}, [ColorPass("float32", read_depth=True)]),
        ({"color": False, "depth": True}, [ColorPass("rgba8", read_depth=True)]),
        ({"normals": "world"}, [ColorPass("rgba8", read_depth=False), ExtraOutputsPass("world")]),
        ({"color": False, "ids": True}, [ExtraOutputsPass("eye")]),
        ({"color": False}, []),
    ],
)
def test_a_frame_is_the_list_of_passes_it_asks_for(request_, expected):
    assert frame_passes(load_view("builtin:sphere"), **request_) == expected


def test_each_pipeline_is_cached_under_one_named_key(renderer):
    """The colour and the extra-outputs pipelines of one frame: two keys naming their pass
    (a closed sphere seen from outside: both cull its back faces, turned_away.py)."""
    from wgpu_shading import Renderer

    fresh = Renderer(device=renderer.device)
    scene = load_view("builtin:sphere", ViewOptions(size=(16, 16)))
    fresh.render_frame(scene, normals="eye")
    keys = [entry.key for entry in fresh.device_cache.pipelines.entries()]
    assert [key.render_pass for key in keys] == [COLOR, EXTRA_OUTPUTS]
    features = fresh.features(scene)[0]
    assert keys[0] == color_key(features, cull_back=True) == PipelineKey(COLOR, features, "rgba8", 1, False, True)
    assert keys[1] == PipelineKey(EXTRA_OUTPUTS, None, "float32", 1, False, True)


# A triangle covering the target at clip depth 0.5, a point at each of the four pixel
# centres of row 1 of a 4×4 target, or a line along row 2.
GEOMETRY_WGSL = """
@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
#if TRIANGLE
    let corner = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(corner * 2.0 - 1.0, 0.5, 1.0);
#elif POINTS
    return vec4<f32>((f32(index) + 0.5) / 2.0 - 1.0, 1.0 - 1.5 / 2.0, 0.5, 1.0);
#else
    return vec4<f32>(select(-1.0, 1.0, index == 1u), 1.0 - 2.5 / 2.0, 0.5, 1.0);
#endif
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return vec4<f32>(1.0, 1.0, 1.0, 1.0);
}
"""


def _draw(device, descriptor: PipelineDescriptor, vertex_count: int, with_color: bool) -> tuple[np.ndarray, np.ndarray]:
    """Draw into a 4×4 target (colour only if the descriptor has one): colour and depth."""
    pipeline = create_pipeline(device, descriptor, ())
    usage = wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC
    color = device.create_texture(size=(4, 4, 1), format=wgpu.TextureFormat.rgba8unorm, usage=usage)
    depth = device.create_texture(size=(4, 4, 1), format=wgpu.TextureFormat.depth32float, usage=usage)
    readback = [device.create_buffer(size=256 * 4, usage=wgpu.BufferUsage.MAP_READ | wgpu.BufferUsage.COPY_DST) for _ in range(2)]
    encoder = device.create_command_encoder()
    attachments = [{"view": color.create_view(), "load_op": "clear", "store_op": "store", "clear_value": (0, 0, 0, 0)}]
    render_pass = encoder.begin_render_pass(
        color_attachments=attachments if with_color else [],
        depth_stencil_attachment={"view": depth.create_view(), "depth_clear_value": 0.0, "depth_load_op": "clear", "depth_store_op": "store"},
    )
    render_pass.set_pipeline(pipeline)
    render_pass.draw(vertex_count)
    render_pass.end()
    encoder.copy_texture_to_buffer({"texture": color}, {"buffer": readback[0], "bytes_per_row": 256, "rows_per_image": 4}, (4, 4, 1))
    encoder.copy_texture_to_buffer({"texture": depth, "aspect": "depth-only"}, {"buffer": readback[1], "bytes_per_row": 256, "rows_per_image": 4}, (4, 4, 1))
    device.queue.submit([encoder.finish()])
    return read_buffer(readback[0], 256, 4, 4, np.uint8, 4), read_buffer(readback[1], 256, 4, 4, np.float32, 1)[:, :, 0]


def _source(shape: str) -> str:
    from wgpu_shading.render.shaders.preprocess import preprocess

    defines = {"TRIANGLE": shape == "triangle", "POINTS": shape == "points"}
    return preprocess("geometry.wgsl", defines, lambda name: GEOMETRY_WGSL)


def test_a_depth_only_pass_with_a_depth_bias(renderer):
    """A shadow map's pipeline: no colour target, no fragment stage, depth biased away from
    the light (WebGPU: bias × the format's resolution at that depth, plus slope scale)."""
    plan = make_plan(None, [], [])
    unbiased = PipelineDescriptor("depth only", _source("triangle"), plan, indexed=False, color_format=None, fragment=False)
    _, depth = _draw(renderer.device, unbiased, 3, with_color=False)
    assert np.all(depth == np.float32(0.5))
    biased = PipelineDescriptor("depth only, biased", _source("triangle"), plan, indexed=False, color_format=None,
                                fragment=False, depth_bias=8, depth_bias_slope_scale=1.0, depth_bias_clamp=0.0)
    _, depth = _draw(renderer.device, biased, 3, with_color=False)
    # float32 depth near 0.5: one unit of bias is 2^-24 (the exponent of 0.5, minus 23)
    assert np.all(depth == np.float32(0.5 + 8 * 2.0**-24)), depth


@pytest.mark.parametrize("topology, shape, vertices, row", [
    (wgpu.PrimitiveTopology.point_list, "points", 4, 1),
    (wgpu.PrimitiveTopology.line_list, "line", 2, 2),
])
def test_points_and_lines_are_a_topology_of_the_descriptor(renderer, topology, shape, vertices, row):
    descriptor = PipelineDescriptor(shape, _source(shape), make_plan(None, [], []), topology=topology, indexed=False)
    color, depth = _draw(renderer.device, descriptor, vertices, with_color=True)
    covered = color[:, :, 0] == 255
    expected = np.zeros((4, 4), bool)
    expected[row] = True
    assert np.array_equal(covered, expected)
    assert np.all(depth[covered] == np.float32(0.5)) and np.all(depth[~covered] == 0.0)


def test_an_alpha_blended_material_in_the_float32_target(renderer):
    """Half-transparent red over transparent black, in both targets: colour × alpha and the
    alpha itself (the "over" blend of docs/conventions.md), closed form."""
    from wgpu_shading import Material, Scene, SceneObject
    from wgpu_shading.scene.geometry.builtins import plane

    red = Material(ambient=(1, 0, 0, 0.5), diffuse=(0, 0, 0, 0.5), specular=(0, 0, 0, 1), alpha_mode="blend")
    scene = Scene(objects=(SceneObject(plane(8.0), red),), lights=(), ambient=(1, 1, 1, 1),
                  background=(0, 0, 0, 0), size=(8, 8))
    np.testing.assert_allclose(renderer.render(scene, float32=True)[4, 4], [0.5, 0, 0, 0.5], atol=1e-6)
    np.testing.assert_allclose(renderer.render(scene)[4, 4], [128, 0, 0, 128], atol=1)
    # a device without WebGPU's float32-blendable feature says so instead of failing in wgpu
    from wgpu_shading import Renderer, SceneError

    plain = Renderer(device=renderer.device.adapter.request_device_sync(required_features=[]))
    with pytest.raises(SceneError, match="float32-blendable"):
        plain.render(scene, float32=True)
    assert plain.render(scene)[4, 4, 3] in (127, 128)
