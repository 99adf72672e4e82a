// Resource bindings. wgpu_shading/render/pipelines.py creates the matching bind group layouts
// from the same feature set.

@group(0) @binding(0) var<uniform> frame_uniforms: FrameUniforms;
@group(1) @binding(0) var<uniform> object_uniforms: ObjectUniforms;

#if TEXTURE
// RGBA8 texture, rows uploaded bottom-up so that v = 0 is the bottom of the image.
@group(1) @binding(1) var surface_texture: texture_2d<f32>;
@group(1) @binding(2) var surface_sampler: sampler;
#endif

// Material maps (wgpu_shading/scene/maps.py), each bound only where a draw uses it, with
// its own sampler (its Texture's filter and wrap modes). Occlusion and shininess maps are
// also read by the vertex stage of flat and Gouraud shading (sampled at the vertex or face).
#if NORMAL_MAP
@group(1) @binding(3) var normal_map_texture: texture_2d<f32>;
@group(1) @binding(4) var normal_map_sampler: sampler;
#endif
#if BUMP_MAP
// The height map as the tangent-space normal map it implies (converted on upload).
@group(1) @binding(5) var bump_map_texture: texture_2d<f32>;
@group(1) @binding(6) var bump_map_sampler: sampler;
#endif
#if SPECULAR_MAP
@group(1) @binding(7) var specular_map_texture: texture_2d<f32>;
@group(1) @binding(8) var specular_map_sampler: sampler;
#endif
#if SHININESS_MAP
@group(1) @binding(9) var shininess_map_texture: texture_2d<f32>;
@group(1) @binding(10) var shininess_map_sampler: sampler;
#endif
#if EMISSIVE_MAP
@group(1) @binding(11) var emissive_map_texture: texture_2d<f32>;
@group(1) @binding(12) var emissive_map_sampler: sampler;
#endif
#if OCCLUSION_MAP
@group(1) @binding(13) var occlusion_map_texture: texture_2d<f32>;
@group(1) @binding(14) var occlusion_map_sampler: sampler;
#endif
#if ALPHA_MAP
@group(1) @binding(15) var alpha_map_texture: texture_2d<f32>;
@group(1) @binding(16) var alpha_map_sampler: sampler;
#endif
