// Extra per-pixel outputs for dataset rendering (wgpu_shading/render/passes/extra_outputs.py):
// the interpolated surface normal (eye or world space) and the object id, in one rgba32float
// target. Positions go through exactly the matrices and operations of the lit shaders
// (clip_from_eye * (eye_from_model * p), the same float32 values), so the same pixels are
// covered and the same surface wins the depth test as in the colour image. Points and
// lines (STROKES) are the colour pass's quads (strokes.wgsl, discs.wgsl): a disc's normal
// turned towards the camera, a square point's and a line's normal zero (they have none).

struct ExtraUniforms {
    clip_from_eye: mat4x4<f32>,
    eye_from_model: mat4x4<f32>,
    // Inverse transpose of the model(-view) matrix's 3x3 part: model normal → output space.
    output_normal_from_model: mat3x3<f32>,
    // 1 + the index of the (object, part) in extra_outputs.segments (0 is left for the background).
    object_id: f32,
#if STROKES
    viewport_size: vec2<f32>,
    stroke_pixels: f32,
#endif
#if POINT_NORMALS
    // The lit pass's eye_normal_from_model: which way a disc faces the camera.
    eye_normal_from_model: mat3x3<f32>,
#endif
}

// extra_uniforms (group 0) and VertexInput (position, normal): render/shaders/bindings.py's
// extra_outputs_plan.
#include "bindings.wgsl"
#if STROKES
#include "strokes.wgsl"
#endif
#if POINT_NORMALS
const MIN_LENGTH_SQUARED: f32 = 1e-30;
#include "discs.wgsl"
#endif

struct ExtraVaryings {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) normal: vec3<f32>,
#if POINT_NORMALS
    @location(1) @interpolate(flat) center: vec3<f32>,
    @location(2) @interpolate(flat) eye_normal: vec3<f32>,
    @location(3) on_image_plane: vec3<f32>,
    @location(4) @interpolate(flat) radius: f32,
#endif
}

#if POINTS
@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32, point: VertexInput) -> ExtraVaryings {
    let center = extra_uniforms.eye_from_model * vec4<f32>(point.position, 1.0);
    let clip = extra_uniforms.clip_from_eye * center;
    let corner = vec2<f32>(2.0 * quad_corner(vertex_index).x - 1.0, quad_corner(vertex_index).y);
    let half_size = 0.5 * extra_uniforms.stroke_pixels;
    var out: ExtraVaryings;
    out.clip_position = moved_by_pixels(clip, corner * half_size, extra_uniforms.viewport_size);
#if POINT_NORMALS
    let eye_normal = extra_uniforms.eye_normal_from_model * point.normal;
    let disc = disc_corner(center.xyz, clip, eye_normal, corner, half_size, extra_uniforms.clip_from_eye, extra_uniforms.viewport_size);
    out.center = center.xyz;
    out.eye_normal = disc.normal;
    out.on_image_plane = disc.on_image_plane;
    out.radius = disc.radius;
    // turned towards the camera as in the lit pass
    out.normal = extra_uniforms.output_normal_from_model * point.normal * select(1.0, -1.0, dot(disc.normal, eye_normal) < 0.0);
#endif
    return out;
}
#elif LINES
@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32, segment: VertexInput) -> ExtraVaryings {
    let start = extra_uniforms.clip_from_eye * (extra_uniforms.eye_from_model * vec4<f32>(segment.start, 1.0));
    let end = extra_uniforms.clip_from_eye * (extra_uniforms.eye_from_model * vec4<f32>(segment.end, 1.0));
    var out: ExtraVaryings;
    out.clip_position = segment_corner(start, end, quad_corner(vertex_index), extra_uniforms.stroke_pixels, extra_uniforms.viewport_size);
    return out;
}
#else
@vertex
fn vs_main(vertex: VertexInput) -> ExtraVaryings {
    let eye_position = extra_uniforms.eye_from_model * vec4<f32>(vertex.position, 1.0);
    var out: ExtraVaryings;
    out.clip_position = extra_uniforms.clip_from_eye * eye_position;
    out.normal = extra_uniforms.output_normal_from_model * vertex.normal;
    return out;
}
#endif

@fragment
fn fs_main(in: ExtraVaryings) -> @location(0) vec4<f32> {
#if POINT_NORMALS
    let eye_length_squared = dot(in.eye_normal, in.eye_normal);
    if (eye_length_squared > MIN_LENGTH_SQUARED) {
        let on_disc = point_on_disc(in.center, in.eye_normal * inverseSqrt(eye_length_squared), in.on_image_plane, in.radius,
                                    extra_uniforms.clip_from_eye);
        if (on_disc.w == 0.0) {
            discard;
        }
    }
#endif
    // Guard the normalization: a degenerate (zero) normal stays zero instead of NaN.
    let length_squared = dot(in.normal, in.normal);
    var normal = vec3<f32>(0.0);
    if (length_squared > 1e-30) {
        normal = in.normal * inverseSqrt(length_squared);
    }
    return vec4<f32>(normal, extra_uniforms.object_id);
}
