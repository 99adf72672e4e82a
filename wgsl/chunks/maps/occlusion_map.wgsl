#if OCCLUSION_MAP
// The occlusion map (glTF occlusionTexture) darkens the ambient terms: 1 + strength·(texel − 1).
// Flat and Gouraud shading light in the vertex stage, so it is read there, at the vertex
// (flat: the face centroid's uv), from level 0; Phong shading reads it per fragment,
// filtered like any texture.
// Its factor at the point being shaded, set before shade() runs.
var<private> ambient_occlusion: f32 = 1.0;

fn occlusion_factor(texel: vec4<f32>) -> f32 {
    return 1.0 + object_uniforms.material.occlusion_strength * (texel.r - 1.0);
}

#at lighting.global_ambient
    lit.ambient_diffuse *= ambient_occlusion;
#end
#at lighting.light_ambient
    ambient *= ambient_occlusion;
#end
#at gouraud.vertex_surface flat.vertex_surface
    ambient_occlusion = occlusion_factor(textureSampleLevel(occlusion_map_texture, occlusion_map_sampler, surface_uv_of(OCCLUSION_MAP_UV_SET), 0.0));
#end
#at phong.fragment_surface
    ambient_occlusion = occlusion_factor(textureSample(occlusion_map_texture, occlusion_map_sampler, surface_uv_of(OCCLUSION_MAP_UV_SET)));
#end
#endif
