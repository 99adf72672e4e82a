// Fragment stage of the frequencies that light in the vertex stage (Gouraud and flat):
// the lit color arrives in the varyings (interpolated for Gouraud, flat for flat shading);
// only the texture and the final clamp happen per fragment.

@fragment
fn fs_main(
    in: Varyings,
#if TWO_SIDED
    @builtin(front_facing) front_facing: bool,
#endif
) -> @location(0) vec4<f32> {
    var lit: LitColor;
    lit.ambient_diffuse = in.front_ambient_diffuse;
#if SPECULAR
    lit.specular = in.front_specular;
#endif
#if TWO_SIDED
    if (!front_facing) {
        lit.ambient_diffuse = in.back_ambient_diffuse;
#if SPECULAR
        lit.specular = in.back_specular;
#endif
    }
#endif
#if TEXTURE
    return final_color(lit, in.uv);
#else
    return final_color(lit);
#endif
}
