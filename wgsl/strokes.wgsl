// Points and lines as quads built on the screen by the vertex stage (docs/primitives.md):
// WebGPU rasterizes its point and line topologies one pixel wide, so each point or line
// segment is an instance of six vertices (two triangles) moved apart in pixels. Sizes come
// from the object's uniforms: the target's size and the quad's size in pixels.

// Corner k (vertex_index 0..5) of a quad: x along it (0 start, 1 end), y across (−1 or 1);
// the two triangles (0, 1, 2) and (3, 4, 5) share the diagonal from (1, −1) to (0, 1).
fn quad_corner(vertex_index: u32) -> vec2<f32> {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(0.0, 1.0),
        vec2<f32>(0.0, 1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
    );
    return corners[vertex_index];
}

// `clip` moved by `pixels` on the screen (x right, y up): in clip space an offset scales
// with w, so that after the perspective divide it is the same number of pixels everywhere.
fn moved_by_pixels(clip: vec4<f32>, pixels: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(clip.xy + pixels * (2.0 / object_uniforms.viewport_size) * clip.w, clip.zw);
}
