// Lines (docs/primitives.md#lines): each segment a quad line_width pixels wide between its
// two ends on the screen (strokes.wgsl), one instance per segment. Drawn in their colour:
// the material's diffuse × the vertex colours, interpolated along the segment; EDGES (a
// triangle mesh's edges, `--edges`): the edge colour.

#include "structs.wgsl"
#include "bindings.wgsl"
#include "lighting.wgsl"
#include "maps.wgsl"
#include "surface.wgsl"
#include "strokes.wgsl"

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
#if VERTEX_COLORS
    @location(0) color: vec4<f32>,
#endif
}

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32, segment: VertexInput) -> Varyings {
    let start = frame_uniforms.clip_from_eye * (object_uniforms.eye_from_model * vec4<f32>(segment.start, 1.0));
    let end = frame_uniforms.clip_from_eye * (object_uniforms.eye_from_model * vec4<f32>(segment.end, 1.0));
    let corner = quad_corner(vertex_index);
    var out: Varyings;
    out.clip_position = segment_corner(start, end, corner, object_uniforms.stroke_pixels, object_uniforms.viewport_size);
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
