#if ATTENUATION
// Attenuation of positional and spot lights with distance: 1 / (kc + kl·d + kq·d²), and
// KHR_lights_punctual's range window.
// The CPU rejects (0, 0, 0) and negative coefficients, so the denominator is >= 0. It is 0
// only for a light at distance 0 with kc = 0, where the true factor is infinite; the floor
// keeps it finite and the final clamp then shows full intensity.
const MIN_ATTENUATION_DENOMINATOR: f32 = 1e-20;

fn attenuation_factor(coefficients: vec3<f32>, inverse_range: f32, distance: f32) -> f32 {
    let denominator = coefficients.x + distance * (coefficients.y + distance * coefficients.z);
    // KHR_lights_punctual's range window (1 when inverse_range is 0)
    let ratio = distance * inverse_range;
    let window = clamp(1.0 - ratio * ratio * ratio * ratio, 0.0, 1.0);
    return window * window / max(denominator, MIN_ATTENUATION_DENOMINATOR);
}

#at positional_lights.light
        scale = attenuation_factor(light.attenuation, light.inverse_range, length(offset));
#end
#at spot_lights.cone
            scale *= attenuation_factor(light.attenuation, light.inverse_range, length(offset));
#end
#endif
