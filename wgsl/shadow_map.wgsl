// The shadow pass (wgpu_shading/render/passes/shadow.py): the depth of every caster as one
// view of a casting light sees it, into one layer of the shadow maps. Depth only: no
// fragment stage. Every triangle casts, from both sides (nothing is culled), as in the exact
// answer (docs/shadows.md#the-exact-answer).

struct ShadowCaster {
    // The view's clip space (reversed depth, render/passes/shadow_views.py) from the
    // caster's model space, formed in float64 before it was rounded.
    clip_from_model: mat4x4<f32>,
}

// caster_uniforms (group 0) and VertexInput (position): render/shaders/bindings.py's
// shadow_map_plan.
#include "bindings.wgsl"

@vertex
fn vs_main(vertex: VertexInput) -> @builtin(position) vec4<f32> {
    return caster_uniforms.clip_from_model * vec4<f32>(vertex.position, 1.0);
}
