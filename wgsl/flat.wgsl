// Flat shading: one color per triangle, from the face normal, lit once at the face
// centroid (the seeds: N, L and V treated as constant over the polygon).
//
// A shared vertex cannot carry one face's normal, so this stage pulls its vertices from
// storage buffers: a non-indexed draw of 3 × triangle-count vertices, where vertex k is
// corner k % 3 of triangle k / 3. Every corner computes the same face color, passed with
// flat interpolation (no per-pixel variation at all).

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

// Group 2 (the mesh: mesh_positions, mesh_indices, mesh_uvs, mesh_colors) is declared by
// the binding plan (wgpu_shading/render/shaders/bindings.py).

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) @interpolate(flat) front_ambient_diffuse: vec3<f32>,
#if SPECULAR
    @location(1) @interpolate(flat) front_specular: vec3<f32>,
#endif
#hook flat.varyings
}

fn model_position(vertex: u32) -> vec3<f32> {
    return vec3<f32>(mesh_positions[3u * vertex], mesh_positions[3u * vertex + 1u], mesh_positions[3u * vertex + 2u]);
}

@vertex
fn vs_main(@builtin(vertex_index) corner_index: u32) -> Varyings {
    let first = 3u * (corner_index / 3u);
    let p0 = model_position(mesh_indices[first]);
    let p1 = model_position(mesh_indices[first + 1u]);
    let p2 = model_position(mesh_indices[first + 2u]);
    let vertex = mesh_indices[corner_index];
    let corner = model_position(vertex);

    // Face normal in model space, to eye space with the normal matrix (correct under
    // non-uniform scale and mirroring). A zero-area face gets the fallback; it covers no
    // pixels anyway.
    let normal = safe_normalize(object_uniforms.eye_normal_from_model * cross(p1 - p0, p2 - p0), FALLBACK_NORMAL);
    let centroid = (object_uniforms.eye_from_model * vec4<f32>((p0 + p1 + p2) / 3.0, 1.0)).xyz;
    var out: Varyings;
    out.clip_position = frame_uniforms.clip_from_eye * (object_uniforms.eye_from_model * vec4<f32>(corner, 1.0));
#hook flat.vertex_surface  // the face before it is lit: maps read at its centroid, vertex colors
    store_lighting(&out, centroid, normal);
#hook flat.vertex
    return out;
}

#include "vertex_lit.wgsl"
