// The frequencies that light in the vertex stage (Gouraud per vertex, flat per face). Each
// declares its own Varyings (interpolated for Gouraud, flat for flat shading) with the same
// lit-color fields; these functions fill and read them.

// The color one vertex (or face) passes on: unclamped like the seeds' GLSL, or clamped.
fn vertex_color(eye_position: vec3<f32>, normal: vec3<f32>) -> LitColor {
    var lit = shade(eye_position, normal, view_direction(eye_position, normal));
#hook vertex_lit.color  // (clamped vertex colors)
    return lit;
}

// Lights one point and stores its front color (and, with two-sided lighting, its back color).
fn store_lighting(out: ptr<function, Varyings>, eye_position: vec3<f32>, normal: vec3<f32>) {
    let front = vertex_color(eye_position, normal);
    (*out).front_ambient_diffuse = front.ambient_diffuse;
#if SPECULAR
    (*out).front_specular = front.specular;
#endif
#hook vertex_lit.store  // more colors to pass on (two-sided lighting's back color)
}

// Only the texture and the final clamp happen per fragment.
@fragment
fn fs_main(
    in: Varyings,
#hook vertex_lit.fragment_inputs
) -> @location(0) vec4<f32> {
#hook vertex_lit.fragment_begin  // (the uv of this fragment)
    var lit: LitColor;
    lit.ambient_diffuse = in.front_ambient_diffuse;
#if SPECULAR
    lit.specular = in.front_specular;
#endif
#hook vertex_lit.fragment_lit  // which color this fragment takes (two-sided lighting)
    return final_color(lit);
}
