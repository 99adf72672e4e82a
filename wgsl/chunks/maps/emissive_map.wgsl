#if EMISSIVE_MAP and EMISSION
// The emissive map patterns the light the surface gives off: added after the texture combine.
#at output.emission
    rgb += object_uniforms.material.emission.rgb * textureSample(emissive_map_texture, emissive_map_sampler, surface_uv_of(EMISSIVE_MAP_UV_SET)).rgb;
#end
#endif
