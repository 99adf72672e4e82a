"""The GPU: adapter and device, feature set, WGSL generation (sources in the top-level
`wgsl/`), the passes a frame is made of, the GPU objects kept between frames, the renderer
and frame pipelining.

Data path: Scene → features.object_features (FeatureSet) → shaders/ (WGSL, binding plan,
uniform layouts and values) → gpu/pipelines (one cached pipeline per PipelineKey) → passes/ (the
colour pass, the extra outputs) → renderer.Renderer → Frame. Folders in floors, imports
only downward: features/device → shaders/ → gpu/ → passes/ → renderer
(tests/test_architecture.py). Imports `scene/` (and `assets/` nowhere: the renderer never
touches files).
"""
