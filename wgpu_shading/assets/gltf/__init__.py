"""Our own glTF 2.0 reader (.gltf/.glb), one module per part of the format:

- reader.py: a file into mesh pieces with their materials (what assets/meshes.py calls);
- document.py: the binary side: GLB chunks, buffers, buffer views, accessors, images, with
  every count checked before anything is allocated (docs/reliability.md);
- nodes.py: the node graph, scene instances and skin poses;
- animations.py: the file's animations at a chosen time (nodes and morph weights replaced);
- morph_targets.py: morph targets moved by their weights;
- primitives.py: primitives into triangle pieces (strips, fans, Draco);
- materials.py: glTF materials into classic Materials with maps, in linear colour space;
- extensions.py: required extensions and KHR_texture_transform;
- punctual_lights.py: KHR_lights_punctual into classic lights.

assets/mesh_pieces.py puts the pieces together into one Mesh (docs/real-world-files.md).
"""
