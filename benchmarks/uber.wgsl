// The "uber-shader": every feature compiled in, chosen at run time by uniform switches.
// Kept only for benchmarks/bench_specialization.py, to measure what the renderer's
// feature-specialized shaders (wgsl/*.wgsl + shadergen.py) save. It implements the same
// conventions (docs/conventions.md) for per-fragment (Phong-frequency) shading, so its
// images match the specialized ones; the shading frequency itself is structural (what the
// vertex stage outputs), not a run-time switch, so it is not part of this comparison.

const MAX_LIGHTS: u32 = 8u;
const LIGHT_DIRECTIONAL: u32 = 0u;
const LIGHT_POSITIONAL: u32 = 1u;
const LIGHT_SPOT: u32 = 2u;
const TEXTURE_NONE: u32 = 0u;
const TEXTURE_MODULATE: u32 = 1u;
const TEXTURE_MODULATE_ALL: u32 = 2u;
const TEXTURE_BLEND: u32 = 3u;
const MIN_LENGTH_SQUARED: f32 = 1e-30;
const FALLBACK_NORMAL: vec3<f32> = vec3<f32>(0.0, 0.0, 1.0);

struct UberLight {
    ambient: vec4<f32>,
    diffuse: vec4<f32>,
    specular: vec4<f32>,
    position: vec3<f32>,        // eye space (positional, spot)
    kind: u32,
    direction: vec3<f32>,       // directional: towards the light; spot: the way light travels
    cutoff_chord_squared: f32,
    attenuation: vec3<f32>,
    exponent: f32,
}

struct UberFrame {
    clip_from_eye: mat4x4<f32>,
    global_ambient: vec4<f32>,
    light_count: u32,
    blinn_phong: u32,
    blinn_exponent_scale: f32,
    local_viewer: u32,
    two_sided: u32,
    lights: array<UberLight, MAX_LIGHTS>,
}

struct UberObject {
    eye_from_model: mat4x4<f32>,
    eye_normal_from_model: mat3x3<f32>,
    ambient: vec4<f32>,
    diffuse: vec4<f32>,
    specular: vec4<f32>,
    emission: vec4<f32>,
    shininess: f32,
    texture_mode: u32,
}

@group(0) @binding(0) var<uniform> frame: UberFrame;
@group(1) @binding(0) var<uniform> object: UberObject;
@group(1) @binding(1) var surface_texture: texture_2d<f32>;  // a 1×1 white texture when unused
@group(1) @binding(2) var surface_sampler: sampler;

struct VertexInput {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
}

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) eye_position: vec3<f32>,
    @location(1) eye_normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
}

fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let length_squared = dot(v, v);
    if (length_squared > MIN_LENGTH_SQUARED) {
        return v * inverseSqrt(length_squared);
    }
    return fallback;
}

fn guarded_power(cosine: f32, exponent: f32) -> f32 {
    if (cosine <= 0.0) {
        return 0.0;
    }
    if (exponent <= 0.0) {
        return 1.0;
    }
    return pow(min(cosine, 1.0), exponent);
}

@vertex
fn vs_main(vertex: VertexInput) -> Varyings {
    let eye_position = object.eye_from_model * vec4<f32>(vertex.position, 1.0);
    var out: Varyings;
    out.clip_position = frame.clip_from_eye * eye_position;
    out.eye_position = eye_position.xyz;
    out.eye_normal = object.eye_normal_from_model * vertex.normal;
    out.uv = vertex.uv;
    return out;
}

@fragment
fn fs_main(in: Varyings, @builtin(front_facing) front_facing: bool) -> @location(0) vec4<f32> {
    let texel = textureSample(surface_texture, surface_sampler, in.uv);
    var normal = safe_normalize(in.eye_normal, FALLBACK_NORMAL);
    if (frame.two_sided != 0u && !front_facing) {
        normal = -normal;
    }
    let position = in.eye_position;
    var to_viewer = vec3<f32>(0.0, 0.0, 1.0);
    if (frame.local_viewer != 0u) {
        to_viewer = safe_normalize(-position, normal);
    }
    var ambient_diffuse = frame.global_ambient.rgb * object.ambient.rgb + object.emission.rgb;
    var specular = vec3<f32>(0.0);
    for (var i = 0u; i < frame.light_count; i++) {
        let light = frame.lights[i];
        var to_light = light.direction;
        var scale = 1.0;
        if (light.kind != LIGHT_DIRECTIONAL) {
            let offset = light.position - position;
            to_light = safe_normalize(offset, normal);
            let distance = length(offset);
            let denominator = light.attenuation.x + distance * (light.attenuation.y + distance * light.attenuation.z);
            scale = 1.0 / max(denominator, 1e-20);
            if (light.kind == LIGHT_SPOT) {
                let chord = -to_light - light.direction;
                if (dot(chord, chord) < light.cutoff_chord_squared) {
                    scale *= guarded_power(dot(-to_light, light.direction), light.exponent);
                } else {
                    scale = 0.0;
                }
            }
        }
        let n_dot_l = dot(normal, to_light);
        ambient_diffuse += scale * (light.ambient.rgb * object.ambient.rgb
            + max(n_dot_l, 0.0) * light.diffuse.rgb * object.diffuse.rgb);
        if (n_dot_l > 0.0) {
            var factor = 0.0;
            if (frame.blinn_phong != 0u) {
                let half_vector = safe_normalize(to_light + to_viewer, vec3<f32>(0.0));
                factor = guarded_power(dot(normal, half_vector), object.shininess * frame.blinn_exponent_scale);
            } else {
                factor = guarded_power(dot(reflect(-to_light, normal), to_viewer), object.shininess);
            }
            specular += scale * factor * light.specular.rgb * object.specular.rgb;
        }
    }
    var rgb = ambient_diffuse + specular;
    var alpha = object.diffuse.a;
    if (object.texture_mode == TEXTURE_MODULATE) {
        rgb = texel.rgb * ambient_diffuse + specular;
    } else if (object.texture_mode == TEXTURE_MODULATE_ALL) {
        rgb = texel.rgb * (ambient_diffuse + specular);
    } else if (object.texture_mode == TEXTURE_BLEND) {
        rgb = 0.5 * texel.rgb + 0.5 * (ambient_diffuse + specular);
    }
    if (object.texture_mode != TEXTURE_NONE) {
        alpha *= texel.a;
    }
    return vec4<f32>(clamp(rgb, vec3<f32>(0.0), vec3<f32>(1.0)), alpha);
}
