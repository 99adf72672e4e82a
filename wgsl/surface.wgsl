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

// The clamped output colour, sRGB-encoded in linear colour space (glTF).
fn output_rgb(rgb: vec3<f32>) -> vec3<f32> {
    let clamped = clamp(rgb, vec3<f32>(0.0), vec3<f32>(1.0));
#if SRGB_OUTPUT
    return srgb_encode(clamped);
#else
    return clamped;
#endif
}

#if UVS
fn final_color(lit_in: LitColor, uv: vec2<f32>) -> vec4<f32> {
#else
fn final_color(lit_in: LitColor) -> vec4<f32> {
#endif
    var lit = lit_in;
#if SPECULAR_MAP and SPECULAR
    // The specular map colours the highlight (map_Ks: × the specular colour).
    lit.specular *= textureSample(specular_map_texture, specular_map_sampler, uv).rgb;
#endif
    var alpha = surface_alpha();
#if TEXTURE
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
    var rgb = texel.rgb * total_light(lit);
#else
    // An ADS material with a texture on top (tarnish on silver): an even mix.
    var rgb = 0.5 * texel.rgb + 0.5 * total_light(lit);
#endif
    alpha *= texel.a;
#else
    var rgb = total_light(lit);
#endif
#if EMISSIVE_MAP and EMISSION
    // Light the surface gives off, patterned by the map: added after the texture combine.
    rgb += object_uniforms.material.emission.rgb * textureSample(emissive_map_texture, emissive_map_sampler, uv).rgb;
#endif
#if ALPHA_MAP
    alpha *= textureSample(alpha_map_texture, alpha_map_sampler, uv).r;
#endif
    return vec4<f32>(output_rgb(rgb), output_alpha(alpha));
}
