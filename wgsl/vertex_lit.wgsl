// The frequencies that light in the vertex stage (Gouraud per vertex, flat per face). Each
// declares its own Varyings (interpolated for Gouraud, flat for flat shading) with the same
// lit-color fields; these two functions fill and read them.

// Lights one point and stores the colors: the front color, and with two-sided lighting a
// back color lit with -N (OpenGL computes both per vertex and picks one per fragment).
fn store_lighting(out: ptr<function, Varyings>, eye_position: vec3<f32>, normal: vec3<f32>) {
    let front = shade(eye_position, normal, view_direction(eye_position, normal));
    (*out).front_ambient_diffuse = front.ambient_diffuse;
#if SPECULAR
    (*out).front_specular = front.specular;
#endif
#if TWO_SIDED
    let back = shade(eye_position, -normal, view_direction(eye_position, -normal));
    (*out).back_ambient_diffuse = back.ambient_diffuse;
#if SPECULAR
    (*out).back_specular = back.specular;
#endif
#endif
}

// Only the texture and the final clamp happen per fragment.
@fragment
fn fs_main(
    in: Varyings,
#if TWO_SIDED
    @builtin(front_facing) front_facing: bool,
#endif
) -> @location(0) vec4<f32> {
    var lit: LitColor;
    lit.ambient_diffuse = in.front_ambient_diffuse;
#if SPECULAR
    lit.specular = in.front_specular;
#endif
#if TWO_SIDED
    if (!front_facing) {
        lit.ambient_diffuse = in.back_ambient_diffuse;
#if SPECULAR
        lit.specular = in.back_specular;
#endif
    }
#endif
#if TEXTURE
    return final_color(lit, in.uv);
#else
    return final_color(lit);
#endif
}
