// The fragment's output: the lit color combined with the surface's maps and texture
// (docs/conventions.md#textures), clamped to [0, 1] per channel and encoded; alpha 1
// (opaque) unless the material blends or masks (chunks/surface/alpha_mode.wgsl).

fn total_light(lit: LitColor) -> vec3<f32> {
#if SPECULAR
    return lit.ambient_diffuse + lit.specular;
#else
    return lit.ambient_diffuse;
#endif
}

// The surface's own alpha: the material's diffuse alpha (× the vertex color's).
fn surface_alpha() -> f32 {
    var alpha = object_uniforms.material.diffuse.a;
#hook output.surface_alpha  // (vertex colors)
    return alpha;
}

// The clamped output colour, encoded for the target.
fn output_rgb(rgb: vec3<f32>) -> vec3<f32> {
    var encoded = clamp(rgb, vec3<f32>(0.0), vec3<f32>(1.0));
#hook output.encoding  // (sRGB output)
    return encoded;
}

fn final_color(lit_in: LitColor) -> vec4<f32> {
    var lit = lit_in;
#hook output.lit  // what changes the lit color itself (a specular map colours the highlight)
    var alpha = surface_alpha();
    var rgb = total_light(lit);
#hook output.surface  // the surface's color over the lit color (the base color texture's modes)
#hook output.emission  // light the surface gives off, patterned by a map
#hook output.alpha  // what changes the surface's alpha (an alpha map)
    return vec4<f32>(output_rgb(rgb), output_alpha(alpha));
}
