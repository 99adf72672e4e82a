"""Meshes and their geometry: the Mesh type (`mesh.py`) and what it is made of — its parts
(`mesh_parts.py`: ranges of triangles, line segments or points, and a surface's edges),
its normals (`crease_normals.py`: welded by position and split at creases, and face
normals; `vertex_normals.py`: the seeds' per-vertex rule and normals a caller gives),
per-vertex arrays converted by blocks (`vertex_arrays.py`), whether it bounds a solid
(`solids.py`) — and the procedural meshes with exact normals (`builtins.py`:
`builtin:sphere`, `torus`, `cube`, `plane`). Imported through `wgpu_shading.scene`."""
