// Points and lines as quads built on the screen by the vertex stage (docs/primitives.md):
// WebGPU rasterizes its point and line topologies one pixel wide, so each point or line
// segment is an instance of four vertices (a triangle strip of two triangles) moved apart
// in pixels. Used by the colour pass (points.wgsl, lines.wgsl) and the extra outputs
// (points_outputs.wgsl, lines_outputs.wgsl), so both cover the same pixels.

// Corner k (vertex_index 0..3) of a quad: x along it (0 start, 1 end), y across (−1 or 1);
// as a strip, the triangles (0, 1, 2) and (1, 2, 3) share the diagonal from (1, −1) to (0, 1).
fn quad_corner(vertex_index: u32) -> vec2<f32> {
    return vec2<f32>(f32(vertex_index & 1u), f32(vertex_index & 2u) - 1.0);
}

// `clip` moved by `pixels` on a target of `viewport` pixels (x right, y up): in clip space
// an offset scales with w, so that after the perspective divide it is the same number of
// pixels everywhere.
fn moved_by_pixels(clip: vec4<f32>, pixels: vec2<f32>, viewport: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(clip.xy + pixels * (2.0 / viewport) * clip.w, clip.zw);
}
