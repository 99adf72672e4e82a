// The frequencies that light in the vertex stage (Gouraud per vertex, flat per face). Each
// declares its own Varyings (interpolated for Gouraud, flat for flat shading) with the same
// lit-color fields; these two functions fill and read them.

#if CLAMP_VERTEX_COLORS
// [shading] clamp_vertex_colors: OpenGL fixed-function clamps each vertex's color to [0, 1]
// before interpolation. Its default (GL_SINGLE_COLOR) clamps the whole sum; the `modulate`
// texture mode is GL_SEPARATE_SPECULAR_COLOR, which clamps the primary (ambient + diffuse
// + emission) and secondary (specular) colors apart. The fragment's final clamp stays.
fn clamped_vertex_color(lit: LitColor) -> LitColor {
    var out: LitColor;
#if SPECULAR
#if TEXTURE_MODULATE
    out.ambient_diffuse = clamp(lit.ambient_diffuse, vec3<f32>(0.0), vec3<f32>(1.0));
    out.specular = clamp(lit.specular, vec3<f32>(0.0), vec3<f32>(1.0));
#else
    out.ambient_diffuse = clamp(lit.ambient_diffuse + lit.specular, vec3<f32>(0.0), vec3<f32>(1.0));
    out.specular = vec3<f32>(0.0);
#endif
#else
    out.ambient_diffuse = clamp(lit.ambient_diffuse, vec3<f32>(0.0), vec3<f32>(1.0));
#endif
    return out;
}
#endif

// The color one vertex (or face) passes on: unclamped like the seeds' GLSL, or clamped.
fn vertex_color(eye_position: vec3<f32>, normal: vec3<f32>) -> LitColor {
#if CLAMP_VERTEX_COLORS
    return clamped_vertex_color(shade(eye_position, normal, view_direction(eye_position, normal)));
#else
    return shade(eye_position, normal, view_direction(eye_position, normal));
#endif
}

// Lights one point and stores the colors: the front color, and with two-sided lighting a
// back color lit with -N (OpenGL computes both per vertex and picks one per fragment).
fn store_lighting(out: ptr<function, Varyings>, eye_position: vec3<f32>, normal: vec3<f32>) {
    let front = vertex_color(eye_position, normal);
    (*out).front_ambient_diffuse = front.ambient_diffuse;
#if SPECULAR
    (*out).front_specular = front.specular;
#endif
#if TWO_SIDED
    let back = vertex_color(eye_position, -normal);
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
#if UVS
    return final_color(lit, in.uv);
#else
    return final_color(lit);
#endif
}
