#if POINT_NORMALS
// Points with normals as small discs (docs/primitives.md#points): the disc lies in the
// plane through the point perpendicular to its normal; seen face-on it fills the circle
// inscribed in the point's quad (point_size pixels across), seen at an angle it is the
// ellipse that plane cuts out of the pixel rays. The colour pass lights each pixel of the
// disc at the disc's point under it with the point's normal (so the disc's centre has the
// lighting of the point itself); the extra outputs cover the same pixels. A point whose
// normal is zero stays a square in its colour.

// Below this cosine between the normal and a pixel ray a disc is drawn as if seen at this
// angle (an ellipse 1/20 as wide as long) instead of vanishing edge-on.
const MIN_DISC_COSINE: f32 = 0.05;

// The disc's point under the pixel whose ray passes through `on_image_plane`, with w = 1;
// w = 0 where the pixel misses the disc, w = 2 for a point without a normal (a square).
// `projection` is the camera's clip_from_eye ([3][3]: 0 perspective, 1 orthographic).
fn pixel_on_disc(center: vec3<f32>, disc_normal: vec3<f32>, on_image_plane: vec3<f32>, radius: f32, projection: mat4x4<f32>) -> vec4<f32> {
    let length_squared = dot(disc_normal, disc_normal);
    if (!(length_squared > MIN_LENGTH_SQUARED)) {
        return vec4<f32>(center, 2.0);
    }
    let normal = disc_normal * inverseSqrt(length_squared);
    // The pixel ray: from the eye through the pixel, or along −z for an orthographic camera.
    let ray = mix(on_image_plane, vec3<f32>(0.0, 0.0, -1.0), projection[3][3]);
    let facing = min(dot(normal, ray), -MIN_DISC_COSINE * length(ray));
    let on_disc = on_image_plane + ray * (dot(normal, center - on_image_plane) / facing);
    let from_center = on_disc - center;
    return vec4<f32>(on_disc, select(0.0, 1.0, dot(from_center, from_center) <= radius * radius));
}

// What the vertex stage hands a disc's pixels, in eye space: the point, its normal turned
// towards the camera (scanners' normals often have no consistent sign), this corner of the
// quad on the plane through the point parallel to the image, and the disc's radius.
#at points.varyings points_outputs.varyings
    @location(1) @interpolate(flat) disc_center: vec3<f32>,
    @location(2) @interpolate(flat) disc_normal: vec3<f32>,
    @location(3) on_image_plane: vec3<f32>,
    @location(4) @interpolate(flat) disc_radius: f32,
#end
// The pixel offset becomes an eye-space offset on the plane parallel to the image through
// the point (x_ndc = P00·x/w, y_ndc = P11·y/w for both projections this renderer makes).
#at points.vertex points_outputs.vertex
    let eye_normal = normal_matrix * vertex.normal;
    // the way to the camera: from the point (perspective, P33 = 0), or +z (orthographic, P33 = 1)
    let to_camera = mix(-center.xyz, vec3<f32>(0.0, 0.0, 1.0), projection[3][3]);
    out.disc_normal = select(eye_normal, -eye_normal, dot(eye_normal, to_camera) < 0.0);
    out.disc_center = center.xyz;
    let eye_offset = corner * half_size * (2.0 / viewport) * clip.w / vec2<f32>(projection[0][0], projection[1][1]);
    out.on_image_plane = center.xyz + vec3<f32>(eye_offset, 0.0);
    out.disc_radius = half_size * (2.0 / viewport.y) * clip.w / projection[1][1];
#end
#at points_outputs.vertex
    // the output normal, turned towards the camera as in the lit pass
    out.normal = extra_uniforms.output_normal_from_model * vertex.normal * select(1.0, -1.0, dot(eye_normal, to_camera) < 0.0);
#end
#at points.fragment_lit
    let on_disc = pixel_on_disc(in.disc_center, in.disc_normal, in.on_image_plane, in.disc_radius, projection);
    if (on_disc.w == 0.0) {
        discard;
    }
    if (on_disc.w == 1.0) {
        let normal = normalize(in.disc_normal);
        lit = shade(on_disc.xyz, normal, view_direction(on_disc.xyz, normal));
    }
#end
#at points_outputs.fragment
    if (pixel_on_disc(in.disc_center, in.disc_normal, in.on_image_plane, in.disc_radius, projection).w == 0.0) {
        discard;
    }
#end
#endif
