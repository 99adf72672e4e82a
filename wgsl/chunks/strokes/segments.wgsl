// Line segments as quads (docs/primitives.md#lines): `width` pixels wide between the
// segment's ends on the screen, cut square at the ends (OpenGL's wide lines), clipped at
// the near plane first.

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

// Corner `corner` (quad_corner) of the quad along a segment between two clip-space ends. A
// segment wholly in front of the near plane, or shorter than a millionth of a pixel, is a
// quad of no area.
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
