#if UVS
// Texture coordinates, for the base color texture and the material maps: `surface_uv` is
// the uv of the point being shaded (a fragment; for the lighting of flat and Gouraud
// shading, the lit vertex or face centroid).
var<private> surface_uv: vec2<f32>;

// The texture coordinates a texture reads at the point being shaded: its set (Texture.uv_set,
// a const of the generated shader per texture: BASE_COLOR_UV_SET, OCCLUSION_MAP_UV_SET, ...);
// set 0 is `surface_uv`, the mesh's other sets come from chunks/surface/uv_sets.wgsl.
fn surface_uv_of(uv_set: u32) -> vec2<f32> {
#hook uvs.other_sets  // (the mesh's other texture coordinate sets)
    return surface_uv;
}

#if FREQUENCY_FLAT
fn model_uv(vertex: u32) -> vec2<f32> {
    return vec2<f32>(mesh_uvs[2u * vertex], mesh_uvs[2u * vertex + 1u]);
}
#endif

#at phong.varyings
    @location(2) uv: vec2<f32>,
#end
#at gouraud.varyings flat.varyings
    @location(4) uv: vec2<f32>,
#end
#at phong.vertex gouraud.vertex
    out.uv = vertex.uv;
#end
#at gouraud.vertex_surface
    surface_uv = vertex.uv;
#end
#at flat.vertex_surface
    // The face's maps at its centroid's uv, like its normal and position.
    surface_uv = (model_uv(mesh_indices[first]) + model_uv(mesh_indices[first + 1u])
        + model_uv(mesh_indices[first + 2u])) / 3.0;
#end
#at flat.vertex
    out.uv = model_uv(vertex);
#end
#at phong.fragment_begin vertex_lit.fragment_begin
    surface_uv = in.uv;
#end
#endif
