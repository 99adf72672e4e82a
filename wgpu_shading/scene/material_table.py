"""The classic OpenGL material table (docs/scene-files.md#materials).

Sources: SGI's teapots.c (Mark J. Kilgard, 1994) as published by F. Devernay, with its
shininess given as a fraction of 128; the SIGGRAPH '99 course notes "Advanced Graphics
Programming Techniques Using OpenGL" (Table 7) for the alphas and the polished metals;
and the course material the project started from for pewter
(docs/conventions.md#where-the-rules-come-from). Shininess is stored in OpenGL units
(the fraction × 128).
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Mapping

from ..errors import SceneError, shown
from .material import Material

# name: (ambient RGB, diffuse RGB, specular RGB, shininess as a fraction of 128, alpha)
_TABLE: dict[str, tuple[tuple[float, ...], tuple[float, ...], tuple[float, ...], float, float]] = {
    "emerald": ((0.0215, 0.1745, 0.0215), (0.07568, 0.61424, 0.07568), (0.633, 0.727811, 0.633), 0.6, 0.55),
    "jade": ((0.135, 0.2225, 0.1575), (0.54, 0.89, 0.63), (0.316228, 0.316228, 0.316228), 0.1, 0.95),
    "obsidian": ((0.05375, 0.05, 0.06625), (0.18275, 0.17, 0.22525), (0.332741, 0.328634, 0.346435), 0.3, 0.82),
    "pearl": ((0.25, 0.20725, 0.20725), (1.0, 0.829, 0.829), (0.296648, 0.296648, 0.296648), 0.088, 0.922),
    "ruby": ((0.1745, 0.01175, 0.01175), (0.61424, 0.04136, 0.04136), (0.727811, 0.626959, 0.626959), 0.6, 0.55),
    "turquoise": ((0.1, 0.18725, 0.1745), (0.396, 0.74151, 0.69102), (0.297254, 0.30829, 0.306678), 0.1, 0.8),
    "brass": ((0.329412, 0.223529, 0.027451), (0.780392, 0.568627, 0.113725), (0.992157, 0.941176, 0.807843), 0.21794872, 1.0),
    "bronze": ((0.2125, 0.1275, 0.054), (0.714, 0.4284, 0.18144), (0.393548, 0.271906, 0.166721), 0.2, 1.0),
    "chrome": ((0.25, 0.25, 0.25), (0.4, 0.4, 0.4), (0.774597, 0.774597, 0.774597), 0.6, 1.0),
    "copper": ((0.19125, 0.0735, 0.0225), (0.7038, 0.27048, 0.0828), (0.256777, 0.137622, 0.086014), 0.1, 1.0),
    "gold": ((0.24725, 0.1995, 0.0745), (0.75164, 0.60648, 0.22648), (0.628281, 0.555802, 0.366065), 0.4, 1.0),
    "silver": ((0.19225, 0.19225, 0.19225), (0.50754, 0.50754, 0.50754), (0.508273, 0.508273, 0.508273), 0.4, 1.0),
    "black_plastic": ((0.0, 0.0, 0.0), (0.01, 0.01, 0.01), (0.5, 0.5, 0.5), 0.25, 1.0),
    "cyan_plastic": ((0.0, 0.1, 0.06), (0.0, 0.50980392, 0.50980392), (0.50196078, 0.50196078, 0.50196078), 0.25, 1.0),
    "green_plastic": ((0.0, 0.0, 0.0), (0.1, 0.35, 0.1), (0.45, 0.55, 0.45), 0.25, 1.0),
    "red_plastic": ((0.0, 0.0, 0.0), (0.5, 0.0, 0.0), (0.7, 0.6, 0.6), 0.25, 1.0),
    "white_plastic": ((0.0, 0.0, 0.0), (0.55, 0.55, 0.55), (0.7, 0.7, 0.7), 0.25, 1.0),
    "yellow_plastic": ((0.0, 0.0, 0.0), (0.5, 0.5, 0.0), (0.6, 0.6, 0.5), 0.25, 1.0),
    "black_rubber": ((0.02, 0.02, 0.02), (0.01, 0.01, 0.01), (0.4, 0.4, 0.4), 0.078125, 1.0),
    "cyan_rubber": ((0.0, 0.05, 0.05), (0.4, 0.5, 0.5), (0.04, 0.7, 0.7), 0.078125, 1.0),
    "green_rubber": ((0.0, 0.05, 0.0), (0.4, 0.5, 0.4), (0.04, 0.7, 0.04), 0.078125, 1.0),
    "red_rubber": ((0.05, 0.0, 0.0), (0.5, 0.4, 0.4), (0.7, 0.04, 0.04), 0.078125, 1.0),
    "white_rubber": ((0.05, 0.05, 0.05), (0.5, 0.5, 0.5), (0.7, 0.7, 0.7), 0.078125, 1.0),
    "yellow_rubber": ((0.05, 0.05, 0.0), (0.5, 0.5, 0.4), (0.7, 0.7, 0.04), 0.078125, 1.0),
    # SIGGRAPH '99 notes, Table 7 (shininess 76.8, 51.2, 83.2, 89.6 in OpenGL units)
    "polished_bronze": ((0.25, 0.148, 0.06475), (0.4, 0.2368, 0.1036), (0.774597, 0.458561, 0.200621), 0.6, 1.0),
    "polished_copper": ((0.2295, 0.08825, 0.0275), (0.5508, 0.2118, 0.066), (0.580594, 0.223257, 0.0695701), 0.4, 1.0),
    "polished_gold": ((0.24725, 0.2245, 0.0645), (0.34615, 0.3143, 0.0903), (0.797357, 0.723991, 0.208006), 0.65, 1.0),
    "polished_silver": ((0.23125, 0.23125, 0.23125), (0.2775, 0.2775, 0.2775), (0.773911, 0.773911, 0.773911), 0.7, 1.0),
    # The seeds' pewter, shininess already in OpenGL units: 9.85 / 128.
    "pewter": ((0.11, 0.06, 0.11), (0.43, 0.47, 0.54), (0.33, 0.33, 0.52), 9.85 / 128.0, 1.0),
}


def _build(name: str) -> Material:
    ambient, diffuse, specular, shininess_fraction, alpha = _TABLE[name]
    return Material(
        ambient=(*ambient, alpha),
        diffuse=(*diffuse, alpha),
        specular=(*specular, alpha),
        shininess=shininess_fraction * 128.0,
        name=name,
    )


MATERIALS: Mapping[str, Material] = MappingProxyType({name: _build(name) for name in _TABLE})
"""Every named material, read-only. Keys use underscores: "black_plastic"."""


def canonical_name(name: str) -> str:
    return name.strip().lower().replace(" ", "_").replace("-", "_")


def material(name: str) -> Material:
    """Look a material up by name ("gold", "black plastic", "polished-silver", ...)."""
    if not isinstance(name, str):
        raise SceneError(f"material: expected a material name (see `wgpu-shading materials`), got {shown(name)}")
    key = canonical_name(name)
    try:
        return MATERIALS[key]
    except KeyError:
        import difflib  # (imported on a mistake only: ~2 ms of every start)
        close = difflib.get_close_matches(key, MATERIALS.keys(), n=3)
        hint = f"; did you mean {' or '.join(map(repr, close))}?" if close else ""
        raise SceneError(
            f"unknown material {shown(name)}{hint} (`wgpu-shading materials` lists all {len(MATERIALS)})"
        ) from None
