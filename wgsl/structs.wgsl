// Uniform layouts: the one declaration of every uniform block.
// wgpu_shading/render/shaders/layout.py parses these structs (after the #if lines are resolved) into
// numpy dtypes, so the Python side can never disagree with the shader about offsets.
//
// PositionalLight and Material keep the seed shaders' fields at their offsets:
// ambient 0, diffuse 16, specular 32, position/shininess 48, size 64 (docs/conventions.md#uniform-layout).
// Fields for optional effects come after them and exist only when the scene uses them.
// All directions and positions are in eye space: the CPU transforms them once per frame,
// like the seed's installLights().

#if DIRECTIONAL_LIGHTS
struct DirectionalLight {
    ambient: vec4<f32>,
    diffuse: vec4<f32>,
    specular: vec4<f32>,
    // Unit vector from the surface towards the light (OpenGL's position with w = 0).
    direction_to_light: vec3<f32>,
}
#endif

#if POSITIONAL_LIGHTS
struct PositionalLight {
    ambient: vec4<f32>,
    diffuse: vec4<f32>,
    specular: vec4<f32>,
    position: vec3<f32>,
#if ATTENUATION
    // Constant, linear and quadratic coefficients: 1 / (kc + kl·d + kq·d²).
    attenuation: vec3<f32>,
    // 1 / range (0: no cut-off): glTF's window clamp(1 − (d/range)⁴, 0, 1)².
    inverse_range: f32,
#endif
}
#endif

#if SPOT_LIGHTS
struct SpotLight {
    ambient: vec4<f32>,
    diffuse: vec4<f32>,
    specular: vec4<f32>,
    position: vec3<f32>,
#if ATTENUATION
    attenuation: vec3<f32>,
    inverse_range: f32,
#endif
    // Unit vector: the way the light travels along the cone's axis.
    direction: vec3<f32>,
    // The cone as a squared chord, |a − b|² = 2 − 2·cos(angle) for unit a and b:
    // 4·sin²(cutoff / 2), computed in float64. Comparing chords instead of cosines keeps
    // small cutoffs exact, where cos(angle) rounds to 1 in float32.
    cutoff_chord_squared: f32,
    exponent: f32,
}
#endif

struct Material {
    ambient: vec4<f32>,
    diffuse: vec4<f32>,
    specular: vec4<f32>,
    shininess: f32,
#if EMISSION
    emission: vec4<f32>,
#endif
#if ALPHA_MASK
    // alphaMode MASK: fragments whose alpha is below this are discarded.
    alpha_cutoff: f32,
#endif
#if NORMAL_MAP
    // glTF normalTexture.scale (MTL -bm): × the tangent-space normal's x and y.
    normal_scale: f32,
#endif
#if OCCLUSION_MAP
    // glTF occlusionTexture.strength: ambient × (1 + strength·(occlusion − 1)).
    occlusion_strength: f32,
#endif
}

// Group 0: one per frame, shared by every object.
struct FrameUniforms {
    clip_from_eye: mat4x4<f32>,
    global_ambient: vec4<f32>,
#if REFLECTION_BLINN_PHONG
    // k_blinn: the Blinn-Phong exponent is shininess × this (the seed shaders use 3, OpenGL 1).
    blinn_exponent_scale: f32,
#endif
#if DIRECTIONAL_LIGHTS
    directional_lights: array<DirectionalLight, DIRECTIONAL_LIGHT_COUNT>,
#endif
#if POSITIONAL_LIGHTS
    positional_lights: array<PositionalLight, POSITIONAL_LIGHT_COUNT>,
#endif
#if SPOT_LIGHTS
    spot_lights: array<SpotLight, SPOT_LIGHT_COUNT>,
#endif
}

// One light's colors times the object's material colors (ambient_i·ambient_m,
// diffuse_i·diffuse_m, specular_i·specular_m), multiplied once per draw on the CPU
// (wgpu_shading/render/shaders/uniforms.py) instead of once per fragment. Besides the multiplies,
// this saves uniform reads, which are the expensive part: Mesa 22.3's llvmpipe/lavapipe
// gathers every uniform component a fragment shader reads lane by lane, with a bounds check
// per lane (docs/performance.md, "Why the same shader was slower").
struct LightProducts {
    ambient: vec4<f32>,
    diffuse: vec4<f32>,
    specular: vec4<f32>,
}

// Group 1: one per object.
struct ObjectUniforms {
    eye_from_model: mat4x4<f32>,
    // The seed's norm_matrix: inverse transpose of eye_from_model's upper 3×3, so normals
    // stay perpendicular under non-uniform scale and stay outward under mirroring.
    eye_normal_from_model: mat3x3<f32>,
    material: Material,
#if STROKES
    // Points and lines (docs/primitives.md): the target's size and the quad's size (a
    // point's size, a line's or an edge's width), in pixels.
    viewport_size: vec2<f32>,
    stroke_pixels: f32,
#endif
#if EDGES
    // --edge-color, written as it is (a colour on the image, like the background).
    edge_color: vec4<f32>,
#endif
#if not UNLIT
    // global_ambient · material ambient, and each light's LightProducts (same order as the
    // FrameUniforms light arrays).
    global_ambient_product: vec4<f32>,
#if DIRECTIONAL_LIGHTS
    directional_products: array<LightProducts, DIRECTIONAL_LIGHT_COUNT>,
#endif
#if POSITIONAL_LIGHTS
    positional_products: array<LightProducts, POSITIONAL_LIGHT_COUNT>,
#endif
#if SPOT_LIGHTS
    spot_products: array<LightProducts, SPOT_LIGHT_COUNT>,
#endif
#endif
#if SHADOWS
    // A closed surface hides a light from its own points that face away from it
    // (docs/shadows.md#closed-surfaces): bit s is set for each casting light s (by slot) it
    // hides that way; none for an open surface. The sign turns the winding normal outward
    // (−1: a mesh wound inside out).
    self_shadowing_lights: u32,
    outward_sign: f32,
#endif
}
#if SHADOWS

// One casting light's shadow maps (render/passes/shadow.py fills it; render/passes/shadow_views.py
// fits them). Every field is read at the light's own slot, the same in every fragment (a
// field chosen per fragment would be gathered lane by lane on llvmpipe).
struct ShadowLight {
    // Rigid: eye space to the light's view, which looks along its −z (a single map), or to
    // the light's cube frame: world axes, origin at the light (each cube face is a fixed turn
    // of it, wgsl/chunks/shadows/lookup.wgsl).
    light_from_eye: mat4x4<f32>,
    // A point's texel coordinates: (x, y) · texels.xy + texels.zw, where (x, y) are the
    // view's x and y (orthographic) or x/t and y/t, t = −z (perspective; every cube face alike).
    texels: vec4<f32>,
    // x: 1 / (far − near) (orthographic) or the near distance (perspective); y: the bias,
    // world units (orthographic) or world units per unit of distance (perspective).
    depth: vec4<f32>,
    // Map layers (−1: none, nothing visible this light can shadow there): a single map's in
    // x; a cube map's faces +X, −X, +Y, −Y in x, y, z, w.
    layers: vec4<i32>,
    // A cube map's faces +Z, −Z in x, y; z: 1 for a cube map, 0 for a single map.
    more_layers: vec4<i32>,
}

// Group 0, with the maps: the casting lights by slot (render/features.py casting_lights).
struct ShadowUniforms {
    lights: array<ShadowLight, SHADOW_LIGHT_COUNT>,
}
#endif
