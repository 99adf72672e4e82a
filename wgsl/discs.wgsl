// Points with normals as small discs (docs/primitives.md#points): the disc lies in the
// plane through the point perpendicular to its normal; seen face-on it fills the circle
// inscribed in the point's quad (point_size pixels across), seen at an angle it is the
// ellipse that plane cuts out of the pixel rays. Used by the colour pass (points.wgsl,
// which lights each pixel of the disc) and the extra outputs (the same pixels, the normal).

// Below this cosine between the normal and a pixel ray a disc is drawn as if seen at this
// angle (an ellipse 1/20 as wide as long) instead of vanishing edge-on.
const MIN_DISC_COSINE: f32 = 0.05;

// What the vertex stage hands the fragments of a disc, all in eye space.
struct DiscCorner {
    // The normal turned towards the camera (scanners' normals often have no consistent
    // sign); zero for a point without one.
    normal: vec3<f32>,
    // This corner of the quad on the plane through the point parallel to the image.
    on_image_plane: vec3<f32>,
    // The disc's radius.
    radius: f32,
}

// `center` is the point in eye space, `clip` its clip position, `corner` the quad corner
// (±1, ±1), `half_size` half the point's size in pixels. The pixel offset becomes an eye-space
// offset on the plane parallel to the image through the point (x_ndc = P00·x/w, y_ndc =
// P11·y/w, for both projections this renderer makes).
fn disc_corner(center: vec3<f32>, clip: vec4<f32>, eye_normal: vec3<f32>, corner: vec2<f32>, half_size: f32,
               projection: mat4x4<f32>, viewport: vec2<f32>) -> DiscCorner {
    let eye_offset = corner * half_size * (2.0 / viewport) * clip.w / vec2<f32>(projection[0][0], projection[1][1]);
    var out: DiscCorner;
    out.on_image_plane = center + vec3<f32>(eye_offset, 0.0);
    out.radius = half_size * (2.0 / viewport.y) * clip.w / projection[1][1];
    // The way to the camera: from the point (perspective, P33 = 0), or +z (orthographic, P33 = 1).
    let to_camera = mix(-center, vec3<f32>(0.0, 0.0, 1.0), projection[3][3]);
    out.normal = select(eye_normal, -eye_normal, dot(eye_normal, to_camera) < 0.0);
    return out;
}

// The disc's point under the pixel whose ray passes through `on_image_plane`, with w = 1;
// w = 0 where the pixel misses the disc. `normal` is unit length.
fn point_on_disc(center: vec3<f32>, normal: vec3<f32>, on_image_plane: vec3<f32>, radius: f32, projection: mat4x4<f32>) -> vec4<f32> {
    // The pixel ray: from the eye through the pixel, or along −z for an orthographic camera.
    let ray = mix(on_image_plane, vec3<f32>(0.0, 0.0, -1.0), projection[3][3]);
    let facing = min(dot(normal, ray), -MIN_DISC_COSINE * length(ray));
    let on_disc = on_image_plane + ray * (dot(normal, center - on_image_plane) / facing);
    let from_center = on_disc - center;
    return vec4<f32>(on_disc, select(0.0, 1.0, dot(from_center, from_center) <= radius * radius));
}
