// Phong shading: lighting per fragment (the seed's Phong vertex and fragment shaders).
// The vertex stage passes the eye-space position and normal; the rasterizer interpolates
// them (perspective-correct) and each fragment renormalizes N and evaluates every light.
// L and V are recomputed from the interpolated position, which equals interpolating them.

#include "structs.wgsl"
#include "bindings.wgsl"
#include "lighting.wgsl"
#include "output.wgsl"
// The surface's effects, one chunk each: what they declare is pasted here, what they do
// at the named points (#hook) below.
#include "chunks/surface/uvs.wgsl"
#include "chunks/surface/uv_sets.wgsl"
#include "chunks/surface/vertex_colors.wgsl"
#include "chunks/surface/two_sided.wgsl"
#include "chunks/maps/normal_map.wgsl"
#include "chunks/maps/occlusion_map.wgsl"
#include "chunks/maps/shininess_map.wgsl"
#include "chunks/maps/specular_map.wgsl"
#include "chunks/surface/base_color_texture.wgsl"
#include "chunks/maps/emissive_map.wgsl"
#include "chunks/maps/alpha_map.wgsl"
#include "chunks/surface/alpha_mode.wgsl"
#include "chunks/surface/srgb_output.wgsl"
#include "chunks/shadows/lookup.wgsl"
#include "chunks/shadows/visibility.wgsl"

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) eye_position: vec3<f32>,
    @location(1) eye_normal: vec3<f32>,
#hook phong.varyings
}

@vertex
fn vs_main(vertex: VertexInput) -> Varyings {
    let eye_position = object_uniforms.eye_from_model * vec4<f32>(vertex.position, 1.0);
    var out: Varyings;
    out.clip_position = frame_uniforms.clip_from_eye * eye_position;
    out.eye_position = eye_position.xyz;
    // Left unnormalized: the fragment stage normalizes after interpolation anyway.
    out.eye_normal = object_uniforms.eye_normal_from_model * vertex.normal;
#hook phong.vertex
    return out;
}

@fragment
fn fs_main(
    in: Varyings,
#hook phong.fragment_inputs
) -> @location(0) vec4<f32> {
#hook phong.fragment_begin  // (the uv of this fragment)
    // The interpolated normal can pass through zero (opposite normals on one triangle).
    var normal = safe_normalize(in.eye_normal, FALLBACK_NORMAL);
    // 1 on front faces, −1 on the back faces that two-sided lighting flips.
    var face_sign = 1.0;
#hook phong.fragment_normal  // what turns the normal: two-sided lighting, normal and bump maps
#hook phong.fragment_surface  // the surface here before it is lit: maps read per fragment, vertex colors
    let lit = shade(in.eye_position, normal, view_direction(in.eye_position, normal));
    return final_color(lit);
}
