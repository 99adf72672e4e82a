// Vertex buffers of the indexed frequencies (Gouraud, Phong): separate position, normal
// and UV buffers (wgpu_shading/render/pipelines.py, vertex_buffer_layouts).

struct VertexInput {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
#if UVS
    @location(2) uv: vec2<f32>,
#endif
#if VERTEX_COLORS
    @location(3) color: vec4<f32>,
#endif
}
