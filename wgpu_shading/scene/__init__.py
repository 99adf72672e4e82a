"""What to draw: plain, immutable, validated dataclasses (docs/scene-files.md).

A scene is what a TOML scene file describes: output, shading settings, a camera, global
ambient light, lights and objects, each object a Mesh with a Material and a transform.
Everything here is world space and float64; the GPU's float32 eye space is `render/`'s.
Procedural meshes (`builtin:torus`, ...) and the classic material table live here too.
This package imports nothing else of ours but `errors`: files are `assets/`'s business.

Every value is validated on construction, so a bad one fails loudly and early. The valid
ranges, and why each keeps every value the GPU sees finite in float32: docs/valid-ranges.md
(tests/test_valid_ranges.py keeps it equal to the checks here).
"""

from .geometry.builtins import BUILTIN_PREFIX, BUILTINS, builtin, cube, plane, sphere_for_triangles, torus, uv_sphere
from .camera import Camera
from .lights import LIGHT_TYPES, DirectionalLight, Light, PositionalLight, SpotLight
from .material import Material, Texture
from .material_table import MATERIALS, canonical_name, material
from .geometry.mesh import Mesh, face_normals, vertex_normals
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
