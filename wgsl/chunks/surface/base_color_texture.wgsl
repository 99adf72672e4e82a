#if TEXTURE
// The base color texture and its modes (docs/conventions.md#textures): the texel replaces
// the surface color under ambient and diffuse light (modulate), also under the highlight
// (modulate_all), or is mixed evenly with the lit color (blend); its alpha multiplies the
// surface's.
#at output.surface
    let texel = textureSample(base_color_texture, base_color_sampler, surface_uv_of(BASE_COLOR_UV_SET));
#if TEXTURE_MODULATE
    // A texture showing the real surface: it replaces the surface color under ambient and
    // diffuse light; the highlight stays the light's color. Without a material this is the
    // seed's material-less example (material colors all 1).
    rgb = texel.rgb * lit.ambient_diffuse;
#if SPECULAR
    rgb += lit.specular;
#endif
#elif TEXTURE_MODULATE_ALL
    // Highlights that carry the surface color (fabric, unpainted wood).
    rgb = texel.rgb * total_light(lit);
#else
    // An ADS material with a texture on top (tarnish on silver): an even mix.
    rgb = 0.5 * texel.rgb + 0.5 * total_light(lit);
#endif
    alpha *= texel.a;
#end
#endif
