"""Readers of the mesh file formats that are not glTF (glTF: assets/gltf/): OBJ with its MTL
materials (obj.py, mtl.py), OFF (off.py), binary STL (stl.py); checks.py holds the size,
header-count and text-encoding checks made before a file is read. PLY and ASCII STL are
read through trimesh (assets/meshes.py)."""
