#if ALPHA_MAP
// The alpha map (map_d) multiplies the surface's alpha by its red channel.
#at output.alpha
    alpha *= textureSample(alpha_map_texture, alpha_map_sampler, surface_uv_of(ALPHA_MAP_UV_SET)).r;
#end
#endif
