// Lines (docs/primitives.md#lines): each segment a quad line_width pixels wide between its
// two ends on the screen (chunks/strokes/segments.wgsl), one instance per segment, drawn
// in its colour: the material's diffuse × the vertex colours, interpolated along the
// segment; a triangle mesh's edges in the edge colour (chunks/strokes/edges.wgsl).

#include "structs.wgsl"
#include "bindings.wgsl"
#include "lighting.wgsl"
#include "output.wgsl"
#include "chunks/strokes/quads.wgsl"
#include "chunks/strokes/segments.wgsl"
// The line's effects, one chunk each: what they declare is pasted here, what they do at
// the named points (#hook) below and in output.wgsl.
#include "chunks/surface/vertex_colors.wgsl"
#include "chunks/strokes/edges.wgsl"
#include "chunks/surface/alpha_mode.wgsl"
#include "chunks/surface/srgb_output.wgsl"

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
#hook lines.varyings
}

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32, vertex: VertexInput) -> Varyings {
    let start = frame_uniforms.clip_from_eye * (object_uniforms.eye_from_model * vec4<f32>(vertex.start, 1.0));
    let end = frame_uniforms.clip_from_eye * (object_uniforms.eye_from_model * vec4<f32>(vertex.end, 1.0));
    let corner = quad_corner(vertex_index);
    var out: Varyings;
    out.clip_position = segment_corner(start, end, corner, object_uniforms.stroke_pixels, object_uniforms.viewport_size);
#hook lines.vertex  // (vertex colors)
    return out;
}

@fragment
fn fs_main(in: Varyings) -> @location(0) vec4<f32> {
#hook lines.fragment_surface  // the line's colour here (vertex colors)
    var lit: LitColor;
    lit.ambient_diffuse = object_uniforms.material.diffuse.rgb * surface_tint();
    return final_color(lit);
}
