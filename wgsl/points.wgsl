// Points (docs/primitives.md#points): each point a screen-aligned quad of point_size pixels
// (strokes.wgsl), one instance per point, its attributes stepping per instance.
//
// A point without a normal (zero) is the square in its colour: the material's diffuse
// colour × its vertex colour, as an unlit surface. With POINT_NORMALS, a point that has a
// normal is a small disc facing it (discs.wgsl), each pixel lit by the lighting equation
// at the disc's point under it with the point's normal: the disc's centre has exactly the
// lighting of the point itself.

#include "structs.wgsl"
#include "bindings.wgsl"
#include "lighting.wgsl"
#include "maps.wgsl"
#include "surface.wgsl"
#include "strokes.wgsl"
#if POINT_NORMALS
#include "discs.wgsl"
#endif

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
#if VERTEX_COLORS
    @location(0) @interpolate(flat) color: vec4<f32>,
#endif
#if POINT_NORMALS
    @location(1) @interpolate(flat) center: vec3<f32>,
    @location(2) @interpolate(flat) normal: vec3<f32>,
    @location(3) on_image_plane: vec3<f32>,
    @location(4) @interpolate(flat) radius: f32,
#endif
}

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32, point: VertexInput) -> Varyings {
    let center = object_uniforms.eye_from_model * vec4<f32>(point.position, 1.0);
    let clip = frame_uniforms.clip_from_eye * center;
    let corner = vec2<f32>(2.0 * quad_corner(vertex_index).x - 1.0, quad_corner(vertex_index).y);  // (±1, ±1)
    let half_size = 0.5 * object_uniforms.stroke_pixels;
    var out: Varyings;
    out.clip_position = moved_by_pixels(clip, corner * half_size, object_uniforms.viewport_size);
#if VERTEX_COLORS
    out.color = point.color;
#endif
#if POINT_NORMALS
    let disc = disc_corner(center.xyz, clip, object_uniforms.eye_normal_from_model * point.normal, corner, half_size,
                           frame_uniforms.clip_from_eye, object_uniforms.viewport_size);
    out.center = center.xyz;
    out.normal = disc.normal;
    out.on_image_plane = disc.on_image_plane;
    out.radius = disc.radius;
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
        let on_disc = point_on_disc(in.center, normal, in.on_image_plane, in.radius, frame_uniforms.clip_from_eye);
        if (on_disc.w == 0.0) {
            discard;
        }
        return final_color(shade(on_disc.xyz, normal, view_direction(on_disc.xyz, normal)));
    }
    // a point without a normal: its colour, unlit
    var plain: LitColor;
    plain.ambient_diffuse = material_diffuse();
    return final_color(plain);
#else
    return final_color(shade(vec3<f32>(0.0), FALLBACK_NORMAL, FALLBACK_NORMAL));
#endif
}
