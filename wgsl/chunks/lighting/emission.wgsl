#if EMISSION and not EMISSIVE_MAP
// Emission: light the surface gives off, added to the lit color. With an emissive map the
// map patterns it, after the texture (chunks/maps/emissive_map.wgsl).
#at lighting.emission
    lit.ambient_diffuse += object_uniforms.material.emission.rgb;
#end
#endif
