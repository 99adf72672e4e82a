"""What a shader is and what it reads, for a feature set, without touching the GPU: the WGSL
module (`shadergen.py`, from the files of the top-level `wgsl/` folder: one chunk per
effect, put together by `preprocess.py`), the binding plan
(`bindings.py`: every bind group entry and vertex buffer by name; `material_maps.py`: how
map textures are stored), the uniform layouts parsed from the WGSL structs (`layout.py`)
and the uniform values filled from a scene (`uniforms.py`). docs/architecture.md#render--the-gpu."""
