// Points (docs/primitives.md): each point a screen-aligned quad of point_size pixels
// (strokes.wgsl), one instance per point, its attributes stepping per instance.
//
// A point without a normal (zero) is the square in its colour: the material's diffuse
// colour × its vertex colour, as an unlit surface. With POINT_NORMALS, a point that has a
// normal is a small disc in the plane through the point perpendicular to its normal: the
// disc seen face-on fills the circle inscribed in the quad (point_size across), seen at an
// angle it is the ellipse that plane cuts out of the pixel rays. Each pixel of the disc is
// lit by the lighting equation at the disc's point under it, with the point's normal
// turned towards the camera (scanners' normals often have no consistent sign), so the
// disc's centre has exactly the lighting of the point itself.

#include "structs.wgsl"
#include "bindings.wgsl"
#include "lighting.wgsl"
#include "surface.wgsl"
#include "strokes.wgsl"

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
#if VERTEX_COLORS
    @location(0) @interpolate(flat) color: vec4<f32>,
#endif
#if POINT_NORMALS
    // Eye space: the point, its normal facing the camera (zero: unlit), and this corner of
    // the quad on the plane through the point parallel to the image (the disc's bounding square).
    @location(1) @interpolate(flat) center: vec3<f32>,
    @location(2) @interpolate(flat) normal: vec3<f32>,
    @location(3) on_image_plane: vec3<f32>,
    // The disc's radius in eye units.
    @location(4) @interpolate(flat) radius: f32,
#endif
}

// Below this cosine between the normal and the line of sight a disc is drawn as if seen at
// this angle (an ellipse 1/20 as wide as long) instead of vanishing edge-on.
const MIN_DISC_COSINE: f32 = 0.05;

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32, point: VertexInput) -> Varyings {
    let center = object_uniforms.eye_from_model * vec4<f32>(point.position, 1.0);
    let clip = frame_uniforms.clip_from_eye * center;
    // corners ±1 on both axes: half a point across from the centre
    let corner = vec2<f32>(2.0 * quad_corner(vertex_index).x - 1.0, quad_corner(vertex_index).y);
    let half_size = 0.5 * object_uniforms.stroke_pixels;
    var out: Varyings;
    out.clip_position = moved_by_pixels(clip, corner * half_size);
#if VERTEX_COLORS
    out.color = point.color;
#endif
#if POINT_NORMALS
    // The pixel offset in eye units on the plane through the point parallel to the image
    // (x_ndc = P00·x/w, y_ndc = P11·y/w for both projections this renderer makes).
    let projection = frame_uniforms.clip_from_eye;
    let eye_offset = corner * half_size * (2.0 / object_uniforms.viewport_size) * clip.w / vec2<f32>(projection[0][0], projection[1][1]);
    out.center = center.xyz;
    out.on_image_plane = center.xyz + vec3<f32>(eye_offset, 0.0);
    out.radius = half_size * (2.0 / object_uniforms.viewport_size.y) * clip.w / projection[1][1];
    var normal = object_uniforms.eye_normal_from_model * point.normal;
    // the way to the camera: from the point for a perspective camera (P33 = 0), +z for an orthographic one (P33 = 1)
    let to_camera = mix(-center.xyz, vec3<f32>(0.0, 0.0, 1.0), projection[3][3]);
    if (dot(normal, to_camera) < 0.0) {
        normal = -normal;
    }
    out.normal = normal;
#endif
    return out;
}

@fragment
fn fs_main(in: Varyings) -> @location(0) vec4<f32> {
#if VERTEX_COLORS
    surface_color = in.color;
#endif
#if POINT_NORMALS
    let length_squared = dot(in.normal, in.normal);
    if (length_squared > MIN_LENGTH_SQUARED) {
        let normal = in.normal * inverseSqrt(length_squared);
        // The pixel ray (from the eye, or along −z for an orthographic camera) meets the
        // disc's plane at `on_disc`; outside the radius, the pixel is not the disc's.
        let ray = mix(in.on_image_plane, vec3<f32>(0.0, 0.0, -1.0), frame_uniforms.clip_from_eye[3][3]);
        let facing = min(dot(normal, ray), -MIN_DISC_COSINE * length(ray));
        let on_disc = in.on_image_plane + ray * (dot(normal, in.center - in.on_image_plane) / facing);
        let from_center = on_disc - in.center;
        if (dot(from_center, from_center) > in.radius * in.radius) {
            discard;
        }
        return final_color(shade(on_disc, normal, view_direction(on_disc, normal)));
    }
    // a point without a normal: its colour, unlit
    var plain: LitColor;
    plain.ambient_diffuse = material_diffuse();
    return final_color(plain);
#else
    return final_color(shade(vec3<f32>(0.0), FALLBACK_NORMAL, FALLBACK_NORMAL));
#endif
}
