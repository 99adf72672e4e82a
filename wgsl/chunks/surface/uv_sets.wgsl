// The mesh's other texture coordinate sets (docs/primitives.md#texture-coordinate-sets):
// Mesh.extra_uvs, each a glTF TEXCOORD_n with a texture's own transform; a texture reads
// set k when its Texture.uv_set is k (surface_uv_of, chunks/surface/uvs.wgsl). A template:
// the shader generator (render/shaders/shadergen.py) writes it once for each set the draw
// reads, %SET% the set (1..3) and %LOCATION% its varying's location. Each set is carried
// like set 0: a vertex buffer (flat shading: a storage buffer), a varying, the value at
// the point being shaded.
var<private> surface_uv_%SET%: vec2<f32>;
#if FREQUENCY_FLAT
fn model_uv_%SET%(vertex: u32) -> vec2<f32> {
    return vec2<f32>(mesh_uv_set_%SET%[2u * vertex], mesh_uv_set_%SET%[2u * vertex + 1u]);
}
#endif
#at uvs.other_sets
    if (uv_set == %SET%u) {
        return surface_uv_%SET%;
    }
#end
#at phong.varyings gouraud.varyings flat.varyings
    @location(%LOCATION%) uv_%SET%: vec2<f32>,
#end
#at phong.vertex gouraud.vertex
    out.uv_%SET% = vertex.uv_%SET%;
#end
#at gouraud.vertex_surface
    surface_uv_%SET% = vertex.uv_%SET%;
#end
#at flat.vertex_surface
    surface_uv_%SET% = (model_uv_%SET%(mesh_indices[first]) + model_uv_%SET%(mesh_indices[first + 1u])
        + model_uv_%SET%(mesh_indices[first + 2u])) / 3.0;
#end
#at flat.vertex
    out.uv_%SET% = model_uv_%SET%(vertex);
#end
#at phong.fragment_begin vertex_lit.fragment_begin
    surface_uv_%SET% = in.uv_%SET%;
#end
