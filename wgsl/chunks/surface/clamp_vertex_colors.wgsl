#if CLAMP_VERTEX_COLORS
// [shading] clamp_vertex_colors (flat and Gouraud): OpenGL fixed-function clamps each
// vertex's color to [0, 1] before interpolation. Its default (GL_SINGLE_COLOR) clamps the
// whole sum; the `modulate` texture mode is GL_SEPARATE_SPECULAR_COLOR, which clamps the
// primary (ambient + diffuse + emission) and secondary (specular) colors apart. The
// fragment's final clamp stays.
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

#at vertex_lit.color
    lit = clamped_vertex_color(lit);
#end
#endif
