// Extra per-pixel outputs for dataset rendering (wgpu_shading/render/passes/extra_outputs.py):
// the interpolated surface normal (eye or world space) and the object id, in one rgba32float
// target. Positions go through exactly the matrices and operations of the lit shaders
// (clip_from_eye * (eye_from_model * p), the same float32 values), so the same pixels are
// covered and the same surface wins the depth test as in the colour image.

struct ExtraUniforms {
    clip_from_eye: mat4x4<f32>,
    eye_from_model: mat4x4<f32>,
    // Inverse transpose of the model(-view) matrix's 3x3 part: model normal → output space.
    output_normal_from_model: mat3x3<f32>,
    // 1 + the index of the (object, part) in extra_outputs.segments (0 is left for the background).
    object_id: f32,
}

// extra_uniforms (group 0) and VertexInput (position, normal): render/shaders/bindings.py's
// extra_outputs_plan.
#include "bindings.wgsl"

struct ExtraVaryings {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) normal: vec3<f32>,
}

@vertex
fn vs_main(vertex: VertexInput) -> ExtraVaryings {
    let eye_position = extra_uniforms.eye_from_model * vec4<f32>(vertex.position, 1.0);
    var out: ExtraVaryings;
    out.clip_position = extra_uniforms.clip_from_eye * eye_position;
    out.normal = extra_uniforms.output_normal_from_model * vertex.normal;
    return out;
}

@fragment
fn fs_main(in: ExtraVaryings) -> @location(0) vec4<f32> {
    // Guard the normalization: a degenerate (zero) normal stays zero instead of NaN.
    let length_squared = dot(in.normal, in.normal);
    var normal = vec3<f32>(0.0);
    if (length_squared > 1e-30) {
        normal = in.normal * inverseSqrt(length_squared);
    }
    return vec4<f32>(normal, extra_uniforms.object_id);
}
