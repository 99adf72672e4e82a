// The extra outputs (render/passes/extra_outputs.py: normals, ids) of points: the colour
// pass's quads (points.wgsl) through the same float32 matrices, so the same pixels are
// covered. A disc's normal turned towards the camera (chunks/strokes/discs.wgsl); a square
// point has no normal (0).

struct PointOutputUniforms {
    clip_from_eye: mat4x4<f32>,
    eye_from_model: mat4x4<f32>,
    // Inverse transpose of the model(-view) matrix's 3x3 part: model normal → output space.
    output_normal_from_model: mat3x3<f32>,
    // The lit pass's eye_normal_from_model: which way a disc faces the camera.
    eye_normal_from_model: mat3x3<f32>,
    // 1 + the index of the (object, part) in extra_outputs.segments.
    object_id: f32,
    viewport_size: vec2<f32>,
    stroke_pixels: f32,
}

#include "bindings.wgsl"
#include "chunks/numerics.wgsl"
#include "chunks/strokes/quads.wgsl"
#include "chunks/strokes/discs.wgsl"

struct ExtraVaryings {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) normal: vec3<f32>,
#hook points_outputs.varyings
}

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32, vertex: VertexInput) -> ExtraVaryings {
    let center = extra_uniforms.eye_from_model * vec4<f32>(vertex.position, 1.0);
    let projection = extra_uniforms.clip_from_eye;
    let clip = projection * center;
    let corner = vec2<f32>(2.0 * quad_corner(vertex_index).x - 1.0, quad_corner(vertex_index).y);
    let half_size = 0.5 * extra_uniforms.stroke_pixels;
    let viewport = extra_uniforms.viewport_size;
    let normal_matrix = extra_uniforms.eye_normal_from_model;
    var out: ExtraVaryings;
    out.clip_position = moved_by_pixels(clip, corner * half_size, viewport);
#hook points_outputs.vertex  // (a disc's plane and normal)
    return out;
}

@fragment
fn fs_main(in: ExtraVaryings) -> @location(0) vec4<f32> {
    let projection = extra_uniforms.clip_from_eye;
#hook points_outputs.fragment  // (the disc's pixels)
    return vec4<f32>(safe_normalize(in.normal, vec3<f32>(0.0)), extra_uniforms.object_id);
}
