// The extra outputs (render/passes/extra_outputs.py: normals, ids) of lines: the colour
// pass's quads (lines.wgsl) through the same float32 matrices, so the same pixels are
// covered. A line has no normal (0).

struct LineOutputUniforms {
    clip_from_eye: mat4x4<f32>,
    eye_from_model: mat4x4<f32>,
    output_normal_from_model: mat3x3<f32>,
    // 1 + the index of the (object, part) in extra_outputs.segments.
    object_id: f32,
    viewport_size: vec2<f32>,
    stroke_pixels: f32,
}

#include "bindings.wgsl"
#include "chunks/strokes/quads.wgsl"
#include "chunks/strokes/segments.wgsl"

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32, vertex: VertexInput) -> @builtin(position) vec4<f32> {
    let start = extra_uniforms.clip_from_eye * (extra_uniforms.eye_from_model * vec4<f32>(vertex.start, 1.0));
    let end = extra_uniforms.clip_from_eye * (extra_uniforms.eye_from_model * vec4<f32>(vertex.end, 1.0));
    return segment_corner(start, end, quad_corner(vertex_index), extra_uniforms.stroke_pixels, extra_uniforms.viewport_size);
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return vec4<f32>(0.0, 0.0, 0.0, extra_uniforms.object_id);
}
