#if SHININESS_MAP
// The shininess map (map_Ns) scales the shininess by its red channel. Read where the
// lighting happens, like the occlusion map (chunks/maps/occlusion_map.wgsl).
// The map's texel at the point being shaded, set before shade() runs.
var<private> shininess_scale: f32 = 1.0;

#at reflection.shininess
    shininess *= shininess_scale;
#end
#at gouraud.vertex_surface flat.vertex_surface
    shininess_scale = textureSampleLevel(shininess_map_texture, shininess_map_sampler, surface_uv_of(SHININESS_MAP_UV_SET), 0.0).r;
#end
#at phong.fragment_surface
    shininess_scale = textureSample(shininess_map_texture, shininess_map_sampler, surface_uv_of(SHININESS_MAP_UV_SET)).r;
#end
#endif
