#if SPECULAR_MAP and SPECULAR
// The specular map (map_Ks, KHR_materials_specular's colour texture) colours the highlight:
// × the specular colour.
#at output.lit
    lit.specular *= textureSample(specular_map_texture, specular_map_sampler, surface_uv_of(SPECULAR_MAP_UV_SET)).rgb;
#end
#endif
