// Gouraud shading: lighting per vertex (the seed's Gouraud vertex shader), colors
// interpolated by the rasterizer. Highlights that fall inside a triangle are lost on
// coarse meshes: that is the method, not a bug. Colors are clamped after interpolation,
// as the seed's shader does (its varyingColor is not clamped in the vertex stage).

#include "structs.wgsl"
#include "bindings.wgsl"
#include "lighting.wgsl"
#include "maps.wgsl"
#include "surface.wgsl"


struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) front_ambient_diffuse: vec3<f32>,
#if SPECULAR
    @location(1) front_specular: vec3<f32>,
#endif
#if TWO_SIDED
    // OpenGL's two-sided lighting computes a second color per vertex for back faces.
    @location(2) back_ambient_diffuse: vec3<f32>,
#if SPECULAR
    @location(3) back_specular: vec3<f32>,
#endif
#endif
#if UVS
    @location(4) uv: vec2<f32>,
#endif
}

@vertex
fn vs_main(vertex: VertexInput) -> Varyings {
    let eye_position = object_uniforms.eye_from_model * vec4<f32>(vertex.position, 1.0);
    let normal = safe_normalize(object_uniforms.eye_normal_from_model * vertex.normal, FALLBACK_NORMAL);
    var out: Varyings;
    out.clip_position = frame_uniforms.clip_from_eye * eye_position;
#if VERTEX_COLORS
    surface_color = vertex.color;
#endif
#if OCCLUSION_MAP or SHININESS_MAP
    read_vertex_maps(vertex.uv);
#endif
    store_lighting(&out, eye_position.xyz, normal);
#if UVS
    out.uv = vertex.uv;
#endif
    return out;
}

#include "vertex_lit.wgsl"
