// Points (docs/primitives.md#points): each point a screen-aligned quad of point_size pixels
// (chunks/strokes/quads.wgsl), one instance per point, its attributes stepping per
// instance. A point is a square in its colour (the material's diffuse × the vertex colour,
// unlit); with a normal, a disc facing it, lit (chunks/strokes/discs.wgsl).

#include "structs.wgsl"
#include "bindings.wgsl"
#include "lighting.wgsl"
#include "output.wgsl"
#include "chunks/strokes/quads.wgsl"
// The point's effects, one chunk each: what they declare is pasted here, what they do at
// the named points (#hook) below.
#include "chunks/surface/vertex_colors.wgsl"
#include "chunks/strokes/discs.wgsl"
#include "chunks/surface/alpha_mode.wgsl"
#include "chunks/surface/srgb_output.wgsl"

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
#hook points.varyings
}

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32, vertex: VertexInput) -> Varyings {
    let center = object_uniforms.eye_from_model * vec4<f32>(vertex.position, 1.0);
    let projection = frame_uniforms.clip_from_eye;
    let clip = projection * center;
    let corner = vec2<f32>(2.0 * quad_corner(vertex_index).x - 1.0, quad_corner(vertex_index).y);  // (±1, ±1)
    let half_size = 0.5 * object_uniforms.stroke_pixels;
    let viewport = object_uniforms.viewport_size;
    let normal_matrix = object_uniforms.eye_normal_from_model;
    var out: Varyings;
    out.clip_position = moved_by_pixels(clip, corner * half_size, viewport);
#hook points.vertex  // (vertex colors; a disc's plane)
    return out;
}

@fragment
fn fs_main(in: Varyings) -> @location(0) vec4<f32> {
    let projection = frame_uniforms.clip_from_eye;
#hook points.fragment_surface  // the point's colour (vertex colors)
    // the point's colour, unlit
    var lit: LitColor;
    lit.ambient_diffuse = object_uniforms.material.diffuse.rgb * surface_tint();
#hook points.fragment_lit  // what lights the point (a disc facing its normal)
    return final_color(lit);
}
