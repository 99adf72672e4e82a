// The lighting equation of docs/conventions.md (OpenGL's fixed-function lighting), in eye space:
//
//   color = emission + global_ambient·ambient_m
//         + Σ_i scale_i · (ambient_i·ambient_m + max(N·L, 0)·diffuse_i·diffuse_m
//                          + f_i · specular_factor · specular_i·specular_m)
//   scale_i = attenuation_i × spot_i,   f_i = 1 if N·L > 0 else 0
//
// Numerics: WGSL implementations may assume no value is NaN or infinite, so a NaN cannot
// be detected afterwards. Every operation that could make one has its input guarded first:
// normalize() of a zero vector, pow() of a base <= 0 or with exponent 0, division by zero.

// Squared lengths at or below this count as zero. Far below real geometry (a 1e-5-sized
// mesh has squared edge lengths near 1e-10) and far above float32's smallest normal.
const MIN_LENGTH_SQUARED: f32 = 1e-30;

// Used when a normal has no direction (zero-area face, cancelling vertex normals, an
// interpolated normal passing through zero): face the viewer, in eye space.
const FALLBACK_NORMAL: vec3<f32> = vec3<f32>(0.0, 0.0, 1.0);

#if VERTEX_COLORS
// The vertex color at the point being shaded: it multiplies the material's ambient and
// diffuse (OpenGL's GL_COLOR_MATERIAL with GL_AMBIENT_AND_DIFFUSE; glTF's COLOR_0 times
// the base color). The entry point sets it before calling shade().
var<private> surface_color: vec4<f32> = vec4<f32>(1.0);
#endif

// What multiplies the material's ambient and diffuse colors at this point (vertex colors);
// the light × material products themselves come precomputed per draw (LightProducts).
fn surface_tint() -> vec3<f32> {
#if VERTEX_COLORS
    return surface_color.rgb;
#else
    return vec3<f32>(1.0);
#endif
}

#if OCCLUSION_MAP
// The occlusion map's factor on the ambient terms at the point being shaded (glTF:
// 1 + strength·(texel − 1)); set by the entry point before calling shade().
var<private> ambient_occlusion: f32 = 1.0;
#endif

#if SHININESS_MAP
// The shininess map's texel at the point being shaded: it scales the shininess.
var<private> shininess_scale: f32 = 1.0;
#endif

fn material_shininess() -> f32 {
#if SHININESS_MAP
    return object_uniforms.material.shininess * shininess_scale;
#else
    return object_uniforms.material.shininess;
#endif
}

fn material_diffuse() -> vec3<f32> {
    return object_uniforms.material.diffuse.rgb * surface_tint();
}

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

// Unit vector from the shaded point to the viewer.
fn view_direction(eye_position: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
#if LOCAL_VIEWER
    // The seeds' shaders: V = normalize(−P). An eye exactly on the surface looks along N.
    return safe_normalize(-eye_position, normal);
#else
    // OpenGL's default infinite viewer (GL_LIGHT_MODEL_LOCAL_VIEWER false).
    return vec3<f32>(0.0, 0.0, 1.0);
#endif
}

// The lit color, split the way textures need it (docs/conventions.md#textures): the part a texture modulates,
// and the specular highlight that `modulate` adds on top.
struct LitColor {
    ambient_diffuse: vec3<f32>,
#if SPECULAR
    specular: vec3<f32>,
#endif
}

fn add_lit(a: LitColor, b: LitColor) -> LitColor {
    var sum: LitColor;
    sum.ambient_diffuse = a.ambient_diffuse + b.ambient_diffuse;
#if SPECULAR
    sum.specular = a.specular + b.specular;
#endif
    return sum;
}

#if SPECULAR
fn specular_factor(normal: vec3<f32>, to_light: vec3<f32>, to_viewer: vec3<f32>) -> f32 {
#if REFLECTION_PHONG
    // (R·V)^s with R = reflect(−L, N), unit length because L and N are.
    let reflected = reflect(-to_light, normal);
    return guarded_power(dot(reflected, to_viewer), material_shininess());
#else
    // (N·H)^(s·k_blinn) with H = normalize(L + V). L = −V leaves no half vector: no
    // highlight (a zero H makes N·H = 0) instead of normalize(0).
    let half_vector = safe_normalize(to_light + to_viewer, vec3<f32>(0.0));
    let exponent = material_shininess() * frame_uniforms.blinn_exponent_scale;
    return guarded_power(dot(normal, half_vector), exponent);
#endif
}
#endif

// One light's terms, all scaled by `scale` (attenuation × spot factor); `products` holds
// the light's colors already multiplied by the material's (LightProducts in structs.wgsl).
fn light_contribution(
    scale: f32,
    products: LightProducts,
    normal: vec3<f32>,
    to_light: vec3<f32>,
    to_viewer: vec3<f32>,
) -> LitColor {
    let n_dot_l = dot(normal, to_light);
    var result: LitColor;
#if OCCLUSION_MAP
    result.ambient_diffuse = scale * (products.ambient.rgb * ambient_occlusion + max(n_dot_l, 0.0) * products.diffuse.rgb) * surface_tint();
#else
    result.ambient_diffuse = scale * (products.ambient.rgb + max(n_dot_l, 0.0) * products.diffuse.rgb) * surface_tint();
#endif
#if SPECULAR
    // f_i: no highlight on the side the light does not reach.
    if (n_dot_l > 0.0) {
        result.specular = scale * specular_factor(normal, to_light, to_viewer) * products.specular.rgb;
    }
#endif
    return result;
}

#if ATTENUATION
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
#endif

// Every light at one surface point. `normal` and `to_viewer` are unit vectors.
fn shade(eye_position: vec3<f32>, normal: vec3<f32>, to_viewer: vec3<f32>) -> LitColor {
    var lit: LitColor;
#if UNLIT
    // KHR_materials_unlit: the surface color as it is.
    lit.ambient_diffuse = material_diffuse();
#else
    lit.ambient_diffuse = object_uniforms.global_ambient_product.rgb * surface_tint();
#if OCCLUSION_MAP
    lit.ambient_diffuse *= ambient_occlusion;
#endif
#if EMISSION and not EMISSIVE_MAP
    lit.ambient_diffuse += object_uniforms.material.emission.rgb;
#endif
#if DIRECTIONAL_LIGHTS
    for (var i = 0u; i < DIRECTIONAL_LIGHT_COUNT; i++) {
        let light = frame_uniforms.directional_lights[i];
        lit = add_lit(lit, light_contribution(1.0, object_uniforms.directional_products[i],
                                              normal, light.direction_to_light, to_viewer));
    }
#endif
#if POSITIONAL_LIGHTS
    for (var i = 0u; i < POSITIONAL_LIGHT_COUNT; i++) {
        let light = frame_uniforms.positional_lights[i];
        let offset = light.position - eye_position;
        // A light exactly at the shaded point has no direction: treat it as straight above.
        let to_light = safe_normalize(offset, normal);
#if ATTENUATION
        let scale = attenuation_factor(light.attenuation, light.inverse_range, length(offset));
#else
        let scale = 1.0;
#endif
        lit = add_lit(lit, light_contribution(scale, object_uniforms.positional_products[i],
                                              normal, to_light, to_viewer));
    }
#endif
#if SPOT_LIGHTS
    for (var i = 0u; i < SPOT_LIGHT_COUNT; i++) {
        let light = frame_uniforms.spot_lights[i];
        let offset = light.position - eye_position;
        let to_light = safe_normalize(offset, normal);
        // Inside the open cone when the angle between the axis and the ray to this point
        // is below the cutoff, compared as squared chords (see SpotLight in structs.wgsl).
        let chord = -to_light - light.direction;
        var scale = 0.0;
        if (dot(chord, chord) < light.cutoff_chord_squared) {
            // The seeds' cos^exp(φ).
            scale = guarded_power(dot(-to_light, light.direction), light.exponent);
#if ATTENUATION
            scale *= attenuation_factor(light.attenuation, light.inverse_range, length(offset));
#endif
        }
        lit = add_lit(lit, light_contribution(scale, object_uniforms.spot_products[i],
                                              normal, to_light, to_viewer));
    }
#endif
#endif
    return lit;
}
