#if SHADOWS
// A shadow in the lighting equation (docs/shadows.md#in-the-lighting-equation): a casting
// light's visibility V scales its diffuse and specular terms, after attenuation and the spot
// factor; its ambient term, the global ambient and emission stay. Each kind's casting
// lights come first in its array (render/shaders/uniforms.py), so light i of a kind casts
// when i is below that kind's count, and its slot is the kinds before it plus i.

// V of the light being added (1 for a light that casts none), set before its terms.
var<private> light_visible: f32 = 1.0;

#if FREQUENCY_PHONG
// Per fragment: the light's shadow maps (lookup.wgsl).
fn light_visibility(slot: u32) -> f32 {
    return shadow_visibility(slot);
}
#else
// In the vertex stage of flat and Gouraud shading every light is lit, except the one whose
// share of the colour is being taken (shares.wgsl); the fragment applies V to the shares.
var<private> light_switched_off: u32 = 0xffffffffu;

fn light_visibility(slot: u32) -> f32 {
    return select(1.0, 0.0, slot == light_switched_off);
}
#endif

// (Only where the light can reach the surface: on the side turned away, and outside a spot's
// cone, V changes nothing and is not looked up.)
#at directional_lights.light
        light_visible = 1.0;
        if (i < DIRECTIONAL_SHADOW_COUNT && dot(normal, to_light) > 0.0) {
            light_visible = light_visibility(i);
        }
#end
#at spot_lights.light
        light_visible = 1.0;
        if (i < SPOT_SHADOW_COUNT && scale > 0.0 && dot(normal, to_light) > 0.0) {
            light_visible = light_visibility(DIRECTIONAL_SHADOW_COUNT + i);
        }
#end
#at positional_lights.light
        light_visible = 1.0;
        if (i < POSITIONAL_SHADOW_COUNT && dot(normal, to_light) > 0.0) {
            light_visible = light_visibility(DIRECTIONAL_SHADOW_COUNT + SPOT_SHADOW_COUNT + i);
        }
#end
#at lighting.light_diffuse
    diffuse *= light_visible;
#end
#at lighting.light_highlight
        highlight *= light_visible;
#end

// The fragment stage knows which side of its triangle it sees (lookup.wgsl).
#if not TWO_SIDED
#at phong.fragment_inputs vertex_lit.fragment_inputs
    @builtin(front_facing) front_facing: bool,
#end
#endif
#endif
