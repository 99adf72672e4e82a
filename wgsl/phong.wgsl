// Phong shading: lighting per fragment (the seed's Phong vertex and fragment shaders).
// The vertex stage passes the eye-space position and normal; the rasterizer interpolates
// them (perspective-correct) and each fragment renormalizes N and evaluates every light.
// L and V are recomputed from the interpolated position, which equals interpolating them.

#include "structs.wgsl"
#include "bindings.wgsl"
#include "lighting.wgsl"
#include "maps.wgsl"
#include "surface.wgsl"


struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) eye_position: vec3<f32>,
    @location(1) eye_normal: vec3<f32>,
#if UVS
    @location(2) uv: vec2<f32>,
#endif
#if VERTEX_COLORS
    @location(3) color: vec4<f32>,
#endif
#if VERTEX_TANGENTS
    // The file's tangent in eye space; w: the handedness, times the sign of the
    // transform's determinant (a mirror flips the bitangent).
    @location(4) eye_tangent: vec4<f32>,
#endif
}

@vertex
fn vs_main(vertex: VertexInput) -> Varyings {
    let eye_position = object_uniforms.eye_from_model * vec4<f32>(vertex.position, 1.0);
    var out: Varyings;
    out.clip_position = frame_uniforms.clip_from_eye * eye_position;
    out.eye_position = eye_position.xyz;
    // Left unnormalized: the fragment stage normalizes after interpolation anyway.
    out.eye_normal = object_uniforms.eye_normal_from_model * vertex.normal;
#if UVS
    out.uv = vertex.uv;
#endif
#if VERTEX_COLORS
    out.color = vertex.color;
#endif
#if VERTEX_TANGENTS
    let linear = mat3x3<f32>(object_uniforms.eye_from_model[0].xyz, object_uniforms.eye_from_model[1].xyz, object_uniforms.eye_from_model[2].xyz);
    out.eye_tangent = vec4<f32>(linear * vertex.tangent.xyz, vertex.tangent.w * sign(determinant(linear)));
#endif
    return out;
}

@fragment
fn fs_main(
    in: Varyings,
#if TWO_SIDED
    @builtin(front_facing) front_facing: bool,
#endif
) -> @location(0) vec4<f32> {
    // The interpolated normal can pass through zero (opposite normals on one triangle).
    var normal = safe_normalize(in.eye_normal, FALLBACK_NORMAL);
#if NORMAL_MAP or BUMP_MAP
    var face_sign = 1.0;
#endif
#if TWO_SIDED
    // GL_LIGHT_MODEL_TWO_SIDE: back faces are lit with the flipped normal.
    if (!front_facing) {
        normal = -normal;
#if NORMAL_MAP or BUMP_MAP
        face_sign = -1.0;
#endif
    }
#endif
#if NORMAL_MAP or BUMP_MAP
    let mapped = map_normal(in.uv);
    // The derivative frame is computed in uniform control flow (dpdx) even where the file's
    // tangents replace it.
    normal = perturbed_normal(normal, in.eye_position, in.uv, mapped, face_sign);
#if VERTEX_TANGENTS
    normal = vertex_tangent_normal(safe_normalize(in.eye_normal, FALLBACK_NORMAL), in.eye_tangent, mapped, face_sign, normal);
#endif
#endif
#if OCCLUSION_MAP or SHININESS_MAP
    read_fragment_maps(in.uv);
#endif
#if VERTEX_COLORS
    surface_color = in.color;
#endif
    let lit = shade(in.eye_position, normal, view_direction(in.eye_position, normal));
#if UVS
    return final_color(lit, in.uv);
#else
    return final_color(lit);
#endif
}
