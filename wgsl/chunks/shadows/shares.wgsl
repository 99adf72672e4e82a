#if SHADOWS and not FREQUENCY_PHONG
// Shadows at the frequencies that light in the vertex stage (docs/shadows.md#flat-and-gouraud-shading):
// the vertex (or face) passes on each casting light's share of its colour, the colour with
// every light lit less the colour with that light hidden (clamped like the colour itself),
// and each fragment takes (1 − V) of every share off at its own point. A share is one vec3
// (the ambient-diffuse and specular parts added) unless a texture or a map treats the two
// apart (SHADOW_SPLIT). At most MAX_VERTEX_LIT_SHADOW_LIGHTS (render/features.py).

// Light `slot`'s share of the colour a vertex passes on.
fn light_share(eye_position: vec3<f32>, normal: vec3<f32>, full: LitColor, slot: u32) -> LitColor {
    light_switched_off = slot;
    let hidden = vertex_color(eye_position, normal);
    light_switched_off = 0xffffffffu;
    var share: LitColor;
    share.ambient_diffuse = full.ambient_diffuse - hidden.ambient_diffuse;
#if SPECULAR
    share.specular = full.specular - hidden.specular;
#endif
    return share;
}

// A share as its varyings: [ambient-diffuse (with the specular part added unless split), specular].
fn share_parts(share: LitColor) -> array<vec3<f32>, 2> {
#if SHADOW_SPLIT
    return array<vec3<f32>, 2>(share.ambient_diffuse, share.specular);
#elif SPECULAR
    return array<vec3<f32>, 2>(share.ambient_diffuse + share.specular, vec3<f32>(0.0));
#else
    return array<vec3<f32>, 2>(share.ambient_diffuse, vec3<f32>(0.0));
#endif
}

// (1 − V) of a share taken off the lit colour.
fn take_share(lit_in: LitColor, parts: array<vec3<f32>, 2>, hidden: f32) -> LitColor {
    var lit = lit_in;
    lit.ambient_diffuse -= hidden * parts[0];
#if SHADOW_SPLIT
    lit.specular -= hidden * parts[1];
#endif
    return lit;
}

// The shares (constant over a flat face; interpolating equal values keeps them).
#at gouraud.varyings flat.varyings
#for LIGHT < SHADOW_LIGHTS
    @location({{6 + 4 * LIGHT}}) front_share_{{LIGHT}}: vec3<f32>,
#if SHADOW_SPLIT
    @location({{7 + 4 * LIGHT}}) front_specular_share_{{LIGHT}}: vec3<f32>,
#endif
#if TWO_SIDED
    @location({{8 + 4 * LIGHT}}) back_share_{{LIGHT}}: vec3<f32>,
#if SHADOW_SPLIT
    @location({{9 + 4 * LIGHT}}) back_specular_share_{{LIGHT}}: vec3<f32>,
#endif
#endif
#endfor
#end

// (Two-sided lighting's `back` colour is known here: two_sided.wgsl is included before.)
#at vertex_lit.store
#for LIGHT < SHADOW_LIGHTS
    let front_{{LIGHT}} = share_parts(light_share(eye_position, normal, front, {{LIGHT}}u));
    (*out).front_share_{{LIGHT}} = front_{{LIGHT}}[0];
#if SHADOW_SPLIT
    (*out).front_specular_share_{{LIGHT}} = front_{{LIGHT}}[1];
#endif
#if TWO_SIDED
    let back_{{LIGHT}} = share_parts(light_share(eye_position, -normal, back, {{LIGHT}}u));
    (*out).back_share_{{LIGHT}} = back_{{LIGHT}}[0];
#if SHADOW_SPLIT
    (*out).back_specular_share_{{LIGHT}} = back_{{LIGHT}}[1];
#endif
#endif
#endfor
#end

// After the fragment took its front or back colour (two_sided.wgsl is included before).
#at vertex_lit.fragment_lit
    var parts: array<vec3<f32>, 2>;
#for LIGHT < SHADOW_LIGHTS
    parts = array<vec3<f32>, 2>(in.front_share_{{LIGHT}}, vec3<f32>(0.0));
#if SHADOW_SPLIT
    parts[1] = in.front_specular_share_{{LIGHT}};
#endif
#if TWO_SIDED
    if (!front_facing) {
        parts = array<vec3<f32>, 2>(in.back_share_{{LIGHT}}, vec3<f32>(0.0));
#if SHADOW_SPLIT
        parts[1] = in.back_specular_share_{{LIGHT}};
#endif
    }
#endif
    lit = take_share(lit, parts, 1.0 - shadow_visibility({{LIGHT}}u));
#endfor
#end
#endif
