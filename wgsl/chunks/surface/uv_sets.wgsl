// The mesh's other texture coordinate sets (docs/primitives.md#texture-coordinate-sets):
// Mesh.extra_uvs, each a glTF TEXCOORD_n with a texture's own transform; a texture reads
// set k when its Texture.uv_set is k (surface_uv_of, chunks/surface/uvs.wgsl). Sets 1..3,
// each carried like set 0: a vertex buffer (flat shading: a storage buffer), a varying,
// the value at the point being shaded.

#if UV_SET_1
var<private> surface_uv_1: vec2<f32>;
#if FREQUENCY_FLAT
fn model_uv_1(vertex: u32) -> vec2<f32> {
    return vec2<f32>(mesh_uv_set_1[2u * vertex], mesh_uv_set_1[2u * vertex + 1u]);
}
#endif
#at uvs.other_sets
    if (uv_set == 1u) {
        return surface_uv_1;
    }
#end
#at phong.varyings gouraud.varyings flat.varyings
    @location(5) uv_1: vec2<f32>,
#end
#at phong.vertex gouraud.vertex
    out.uv_1 = vertex.uv_1;
#end
#at gouraud.vertex_surface
    surface_uv_1 = vertex.uv_1;
#end
#at flat.vertex_surface
    surface_uv_1 = (model_uv_1(mesh_indices[first]) + model_uv_1(mesh_indices[first + 1u])
        + model_uv_1(mesh_indices[first + 2u])) / 3.0;
#end
#at flat.vertex
    out.uv_1 = model_uv_1(vertex);
#end
#at phong.fragment_begin vertex_lit.fragment_begin
    surface_uv_1 = in.uv_1;
#end
#endif

#if UV_SET_2
var<private> surface_uv_2: vec2<f32>;
#if FREQUENCY_FLAT
fn model_uv_2(vertex: u32) -> vec2<f32> {
    return vec2<f32>(mesh_uv_set_2[2u * vertex], mesh_uv_set_2[2u * vertex + 1u]);
}
#endif
#at uvs.other_sets
    if (uv_set == 2u) {
        return surface_uv_2;
    }
#end
#at phong.varyings gouraud.varyings flat.varyings
    @location(6) uv_2: vec2<f32>,
#end
#at phong.vertex gouraud.vertex
    out.uv_2 = vertex.uv_2;
#end
#at gouraud.vertex_surface
    surface_uv_2 = vertex.uv_2;
#end
#at flat.vertex_surface
    surface_uv_2 = (model_uv_2(mesh_indices[first]) + model_uv_2(mesh_indices[first + 1u])
        + model_uv_2(mesh_indices[first + 2u])) / 3.0;
#end
#at flat.vertex
    out.uv_2 = model_uv_2(vertex);
#end
#at phong.fragment_begin vertex_lit.fragment_begin
    surface_uv_2 = in.uv_2;
#end
#endif

#if UV_SET_3
var<private> surface_uv_3: vec2<f32>;
#if FREQUENCY_FLAT
fn model_uv_3(vertex: u32) -> vec2<f32> {
    return vec2<f32>(mesh_uv_set_3[2u * vertex], mesh_uv_set_3[2u * vertex + 1u]);
}
#endif
#at uvs.other_sets
    if (uv_set == 3u) {
        return surface_uv_3;
    }
#end
#at phong.varyings gouraud.varyings flat.varyings
    @location(7) uv_3: vec2<f32>,
#end
#at phong.vertex gouraud.vertex
    out.uv_3 = vertex.uv_3;
#end
#at gouraud.vertex_surface
    surface_uv_3 = vertex.uv_3;
#end
#at flat.vertex_surface
    surface_uv_3 = (model_uv_3(mesh_indices[first]) + model_uv_3(mesh_indices[first + 1u])
        + model_uv_3(mesh_indices[first + 2u])) / 3.0;
#end
#at flat.vertex
    out.uv_3 = model_uv_3(vertex);
#end
#at phong.fragment_begin vertex_lit.fragment_begin
    surface_uv_3 = in.uv_3;
#end
#endif
