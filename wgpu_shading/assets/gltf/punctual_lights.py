"""KHR_lights_punctual → the classic (OpenGL) lights, placed by their nodes.

The extension's lights are the classic kinds (directional, point, spot); how each of its
quantities becomes a classic one (docs/real-world-files.md, "File lights"):

- colour × intensity is the light's diffuse and specular colour (ambient 0). Intensity is
  in lux for directional lights and candela for point and spot lights: 1 lux of
  illuminance counts as classic intensity 1 (a white diffuse surface facing a 1-lux
  light is white), and a point light of I candela gives I / d² lux at distance d, so
  point and spot lights get attenuation (0, 0, 1): pure inverse-square falloff, as the
  extension specifies.
- `range` becomes the light's `range`: the extension's recommended window
  clamp(1 − (d/range)⁴, 0, 1)² multiplies the inverse square, so the light fades to zero
  at that distance (lights without `range` never cut off).
- spot cones: cutoff = outerConeAngle; the smooth fall-off between innerConeAngle and
  outerConeAngle becomes OpenGL's cos(φ)^exponent with the exponent chosen so that the
  intensity is one half at the middle angle (inner + outer) / 2 (exponent 0, a hard edge,
  when inner = outer).
- a light points along its node's −Z axis and sits at its node's world position; lights
  under nodes scaled to zero are hidden with them.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...scene.lights import DirectionalLight, PositionalLight, SpotLight
from ...scene.values import MAX_COLOR, MAX_LIGHTS
from .document import GltfData, gltf_error
from .nodes import scene_nodes, scene_roots, world_matrices

_EXTENSION = "KHR_lights_punctual"
_INVERSE_SQUARE = (0.0, 0.0, 1.0)


def _number(data: GltfData, value: object, field: str, low: float, high: float) -> float:
    if type(value) not in (int, float) or not low <= value <= high:
        raise gltf_error(data.path, field, f"expected a number in {low:g}..{high:g}, got {value!r:.60}")
    return float(value)


def _light_table(data: GltfData) -> list:
    extensions = data.document.get("extensions", {})
    if not isinstance(extensions, dict):
        raise gltf_error(data.path, "extensions", f"expected an object, got {type(extensions).__name__}")
    extension = extensions.get(_EXTENSION, {})
    if not isinstance(extension, dict) or not isinstance(extension.get("lights", []), list):
        raise gltf_error(data.path, f"extensions.{_EXTENSION}", "expected an object with a list of lights")
    return extension.get("lights", [])


def gltf_lights(source: Path | GltfData, nodes: list | None = None) -> list[tuple[object, np.ndarray]]:
    """The file's lights of its scene's nodes as (classic light in the file's space, its
    node's world matrix) pairs; [] when it has none. `source`: the file, or the document
    already read for its meshes (reader.py: a file is parsed once); `nodes`: the nodes as
    an animation poses them (animations.posed_nodes), else the file's own."""
    data = source if isinstance(source, GltfData) else GltfData(source, json_only=True)
    table = _light_table(data)
    if not table:
        return []
    world, roots = world_matrices(data, nodes)
    nodes = data.items("nodes") if nodes is None else nodes
    lights = []
    for index in scene_nodes(data, scene_roots(data, roots)):
        extensions = nodes[index].get("extensions", {})
        reference = extensions.get(_EXTENSION) if isinstance(extensions, dict) else None
        if reference is None or world[index] is None:
            continue
        field = f"nodes[{index}].extensions.{_EXTENSION}.light"
        light_index = reference.get("light") if isinstance(reference, dict) else None
        if type(light_index) is not int or not 0 <= light_index < len(table) or not isinstance(table[light_index], dict):
            raise gltf_error(data.path, field, f"{light_index!r:.40} is not an index into the file's {len(table)} lights")
        lights.append((_classic(data, table[light_index], f"extensions.{_EXTENSION}.lights[{light_index}]", world[index]), world[index]))
        if len(lights) > MAX_LIGHTS:
            raise gltf_error(data.path, f"extensions.{_EXTENSION}", f"more than {MAX_LIGHTS} lights are placed; at most {MAX_LIGHTS} are supported (--viewer-lights ignores them)")
    return lights


def _classic(data: GltfData, light: dict, where: str, matrix: np.ndarray):
    kind = light.get("type")
    if kind not in ("directional", "point", "spot"):
        raise gltf_error(data.path, f"{where}.type", f"expected directional, point or spot, got {kind!r:.40}")
    color = light.get("color", [1.0, 1.0, 1.0])
    if not isinstance(color, list) or len(color) != 3:
        raise gltf_error(data.path, f"{where}.color", f"expected 3 numbers, got {color!r:.60}")
    rgb = [_number(data, c, f"{where}.color", 0.0, 1.0) for c in color]
    intensity = _number(data, light.get("intensity", 1.0), f"{where}.intensity", 0.0, MAX_COLOR)
    light_range = _number(data, light["range"], f"{where}.range", 1e-30, 1e15) if "range" in light else 0.0
    value = tuple(min(c * intensity, MAX_COLOR) for c in rgb) + (1.0,)
    colors = {"diffuse": value, "specular": value}
    position = tuple(float(v) for v in matrix[:3, 3])
    axis = -matrix[:3, 2]
    length = float(np.linalg.norm(axis))
    direction = tuple(float(v) for v in axis / length) if length > 0 else (0.0, 0.0, -1.0)
    if kind == "directional":
        return DirectionalLight(direction=direction, **colors)
    if kind == "point":
        return PositionalLight(position=position, attenuation=_INVERSE_SQUARE, range=light_range, **colors)
    spot = light.get("spot", {})
    if not isinstance(spot, dict):
        raise gltf_error(data.path, f"{where}.spot", f"expected an object, got {type(spot).__name__}")
    outer = _number(data, spot.get("outerConeAngle", math.pi / 4), f"{where}.spot.outerConeAngle", 0.0, math.pi / 2)
    inner = _number(data, spot.get("innerConeAngle", 0.0), f"{where}.spot.innerConeAngle", 0.0, outer)
    return SpotLight(position=position, direction=direction, cutoff=math.degrees(outer), exponent=spot_exponent(inner, outer),
                     attenuation=_INVERSE_SQUARE, range=light_range, **colors)


def spot_exponent(inner: float, outer: float) -> float:
    """The exponent e with cos((inner + outer) / 2)^e = 1/2 (0 for a hard-edged cone)."""
    middle = (inner + outer) / 2.0
    if outer - inner < 1e-6 or math.cos(middle) >= 1.0 - 1e-12:
        return 0.0
    return min(math.log(0.5) / math.log(math.cos(middle)), 1e6)
