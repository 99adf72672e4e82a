#if SPOT_LIGHTS
// Spot lights: a positional light limited to a cone, fading towards its edge (cos^exp).
#at lighting.lights
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
#hook spot_lights.cone  // inside the cone: attenuation
        }
#hook spot_lights.light  // light i is known (light, offset, to_light): a shadow lookup
        lit = add_lit(lit, light_contribution(scale, object_uniforms.spot_products[i],
                                              normal, to_light, to_viewer));
    }
#end
#endif
