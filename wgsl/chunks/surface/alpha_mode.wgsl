// The material's alpha mode (glTF alphaMode): opaque (alpha 1), mask (discarded below the
// cutoff, else 1) or blend (the surface's alpha, composited over what is behind).
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
