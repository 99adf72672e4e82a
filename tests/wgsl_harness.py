"""Run the product's WGSL functions (wgsl/lighting.wgsl, preprocessed for a scene's feature
set) in a compute shader on chosen inputs, and read the results back as float32.

Some hard cases need exact inputs that rasterization only hits by luck — a light exactly
at the shaded point, L exactly −V, a normal of exactly zero length. Here the inputs are
given directly, the uniforms are the scene's (filled by wgpu_shading.render.shaders.uniforms), and the
result is compared with the float64 reference at the same inputs.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import wgpu

from wgpu_shading.render.features import object_features
from wgpu_shading.render.shaders.layout import layouts_for
from wgpu_shading.scene import Scene
from wgpu_shading.render.shaders.preprocess import preprocess
from wgpu_shading.render.shaders.shadergen import generate_wgsl, sources_for
from wgpu_shading.render.shaders.uniforms import eye_from_model, frame_uniforms, object_uniforms


def run_kernel(device, scene: Scene, inputs: np.ndarray, body: str, outputs: int, object_index: int = 0) -> np.ndarray:
    """Evaluate `body` (WGSL statements) once per row of `inputs`.

    In `body`, `input_vector(k)` / `input_scalar(k)` read the row's floats k.. and
    `write_vector(k, v)` / `write_scalar(k, x)` store results; every function of
    lighting.wgsl (shade, safe_normalize, guarded_power, view_direction, ...) is available
    with the scene's uniforms bound. Returns (rows, outputs) float32.
    """
    obj = scene.objects[object_index]
    features = replace(object_features(scene, obj, object_index), frequency="phong", texture_mode=None)
    header = generate_wgsl(features).split("\n\n", 1)[0]  # feature comment + light-count constants
    defines = features.defines()
    library = "\n".join(preprocess(name, defines, sources_for(features)) for name in ("structs.wgsl", "bindings.wgsl", "lighting.wgsl"))
    inputs = np.ascontiguousarray(inputs, dtype=np.float32)
    rows, stride = inputs.shape
    source = f"""{header}
{library}

@group(2) @binding(0) var<storage, read> harness_inputs: array<f32>;
@group(2) @binding(1) var<storage, read_write> harness_outputs: array<f32>;
var<private> harness_row: u32;

fn input_scalar(k: u32) -> f32 {{ return harness_inputs[harness_row * {stride}u + k]; }}
fn input_vector(k: u32) -> vec3<f32> {{ return vec3<f32>(input_scalar(k), input_scalar(k + 1u), input_scalar(k + 2u)); }}
fn write_scalar(k: u32, value: f32) {{ harness_outputs[harness_row * {outputs}u + k] = value; }}
fn write_vector(k: u32, value: vec3<f32>) {{ write_scalar(k, value.x); write_scalar(k + 1u, value.y); write_scalar(k + 2u, value.z); }}

@compute @workgroup_size(64)
fn harness_main(@builtin(global_invocation_id) id: vec3<u32>) {{
    harness_row = id.x;
    // Phony uses keep both uniform groups in the automatic layout whatever `body` reads.
    _ = frame_uniforms.global_ambient;
    _ = object_uniforms.material;
    if (harness_row >= {rows}u) {{
        return;
    }}
{body}
}}
"""
    layouts = layouts_for(generate_wgsl(features))
    frame = frame_uniforms(scene, layouts.dtype("FrameUniforms"))
    object_data = object_uniforms(eye_from_model(scene, obj), obj.material, layouts.dtype("ObjectUniforms"), scene)
    pipeline = device.create_compute_pipeline(
        layout="auto", compute={"module": device.create_shader_module(code=source), "entry_point": "harness_main"}
    )
    uniform = wgpu.BufferUsage.UNIFORM
    result = device.create_buffer(size=4 * rows * outputs, usage=wgpu.BufferUsage.STORAGE | wgpu.BufferUsage.COPY_SRC)
    resources = {
        0: [device.create_buffer_with_data(data=frame.tobytes(), usage=uniform)],
        1: [device.create_buffer_with_data(data=object_data.tobytes(), usage=uniform)],
        2: [device.create_buffer_with_data(data=inputs.tobytes(), usage=wgpu.BufferUsage.STORAGE), result],
    }
    encoder = device.create_command_encoder()
    compute = encoder.begin_compute_pass()
    compute.set_pipeline(pipeline)
    for group, buffers in resources.items():
        entries = [{"binding": i, "resource": {"buffer": b}} for i, b in enumerate(buffers)]
        compute.set_bind_group(group, device.create_bind_group(layout=pipeline.get_bind_group_layout(group), entries=entries))
    compute.dispatch_workgroups((rows + 63) // 64)
    compute.end()
    device.queue.submit([encoder.finish()])
    return np.frombuffer(device.queue.read_buffer(result), dtype=np.float32).reshape(rows, outputs).copy()


def gpu_shade(device, scene: Scene, points, normals, to_viewer) -> tuple[np.ndarray, np.ndarray]:
    """lighting.wgsl's shade() at eye-space (points, unit normals, unit view vectors)."""
    inputs = np.concatenate([np.asarray(points), np.asarray(normals), np.asarray(to_viewer)], axis=1)
    features = object_features(scene, scene.objects[0])
    body = """    let lit = shade(input_vector(0u), input_vector(3u), input_vector(6u));
    write_vector(0u, lit.ambient_diffuse);"""
    if features.specular:
        body += "\n    write_vector(3u, lit.specular);"
    result = run_kernel(device, scene, inputs, body, 6)
    return result[:, :3].astype(np.float64), result[:, 3:].astype(np.float64)
