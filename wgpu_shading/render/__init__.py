"""The GPU: adapter and device, feature set, WGSL generation (sources in the top-level
`wgsl/`), uniform layouts, the pipeline cache, the renderer and frame pipelining.

Data path: Scene → features.object_features → shadergen.generate_wgsl → pipeline_cache.PipelineCache
→ renderer.Renderer (uniforms.py fills the buffers whose layout layout.py derived) → Frame.
Imports `scene/` (and `assets/` nowhere: the renderer never touches files).
"""
