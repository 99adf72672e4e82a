"""The independent float64 reference renderer (numpy only).

`docs/conventions.md` defines exactly what wgpu-shading draws. The GPU implements it in
WGSL and float32; the reference implements it a second time, in float64, from the document
rather than from the shaders, so that a disagreement between the two points at a bug in
one of them. It must not import wgpu or any GPU module of the package: the scene
dataclasses (`scene/`) are only the description of what to draw.

    from wgpu_shading.study import reference as ref
    image = ref.render_reference(scene)          # the same meshes, rasterized in float64

The modules, in the order a frame goes through them:

    transforms.py   model → world → eye → window: view, model and normal matrices, pixel rays
    lighting.py     the lighting equation and texture combine at arrays of eye-space points
    raster.py       clipping and the exact-integer rasterizer (coverage, z-buffer, edge margins)
    shading.py      the same-mesh reference: RasterizedScene, shaded per frequency; render_reference
    analytic.py     exact sphere and rectangle, ray-cast and shaded per pixel
    analytic_scene.py  several exact spheres and rectangles with exact shadows in closed form
    visibility.py   exact shadows of the scene's own triangles: V_i per pixel by ray casting
    image.py        ReferenceImage, what every reference render returns

Public API (what the tests and the accuracy study use; the modules' other names are
building blocks of this package):

    render_reference(scene) -> ReferenceImage                (with exact shadows: .visibility)
    render_analytic_scene(scene, shapes) -> ReferenceImage   AnalyticSphere / AnalyticRectangle, exact shadows
    ShadowRays(scene).visibility(world_points, objects, triangles) -> (lights, N) V_i
    RasterizedScene(scene).shade(shading, visibility) -> rgba   one rasterization, many shadings
    render_analytic_sphere(scene, center, radius, material) -> ReferenceImage
    render_analytic_rectangle(scene, center, half_u, half_v, material) -> ReferenceImage
    sphere_in_world(obj, radius) -> (center, radius) of a sphere mesh placed by a SceneObject
    shade(points, normals, to_viewer, scene, material) -> (ambient_diffuse, specular)
    view_vectors(points, normals, local_viewer) -> to_viewer
    combine(ambient_diffuse, specular, material, texel) -> rgba (clamped)
    sample_texture_bilinear(pixels, uv) -> rgba in [0, 1]
    lights_in_eye_space(scene), safe_normalize(v), guarded_power(base, exponent)
    eye_from_world(camera), world_from_model(obj), normal_matrix(model_view), pixel_rays(camera, size),
    window_rays(camera, size, x, y) -> (origins, directions)   perspective and orthographic
"""

from __future__ import annotations

from .analytic import render_analytic_rectangle, render_analytic_sphere
from .analytic_scene import AnalyticRectangle, AnalyticShape, AnalyticSphere, render_analytic_scene
from .image import ReferenceImage
from .lighting import combine, guarded_power, lights_in_eye_space, safe_normalize, sample_texture_bilinear, shade, view_vectors
from .shading import RasterizedScene, render_reference
from .transforms import eye_from_world, normal_matrix, pixel_rays, sphere_in_world, window_rays, world_from_model
from .visibility import ShadowRays

__all__ = [
    "AnalyticRectangle",
    "AnalyticShape",
    "AnalyticSphere",
    "ShadowRays",
    "render_analytic_scene",
    "window_rays",
    "RasterizedScene",
    "ReferenceImage",
    "combine",
    "eye_from_world",
    "guarded_power",
    "lights_in_eye_space",
    "normal_matrix",
    "pixel_rays",
    "render_analytic_rectangle",
    "render_analytic_sphere",
    "render_reference",
    "safe_normalize",
    "sample_texture_bilinear",
    "shade",
    "sphere_in_world",
    "view_vectors",
    "world_from_model",
]
