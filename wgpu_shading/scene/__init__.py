"""What to draw: plain, immutable, validated dataclasses (docs/scene-files.md).

A scene is what a TOML scene file describes: output, shading settings, a camera, global
ambient light, lights and objects, each object a Mesh with a Material and a transform.
Everything here is world space and float64; the GPU's float32 eye space is `render/`'s.
Procedural meshes (`builtin:torus`, ...) and the classic material table live here too.
This package imports nothing else of ours but `errors`: files are `assets/`'s business.

Valid ranges (enforced on construction, so a bad value fails loudly and early):
  colors        RGBA or RGB (alpha 1), every component finite, 0 .. 1e6, alpha <= 1
  background    every component 0 .. 1
  positions     finite, |coordinate| <= 1e15
  directions    finite, at least 1e-30 long (they are normalized when used)
  shininess     0 .. 1e6 (0 means x^0 = 1: a uniform specular term on the lit side)
  attenuation   constant, linear, quadratic: each 0 .. 1e15, not all zero
  spot cutoff   0 .. 90 degrees; spot exponent 0 .. 1e6
  fov_y         1e-6 .. <180 degrees; 1e-20 <= near < far, far/near <= 1e30
  scale         every component 1e-12 .. 1e12 in size (negative mirrors)
  size          1 .. 16384 pixels per side
  lights        at most 256
  meshes        at most 2^25 vertices and triangles, 1e-9 .. 1e9 units across
  eye space     every object's bounding box within ±1e18 of the camera
docs/reliability.md explains why (every value the GPU sees stays finite in float32).
"""

from .builtins import BUILTIN_PREFIX, BUILTINS, builtin, cube, plane, sphere_for_triangles, torus, uv_sphere
from .camera import Camera
from .lights import LIGHT_TYPES, DirectionalLight, Light, PositionalLight, SpotLight
from .material import Material, Texture
from .material_table import MATERIALS, canonical_name, material
from .mesh import Mesh, face_normals, vertex_normals
from .objects import Scene, SceneObject, Shading, every_light_casts, has_shadows, shadowing_lights
from .shadows import SHADOW_FILTERS, ShadowSettings
from .values import (
    FREQUENCIES,
    MAX_COORDINATE,
    MAX_EXPONENT,
    MAX_IMAGE_SIDE,
    REFLECTIONS,
    TEXTURE_MODES,
    Color,
    Frequency,
    Reflection,
    TextureMode,
    Vec3,
    choice,
    color,
    direction,
    image_size,
    number,
    vec3,
)

__all__ = [
    "BUILTINS", "BUILTIN_PREFIX", "Camera", "Color", "DirectionalLight", "FREQUENCIES", "Frequency",
    "LIGHT_TYPES", "Light", "MATERIALS", "MAX_COORDINATE", "MAX_EXPONENT", "MAX_IMAGE_SIDE", "Material",
    "Mesh", "PositionalLight", "REFLECTIONS", "Reflection", "Scene", "SceneObject", "SHADOW_FILTERS", "Shading", "ShadowSettings", "SpotLight",
    "TEXTURE_MODES", "Texture", "TextureMode", "Vec3", "builtin", "canonical_name", "choice", "color", "cube",
    "direction", "every_light_casts", "face_normals", "has_shadows", "image_size", "material", "number", "plane", "shadowing_lights", "sphere_for_triangles", "torus",
    "uv_sphere", "vec3", "vertex_normals",
]
