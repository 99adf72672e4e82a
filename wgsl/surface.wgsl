// The fragment's output: lighting combined with the texture (docs/conventions.md#textures), clamped to [0, 1]
// per channel. Alpha: 1 (opaque), unless the material blends (its
// diffuse alpha × the texel's) or masks (discarded below the cutoff, else 1).

fn output_alpha(alpha: f32) -> f32 {
#if ALPHA_MASK
    if (alpha < object_uniforms.material.alpha_cutoff) {
        discard;
    }
    return 1.0;
#elif ALPHA_BLEND
    return alpha;
#else
    return 1.0;
#endif
}

fn surface_alpha() -> f32 {
#if VERTEX_COLORS
    return object_uniforms.material.diffuse.a * surface_color.a;
#else
    return object_uniforms.material.diffuse.a;
#endif
}

fn total_light(lit: LitColor) -> vec3<f32> {
#if SPECULAR
    return lit.ambient_diffuse + lit.specular;
#else
    return lit.ambient_diffuse;
#endif
}

#if TEXTURE
fn final_color(lit: LitColor, uv: vec2<f32>) -> vec4<f32> {
    let texel = textureSample(base_color_texture, base_color_sampler, uv);
#if TEXTURE_MODULATE
    // A texture showing the real surface: it replaces the surface color under ambient and
    // diffuse light; the highlight stays the light's color. Without a material this is the
    // seed's material-less example (material colors all 1).
    var rgb = texel.rgb * lit.ambient_diffuse;
#if SPECULAR
    rgb += lit.specular;
#endif
#elif TEXTURE_MODULATE_ALL
    // Highlights that carry the surface color (fabric, unpainted wood).
    let rgb = texel.rgb * total_light(lit);
#else
    // An ADS material with a texture on top (tarnish on silver): an even mix.
    let rgb = 0.5 * texel.rgb + 0.5 * total_light(lit);
#endif
    return vec4<f32>(clamp(rgb, vec3<f32>(0.0), vec3<f32>(1.0)), output_alpha(surface_alpha() * texel.a));
}
#else
fn final_color(lit: LitColor) -> vec4<f32> {
    return vec4<f32>(clamp(total_light(lit), vec3<f32>(0.0), vec3<f32>(1.0)), output_alpha(surface_alpha()));
}
#endif
