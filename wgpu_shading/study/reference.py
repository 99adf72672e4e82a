"""The independent float64 reference renderer (numpy only).

`docs/conventions.md` defines exactly what wgpu-shading draws. The GPU implements it in
WGSL and float32; the reference implements it a second time, in float64, from the document
rather than from the shaders, so that a disagreement between the two points at a bug in
one of them. It must not import wgpu or any GPU module of the package: the scene
dataclasses (`scene/`) are only the description of what to draw.

This module gathers the reference's public names in one namespace (`from wgpu_shading.study
import reference as ref`); the code lives in

    reference_transforms  model → world → eye → window: view, model and normal matrices, pixel rays
    reference_lighting    the lighting equation and texture combine at arrays of eye-space points
    reference_raster      clipping and the exact-integer rasterizer (coverage, z-buffer, edge margins)
    reference_mesh        the same-mesh reference: RasterizedScene, shaded per frequency; render_reference
    reference_analytic    exact sphere and rectangle, ray-cast and shaded per pixel
    reference_image       ReferenceImage, what every reference render returns

Public API:

    shade(points, normals, to_viewer, scene, material) -> (ambient_diffuse, specular)
    view_vectors(points, normals, local_viewer) -> to_viewer
    combine(ambient_diffuse, specular, material, texel) -> rgba (clamped)
    sample_texture_bilinear(pixels, uv) -> rgba in [0, 1]
    render_reference(scene) -> ReferenceImage        the same meshes, rasterized in float64
    render_analytic_sphere(scene, center, radius, material) -> ReferenceImage
    render_analytic_rectangle(scene, center, half_u, half_v, material) -> ReferenceImage
    sphere_in_world(obj, radius) -> (center, radius) of a sphere mesh placed by a SceneObject
"""

from __future__ import annotations

from .reference_analytic import render_analytic_rectangle, render_analytic_sphere
from .reference_image import ReferenceImage
from .reference_lighting import (
    FALLBACK_NORMAL,
    INFINITE_VIEWER,
    MIN_ATTENUATION_DENOMINATOR,
    MIN_LENGTH_SQUARED,
    EyeLight,
    attenuation_factor,
    combine,
    guarded_power,
    lights_in_eye_space,
    safe_normalize,
    sample_texture_bilinear,
    shade,
    specular_factor,
    view_vectors,
)
from .reference_mesh import RasterizedScene, render_reference
from .reference_raster import CANDIDATE_CHUNK, GUARD_BAND_PIXELS, SUBPIXEL
from .reference_transforms import model_matrix, normal_matrix, pixel_rays, sphere_in_world, view_matrix

__all__ = [
    "CANDIDATE_CHUNK",
    "EyeLight",
    "FALLBACK_NORMAL",
    "GUARD_BAND_PIXELS",
    "INFINITE_VIEWER",
    "MIN_ATTENUATION_DENOMINATOR",
    "MIN_LENGTH_SQUARED",
    "RasterizedScene",
    "ReferenceImage",
    "SUBPIXEL",
    "attenuation_factor",
    "combine",
    "guarded_power",
    "lights_in_eye_space",
    "model_matrix",
    "normal_matrix",
    "pixel_rays",
    "render_analytic_rectangle",
    "render_analytic_sphere",
    "render_reference",
    "safe_normalize",
    "sample_texture_bilinear",
    "shade",
    "specular_factor",
    "sphere_in_world",
    "view_matrix",
    "view_vectors",
]
