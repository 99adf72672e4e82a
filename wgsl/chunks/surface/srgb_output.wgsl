#if SRGB_OUTPUT
// Linear colour space (glTF): the output is sRGB-encoded (colour textures are decoded by
// an *-srgb texture format, which needs no shader code).
// Linear light → sRGB encoding (IEC 61966-2-1) of a colour already clamped to [0, 1]. The
// max() keeps pow's base positive; the low branch is taken there anyway.
fn srgb_encode(linear: vec3<f32>) -> vec3<f32> {
    let high = 1.055 * pow(max(linear, vec3<f32>(0.0031308)), vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, linear * 12.92, linear <= vec3<f32>(0.0031308));
}

#at output.encoding
    encoded = srgb_encode(encoded);
#end
#endif
