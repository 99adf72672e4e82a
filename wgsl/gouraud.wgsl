// Gouraud shading: lighting per vertex (the seed's Gouraud vertex shader), colors
// interpolated by the rasterizer. Highlights that fall inside a triangle are lost on
// coarse meshes: that is the method, not a bug. Colors are clamped after interpolation,
// as the seed's shader does (its varyingColor is not clamped in the vertex stage).

#include "structs.wgsl"
#include "bindings.wgsl"
#include "lighting.wgsl"
#include "output.wgsl"
// The surface's effects, one chunk each: what they declare is pasted here, what they do
// at the named points (#hook) below and in vertex_lit.wgsl.
#include "chunks/surface/uvs.wgsl"
#include "chunks/surface/uv_sets.wgsl"
#include "chunks/surface/vertex_colors.wgsl"
#include "chunks/surface/two_sided.wgsl"
#include "chunks/surface/clamp_vertex_colors.wgsl"
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
#include "chunks/shadows/shares.wgsl"

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) front_ambient_diffuse: vec3<f32>,
#if SPECULAR
    @location(1) front_specular: vec3<f32>,
#endif
#hook gouraud.varyings
}

@vertex
fn vs_main(vertex: VertexInput) -> Varyings {
    let eye_position = object_uniforms.eye_from_model * vec4<f32>(vertex.position, 1.0);
    let normal = safe_normalize(object_uniforms.eye_normal_from_model * vertex.normal, FALLBACK_NORMAL);
    var out: Varyings;
    out.clip_position = frame_uniforms.clip_from_eye * eye_position;
#hook gouraud.vertex_surface  // the surface here before it is lit: maps read per vertex, vertex colors
    store_lighting(&out, eye_position.xyz, normal);
#hook gouraud.vertex
    return out;
}

#include "vertex_lit.wgsl"
