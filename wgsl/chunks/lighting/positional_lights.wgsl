#if POSITIONAL_LIGHTS
// Positional (point) lights: light from a point in every direction.
#at lighting.lights
    for (var i = 0u; i < POSITIONAL_LIGHT_COUNT; i++) {
        let light = frame_uniforms.positional_lights[i];
        let offset = light.position - eye_position;
        // A light exactly at the shaded point has no direction: treat it as straight above.
        let to_light = safe_normalize(offset, normal);
        var scale = 1.0;
#hook positional_lights.light  // light i is known (light, offset, to_light): attenuation, a shadow lookup
        lit = add_lit(lit, light_contribution(scale, object_uniforms.positional_products[i],
                                              normal, to_light, to_viewer));
    }
#end
#endif
