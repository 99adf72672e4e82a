// Resource bindings. wgpu_shading/render/pipelines.py creates the matching bind group layouts
// from the same feature set.

@group(0) @binding(0) var<uniform> frame_uniforms: FrameUniforms;
@group(1) @binding(0) var<uniform> object_uniforms: ObjectUniforms;

#if TEXTURE
// RGBA8 texture, rows uploaded bottom-up so that v = 0 is the bottom of the image.
@group(1) @binding(1) var surface_texture: texture_2d<f32>;
@group(1) @binding(2) var surface_sampler: sampler;
#endif
