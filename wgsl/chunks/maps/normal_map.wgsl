#if NORMAL_MAP or BUMP_MAP
// Normal and bump maps (Phong shading: per-fragment normals): the normal turned by the
// tangent-space normal the maps give, in the per-fragment derivative frame, or in the
// file's tangent frame where the mesh has tangents (glTF TANGENT).
// The tangent-space normal the maps give at uv: texel·2 − 1, the normal map's x and y
// scaled by normal_scale. With both maps their slopes add ("whiteout" blending).
fn map_normal(uv: vec2<f32>) -> vec3<f32> {
#if NORMAL_MAP
    let from_normal_map = textureSample(normal_map_texture, normal_map_sampler, uv).xyz * 2.0 - 1.0;
    var tangent_normal = vec3<f32>(from_normal_map.xy * object_uniforms.material.normal_scale, from_normal_map.z);
#endif
#if BUMP_MAP
    let from_bump_map = textureSample(bump_map_texture, bump_map_sampler, uv).xyz * 2.0 - 1.0;
#if NORMAL_MAP
    tangent_normal = vec3<f32>(tangent_normal.xy + from_bump_map.xy, tangent_normal.z * from_bump_map.z);
#else
    let tangent_normal = from_bump_map;
#endif
#endif
    return tangent_normal;
}

// The surface normal turned by the tangent-space normal `mapped`, in the per-fragment
// derivative frame of three.js (getTangentFrame; C. Schüler, "Normal mapping without
// precomputed tangents", 2013): T and B follow u and v across the triangle, from the
// screen-space derivatives of the eye position and the uv, projected perpendicular to N.
// No TANGENT attribute is needed or read. WGSL's dpdy runs down the framebuffer, so it is
// negated to get OpenGL's upward y, which three.js' formula assumes. `face_sign` is −1 on
// back faces of two-sided lighting (three.js' faceDirection).
fn perturbed_normal(normal: vec3<f32>, eye_position: vec3<f32>, uv: vec2<f32>, mapped: vec3<f32>, face_sign: f32) -> vec3<f32> {
    let q0 = dpdx(eye_position);
    let q1 = -dpdy(eye_position);
    let st0 = dpdx(uv);
    let st1 = -dpdy(uv);
    let q1_perpendicular = cross(q1, normal);
    let q0_perpendicular = cross(normal, q0);
    let tangent = q1_perpendicular * st0.x + q0_perpendicular * st1.x;
    let bitangent = q1_perpendicular * st0.y + q0_perpendicular * st1.y;
    let largest = max(dot(tangent, tangent), dot(bitangent, bitangent));
    var scale = 0.0;  // uvs that do not change across the triangle: no frame, N as it is
    if (largest > 0.0) {
        scale = face_sign * inverseSqrt(largest);
    }
    return safe_normalize(tangent * (scale * mapped.x) + bitangent * (scale * mapped.y) + normal * mapped.z, normal);
}

#at phong.fragment_normal
#if NORMAL_MAP
    let normal_uv = surface_uv_of(NORMAL_MAP_UV_SET);  // (a bump map, from OBJ, reads set 0 with it)
#else
    let normal_uv = surface_uv_of(BUMP_MAP_UV_SET);
#endif
    let mapped = map_normal(normal_uv);
    // The derivative frame is computed in uniform control flow (dpdx) even where the file's
    // tangents replace it.
    normal = perturbed_normal(normal, in.eye_position, normal_uv, mapped, face_sign);
#if VERTEX_TANGENTS
    normal = vertex_tangent_normal(safe_normalize(in.eye_normal, FALLBACK_NORMAL), in.eye_tangent, mapped, face_sign, normal);
#endif
#end

#if VERTEX_TANGENTS
// The surface normal turned by `mapped` in the file's tangent frame (glTF TANGENT, as
// three.js with vertex tangents): T = normalize(t − N·(N·t)), B = (N × T)·w, with N the
// front face's normal (`front_normal`); on back faces of two-sided lighting T and B are
// negated like the derivative frame's. Where the tangent is missing (zero) or parallel
// to N, `derivative` (the derivative frame's result) is kept.
fn vertex_tangent_normal(front_normal: vec3<f32>, tangent: vec4<f32>, mapped: vec3<f32>, face_sign: f32, derivative: vec3<f32>) -> vec3<f32> {
    let projected = tangent.xyz - front_normal * dot(front_normal, tangent.xyz);
    let length_squared = dot(projected, projected);
    if (!(length_squared > 1e-12 * max(dot(tangent.xyz, tangent.xyz), 1e-30))) {
        return derivative;
    }
    let t = projected * inverseSqrt(length_squared);
    let handedness = select(-1.0, 1.0, tangent.w >= 0.0);
    let b = cross(front_normal, t) * handedness;
    let normal = front_normal * face_sign;
    return safe_normalize((t * mapped.x + b * mapped.y) * face_sign + normal * mapped.z, normal);
}

#at phong.varyings
    // The file's tangent in eye space; w: the handedness, times the sign of the
    // transform's determinant (a mirror flips the bitangent).
    @location(4) eye_tangent: vec4<f32>,
#end
#at phong.vertex
    let linear = mat3x3<f32>(object_uniforms.eye_from_model[0].xyz, object_uniforms.eye_from_model[1].xyz, object_uniforms.eye_from_model[2].xyz);
    out.eye_tangent = vec4<f32>(linear * vertex.tangent.xyz, vertex.tangent.w * sign(determinant(linear)));
#end
#endif
#endif
