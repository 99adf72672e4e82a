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
#if SHADOW_LIGHTS > 0
    @location(6) front_share_0: vec3<f32>,
#if SHADOW_SPLIT
    @location(7) front_specular_share_0: vec3<f32>,
#endif
#if TWO_SIDED
    @location(8) back_share_0: vec3<f32>,
#if SHADOW_SPLIT
    @location(9) back_specular_share_0: vec3<f32>,
#endif
#endif
#endif
#if SHADOW_LIGHTS > 1
    @location(10) front_share_1: vec3<f32>,
#if SHADOW_SPLIT
    @location(11) front_specular_share_1: vec3<f32>,
#endif
#if TWO_SIDED
    @location(12) back_share_1: vec3<f32>,
#if SHADOW_SPLIT
    @location(13) back_specular_share_1: vec3<f32>,
#endif
#endif
#endif
#if SHADOW_LIGHTS > 2
    @location(14) front_share_2: vec3<f32>,
#if SHADOW_SPLIT
    @location(15) front_specular_share_2: vec3<f32>,
#endif
#if TWO_SIDED
    @location(16) back_share_2: vec3<f32>,
#if SHADOW_SPLIT
    @location(17) back_specular_share_2: vec3<f32>,
#endif
#endif
#endif
#if SHADOW_LIGHTS > 3
    @location(18) front_share_3: vec3<f32>,
#if SHADOW_SPLIT
    @location(19) front_specular_share_3: vec3<f32>,
#endif
#if TWO_SIDED
    @location(20) back_share_3: vec3<f32>,
#if SHADOW_SPLIT
    @location(21) back_specular_share_3: vec3<f32>,
#endif
#endif
#endif
#end

// (Two-sided lighting's `back` colour is known here: two_sided.wgsl is included before.)
#at vertex_lit.store
#if SHADOW_LIGHTS > 0
    let front_0 = share_parts(light_share(eye_position, normal, front, 0u));
    (*out).front_share_0 = front_0[0];
#if SHADOW_SPLIT
    (*out).front_specular_share_0 = front_0[1];
#endif
#if TWO_SIDED
    let back_0 = share_parts(light_share(eye_position, -normal, back, 0u));
    (*out).back_share_0 = back_0[0];
#if SHADOW_SPLIT
    (*out).back_specular_share_0 = back_0[1];
#endif
#endif
#endif
#if SHADOW_LIGHTS > 1
    let front_1 = share_parts(light_share(eye_position, normal, front, 1u));
    (*out).front_share_1 = front_1[0];
#if SHADOW_SPLIT
    (*out).front_specular_share_1 = front_1[1];
#endif
#if TWO_SIDED
    let back_1 = share_parts(light_share(eye_position, -normal, back, 1u));
    (*out).back_share_1 = back_1[0];
#if SHADOW_SPLIT
    (*out).back_specular_share_1 = back_1[1];
#endif
#endif
#endif
#if SHADOW_LIGHTS > 2
    let front_2 = share_parts(light_share(eye_position, normal, front, 2u));
    (*out).front_share_2 = front_2[0];
#if SHADOW_SPLIT
    (*out).front_specular_share_2 = front_2[1];
#endif
#if TWO_SIDED
    let back_2 = share_parts(light_share(eye_position, -normal, back, 2u));
    (*out).back_share_2 = back_2[0];
#if SHADOW_SPLIT
    (*out).back_specular_share_2 = back_2[1];
#endif
#endif
#endif
#if SHADOW_LIGHTS > 3
    let front_3 = share_parts(light_share(eye_position, normal, front, 3u));
    (*out).front_share_3 = front_3[0];
#if SHADOW_SPLIT
    (*out).front_specular_share_3 = front_3[1];
#endif
#if TWO_SIDED
    let back_3 = share_parts(light_share(eye_position, -normal, back, 3u));
    (*out).back_share_3 = back_3[0];
#if SHADOW_SPLIT
    (*out).back_specular_share_3 = back_3[1];
#endif
#endif
#endif
#end

// After the fragment took its front or back colour (two_sided.wgsl is included before).
#at vertex_lit.fragment_lit
    var parts: array<vec3<f32>, 2>;
#if SHADOW_LIGHTS > 0
    parts = array<vec3<f32>, 2>(in.front_share_0, vec3<f32>(0.0));
#if SHADOW_SPLIT
    parts[1] = in.front_specular_share_0;
#endif
#if TWO_SIDED
    if (!front_facing) {
        parts = array<vec3<f32>, 2>(in.back_share_0, vec3<f32>(0.0));
#if SHADOW_SPLIT
        parts[1] = in.back_specular_share_0;
#endif
    }
#endif
    lit = take_share(lit, parts, 1.0 - shadow_visibility(0u));
#endif
#if SHADOW_LIGHTS > 1
    parts = array<vec3<f32>, 2>(in.front_share_1, vec3<f32>(0.0));
#if SHADOW_SPLIT
    parts[1] = in.front_specular_share_1;
#endif
#if TWO_SIDED
    if (!front_facing) {
        parts = array<vec3<f32>, 2>(in.back_share_1, vec3<f32>(0.0));
#if SHADOW_SPLIT
        parts[1] = in.back_specular_share_1;
#endif
    }
#endif
    lit = take_share(lit, parts, 1.0 - shadow_visibility(1u));
#endif
#if SHADOW_LIGHTS > 2
    parts = array<vec3<f32>, 2>(in.front_share_2, vec3<f32>(0.0));
#if SHADOW_SPLIT
    parts[1] = in.front_specular_share_2;
#endif
#if TWO_SIDED
    if (!front_facing) {
        parts = array<vec3<f32>, 2>(in.back_share_2, vec3<f32>(0.0));
#if SHADOW_SPLIT
        parts[1] = in.back_specular_share_2;
#endif
    }
#endif
    lit = take_share(lit, parts, 1.0 - shadow_visibility(2u));
#endif
#if SHADOW_LIGHTS > 3
    parts = array<vec3<f32>, 2>(in.front_share_3, vec3<f32>(0.0));
#if SHADOW_SPLIT
    parts[1] = in.front_specular_share_3;
#endif
#if TWO_SIDED
    if (!front_facing) {
        parts = array<vec3<f32>, 2>(in.back_share_3, vec3<f32>(0.0));
#if SHADOW_SPLIT
        parts[1] = in.back_specular_share_3;
#endif
    }
#endif
    lit = take_share(lit, parts, 1.0 - shadow_visibility(3u));
#endif
#end
#endif
