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
#include "maps.wgsl"
#include "surface.wgsl"

// Group 2 (the mesh: mesh_positions, mesh_indices, mesh_uvs, mesh_colors) is declared by
// the binding plan (wgpu_shading/render/shaders/bindings.py).

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) @interpolate(flat) front_ambient_diffuse: vec3<f32>,
#if SPECULAR
    @location(1) @interpolate(flat) front_specular: vec3<f32>,
#endif
#if TWO_SIDED
    @location(2) @interpolate(flat) back_ambient_diffuse: vec3<f32>,
#if SPECULAR
    @location(3) @interpolate(flat) back_specular: vec3<f32>,
#endif
#endif
#if UVS
    @location(4) uv: vec2<f32>,
#endif
}

fn model_position(vertex: u32) -> vec3<f32> {
    return vec3<f32>(mesh_positions[3u * vertex], mesh_positions[3u * vertex + 1u], mesh_positions[3u * vertex + 2u]);
}

#if UVS
fn model_uv(vertex: u32) -> vec2<f32> {
    return vec2<f32>(mesh_uvs[2u * vertex], mesh_uvs[2u * vertex + 1u]);
}
#endif

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
#if VERTEX_COLORS
    // One color per face, like its normal: the mean of its corners' colors.
    surface_color = (mesh_colors[mesh_indices[first]] + mesh_colors[mesh_indices[first + 1u]]
        + mesh_colors[mesh_indices[first + 2u]]) / 3.0;
#endif
#if OCCLUSION_MAP or SHININESS_MAP
    // The face's maps at its centroid's uv, like its normal and position.
    read_vertex_maps((model_uv(mesh_indices[first]) + model_uv(mesh_indices[first + 1u])
        + model_uv(mesh_indices[first + 2u])) / 3.0);
#endif
    store_lighting(&out, centroid, normal);
#if UVS
    out.uv = model_uv(vertex);
#endif
    return out;
}

#include "vertex_lit.wgsl"
