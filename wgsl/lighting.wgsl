// The lighting equation of docs/conventions.md (OpenGL's fixed-function lighting), in eye space:
//
//   color = emission + global_ambient·ambient_m
//         + Σ_i scale_i · (ambient_i·ambient_m + max(N·L, 0)·diffuse_i·diffuse_m
//                          + f_i · specular_factor · specular_i·specular_m)
//   scale_i = attenuation_i × spot_i,   f_i = 1 if N·L > 0 else 0
//
// The equation's own effects, one chunk each (what they put at the points lighting.* below):
#include "chunks/numerics.wgsl"
#include "chunks/lighting/viewer.wgsl"
#include "chunks/lighting/reflection.wgsl"
#include "chunks/lighting/emission.wgsl"
#include "chunks/lighting/directional_lights.wgsl"
#include "chunks/lighting/positional_lights.wgsl"
#include "chunks/lighting/spot_lights.wgsl"
#include "chunks/lighting/attenuation.wgsl"
#include "chunks/lighting/unlit.wgsl"

// What multiplies the material's ambient and diffuse colors at this point (vertex colors);
// the light × material products themselves come precomputed per draw (LightProducts).
fn surface_tint() -> vec3<f32> {
    var tint = vec3<f32>(1.0);
#hook lighting.surface_tint  // (vertex colors)
    return tint;
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

#if not UNLIT
// One light's terms, all scaled by `scale` (attenuation × spot factor); `products` holds
// the light's colors already multiplied by the material's (LightProducts in structs.wgsl).
// An effect on one light's ambient, diffuse or highlight term scales it at its point
// (an occlusion map the ambient; a shadow the diffuse and the highlight).
fn light_contribution(
    scale: f32,
    products: LightProducts,
    normal: vec3<f32>,
    to_light: vec3<f32>,
    to_viewer: vec3<f32>,
) -> LitColor {
    let n_dot_l = dot(normal, to_light);
    var ambient = products.ambient.rgb;
#hook lighting.light_ambient  // what scales this light's ambient term (an occlusion map)
    var diffuse = max(n_dot_l, 0.0);
#hook lighting.light_diffuse  // what scales its diffuse term (a shadow: the light's visibility)
    var result: LitColor;
    result.ambient_diffuse = scale * (ambient + diffuse * products.diffuse.rgb) * surface_tint();
#if SPECULAR
    // f_i: no highlight on the side the light does not reach.
    if (n_dot_l > 0.0) {
        var highlight = specular_factor(normal, to_light, to_viewer);
#hook lighting.light_highlight  // what scales its highlight (a shadow: the light's visibility)
        result.specular = scale * highlight * products.specular.rgb;
    }
#endif
    return result;
}

// Every light at one surface point. `normal` and `to_viewer` are unit vectors. (Without
// lighting, KHR_materials_unlit, chunks/lighting/unlit.wgsl has its own shade().)
fn shade(eye_position: vec3<f32>, normal: vec3<f32>, to_viewer: vec3<f32>) -> LitColor {
    var lit: LitColor;
    lit.ambient_diffuse = object_uniforms.global_ambient_product.rgb * surface_tint();
#hook lighting.global_ambient  // what scales the global ambient term (an occlusion map)
#hook lighting.emission  // the material's emission
#hook lighting.lights  // each kind of light adds its lights (chunks/lighting/*_lights.wgsl)
    return lit;
}
#endif
