// Numerics shared by every effect. WGSL implementations may assume no value is NaN or
// infinite, so a NaN cannot be detected afterwards: every operation that could make one
// has its input guarded first (normalize() of a zero vector, pow() of a base <= 0 or with
// exponent 0, division by zero).

// Squared lengths at or below this count as zero. Far below real geometry (a 1e-5-sized
// mesh has squared edge lengths near 1e-10) and far above float32's smallest normal.
const MIN_LENGTH_SQUARED: f32 = 1e-30;

// Used when a normal has no direction (zero-area face, cancelling vertex normals, an
// interpolated normal passing through zero): face the viewer, in eye space.
const FALLBACK_NORMAL: vec3<f32> = vec3<f32>(0.0, 0.0, 1.0);

fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let length_squared = dot(v, v);
    if (length_squared > MIN_LENGTH_SQUARED) {
        return v * inverseSqrt(length_squared);
    }
    return fallback;
}

#if SPECULAR or SPOT_LIGHTS
// max(cosine, 0)^exponent for a cosine in [-1, 1] and an exponent >= 0 (validated on the
// CPU). pow(x, y) is undefined for x < 0 and for x = 0 with y <= 0, so the edge cases are
// decided before pow runs: a base <= 0 gives 0 for every exponent (0^0 too), and x^0 = 1
// for x > 0. That makes the result continuous in the exponent at 0: a tiny shininess that
// rounds to 0 in float32 changes nothing.
fn guarded_power(cosine: f32, exponent: f32) -> f32 {
    if (cosine <= 0.0) {
        return 0.0;
    }
    if (exponent <= 0.0) {
        return 1.0;
    }
    return pow(min(cosine, 1.0), exponent);
}
#endif
