#if UNLIT
// KHR_materials_unlit: no lighting, the surface color as it is (the material's diffuse
// color, times the vertex color).
fn shade(eye_position: vec3<f32>, normal: vec3<f32>, to_viewer: vec3<f32>) -> LitColor {
    var lit: LitColor;
    lit.ambient_diffuse = object_uniforms.material.diffuse.rgb * surface_tint();
    return lit;
}
#endif
