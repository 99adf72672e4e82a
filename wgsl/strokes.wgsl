// Points and lines as quads built on the screen by the vertex stage (docs/primitives.md):
// WebGPU rasterizes its point and line topologies one pixel wide, so each point or line
// segment is an instance of four vertices (a triangle strip of two triangles) moved apart
// in pixels. Used by the colour pass (points.wgsl, lines.wgsl) and the extra outputs
// (extra_outputs.wgsl), so both cover the same pixels.

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

#if LINES
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

// Corner `corner` (quad_corner) of the quad `width` pixels wide along a segment between two
// clip-space ends, cut square at the ends (OpenGL's wide lines). A segment wholly in front
// of the near plane, or shorter than a millionth of a pixel, is a quad of no area.
fn segment_corner(start_clip: vec4<f32>, end_clip: vec4<f32>, corner: vec2<f32>, width: f32, viewport: vec2<f32>) -> vec4<f32> {
    let start = beyond_near_plane(start_clip, end_clip);
    let end = beyond_near_plane(end_clip, start_clip);
    var across = vec2<f32>(0.0);
    if (start.w > 0.0 && end.w > 0.0 && start.w - start.z >= 0.0) {
        let along = (end.xy / end.w - start.xy / start.w) * (0.5 * viewport);
        let length_squared = dot(along, along);
        if (length_squared > 1e-12) {
            across = vec2<f32>(-along.y, along.x) * inverseSqrt(length_squared) * (0.5 * width);
        }
    }
    return moved_by_pixels(select(start, end, corner.x > 0.5), across * corner.y, viewport);
}
#endif
