"""Reading and writing files: meshes through trimesh (with the materials they carry),
textures, TOML scene files, output images and animations. Imports `scene/` only."""

from .meshes import MESH_SUFFIXES, load_mesh
from .scenefile import load_scene, parse_scene
from .textures import load_texture

__all__ = ["MESH_SUFFIXES", "load_mesh", "load_scene", "load_texture", "parse_scene"]
