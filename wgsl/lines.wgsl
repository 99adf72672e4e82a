// Lines (docs/primitives.md): each segment a quad line_width pixels wide along its two
// ends on the screen (strokes.wgsl), one instance per segment, square-cut at the ends (as
// OpenGL's wide lines). Drawn in their colour: the material's diffuse × the vertex
// colours, interpolated along the segment; EDGES (a triangle mesh's edges, `--edges`):
// the edge colour.

#include "structs.wgsl"
#include "bindings.wgsl"
#include "lighting.wgsl"
#include "surface.wgsl"
#include "strokes.wgsl"

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
#if VERTEX_COLORS
    @location(0) color: vec4<f32>,
#endif
}

// The part of the segment from `near_end` to `far_end` that lies beyond the near plane
// (reversed Z: z ≤ w there); an end in front of it is moved onto it, so the other end's
// perspective divide never sees w ≤ 0.
fn beyond_near_plane(near_end: vec4<f32>, far_end: vec4<f32>) -> vec4<f32> {
    let inside_near = near_end.w - near_end.z;
    let inside_far = far_end.w - far_end.z;
    if (inside_near >= 0.0 || inside_far <= 0.0) {
        return near_end;
    }
    return mix(near_end, far_end, inside_near / (inside_near - inside_far));
}

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32, segment: VertexInput) -> Varyings {
    let start_clip = frame_uniforms.clip_from_eye * (object_uniforms.eye_from_model * vec4<f32>(segment.start, 1.0));
    let end_clip = frame_uniforms.clip_from_eye * (object_uniforms.eye_from_model * vec4<f32>(segment.end, 1.0));
    let start = beyond_near_plane(start_clip, end_clip);
    let end = beyond_near_plane(end_clip, start_clip);
    let corner = quad_corner(vertex_index);
    var out: Varyings;
    // Both ends in front of the near plane, or on one pixel: nothing to draw (a quad of no area).
    let half_pixels = 0.5 * object_uniforms.viewport_size;
    var across = vec2<f32>(0.0);
    if (start.w > 0.0 && end.w > 0.0 && start.w - start.z >= 0.0) {
        let along = (end.xy / end.w - start.xy / start.w) * half_pixels;
        let length_squared = dot(along, along);
        if (length_squared > 1e-12) {
            across = vec2<f32>(-along.y, along.x) * inverseSqrt(length_squared) * (0.5 * object_uniforms.stroke_pixels);
        }
    }
    let end_point = select(start, end, corner.x > 0.5);
    out.clip_position = moved_by_pixels(end_point, across * corner.y);
#if VERTEX_COLORS
    out.color = select(segment.start_color, segment.end_color, corner.x > 0.5);
#endif
    return out;
}

@fragment
fn fs_main(in: Varyings) -> @location(0) vec4<f32> {
#if EDGES
    return object_uniforms.edge_color;
#else
#if VERTEX_COLORS
    surface_color = in.color;
#endif
    var plain: LitColor;
    plain.ambient_diffuse = material_diffuse();
    return final_color(plain);
#endif
}
