#if SPECULAR
// The reflection model of the highlight: Phong's (R·V)^s or Blinn-Phong's (N·H)^(s·k_blinn).

fn material_shininess() -> f32 {
    var shininess = object_uniforms.material.shininess;
#hook reflection.shininess  // (a shininess map)
    return shininess;
}

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
