"""Readers of the mesh file formats that are not glTF (glTF: assets/gltf/), each returning a
MeshFile (assets/mesh_pieces.py) and listed by suffix in assets/meshes.py MESH_READERS:
OBJ with its MTL materials (obj.py, mtl.py), OFF (off.py), STL (stl.py: binary with numpy,
ASCII through trimesh), PLY (ply.py: binary point clouds with numpy, `edge` elements in
ply_edges.py, the rest through trimesh_reader.py), point clouds as text (point_text.py:
.xyz, .pts); checks.py holds the size,
header-count and text-encoding checks made before a file is read."""
