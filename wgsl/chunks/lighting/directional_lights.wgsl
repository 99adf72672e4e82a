#if DIRECTIONAL_LIGHTS
// Directional lights: a direction, no position (OpenGL's w = 0 lights).
#at lighting.lights
    for (var i = 0u; i < DIRECTIONAL_LIGHT_COUNT; i++) {
        let light = frame_uniforms.directional_lights[i];
        let to_light = light.direction_to_light;
        let scale = 1.0;
#hook directional_lights.light  // light i is known (light, to_light): a per-light factor (a shadow lookup)
        lit = add_lit(lit, light_contribution(scale, object_uniforms.directional_products[i],
                                              normal, to_light, to_viewer));
    }
#end
#endif
