"""How the accuracy study measures error, and the analytic truth it measures against.

Errors are measured against two float64 references (`wgpu_shading.study.reference`):

- the **analytic truth**: the exact sphere, ray-cast through every pixel centre and shaded
  per pixel with its exact normal (what any tessellation and frequency should converge to);
- the **same-mesh reference**: the very triangles the GPU draws, rasterized and shaded in
  float64 (what this frequency on this mesh should give; any difference is float32 rounding).

**Error** (everywhere in the study, in units of 1/255, one 8-bit step): per pixel, the
largest absolute difference over R, G and B of the colours clamped to [0, 1], between the
GPU's float32 render target and the reference. Against the analytic truth it is taken
over the pixels that both the exact sphere and the mesh cover, leaving out a band of
`SILHOUETTE_BAND` (1) pixel inside the exact silhouette; against the same-mesh reference,
over the pixels the reference covers, leaving out those within `EDGE_BAND` (1/16) pixel of
an edge of their triangle (float32 window coordinates may hand those to a neighbour).
From the per-pixel errors: RMSE, the 99.9th percentile (`p99.9`), the maximum, and the
error **at the specular peak**: the largest error in the 3×3 pixels around the pixel where
the analytic truth's specular term is largest (where Gouraud shading loses the highlight).
Besides, `highlight`: how far the image's brightest value is from the truth's, wherever
each lies (a lost highlight, as opposed to a moved one).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...scene import Material, Scene, SceneObject
from ...errors import AccuracyError
from ...render.image_error import ERROR_UNIT, ErrorStats, pixel_error
from ..reference import ReferenceImage, pixel_rays, render_analytic_sphere, shade, sphere_in_world, view_matrix, view_vectors

SILHOUETTE_BAND = 1.0  # pixels inside the exact silhouette left out of the analytic comparison
EDGE_BAND = 1.0 / 16.0  # pixels from a triangle edge left out of the same-mesh comparison
PEAK_WINDOW = 1  # the specular-peak error is the largest in a (2·1 + 1)² window


# --------------------------------------------------------------------------- errors


def highlight_error(image: np.ndarray, reference: np.ndarray, mask: np.ndarray) -> float:
    """How far the brightest value of `image` is from the brightest value of `reference`,
    each taken over the compared pixels wherever it lies: max over RGB of
    |max_pixels clamp(image) − max_pixels clamp(reference)|, in 1/255. A highlight that is
    lost (Gouraud shading with no vertex under it) shows here even when it is merely moved."""
    if not mask.any():
        return float("nan")
    a = np.clip(np.asarray(image, dtype=np.float64)[..., :3][mask], 0.0, 1.0).max(axis=0)
    b = np.clip(np.asarray(reference, dtype=np.float64)[..., :3][mask], 0.0, 1.0).max(axis=0)
    return float(np.abs(a - b).max() / ERROR_UNIT)


def peak_error(error_map: np.ndarray, mask: np.ndarray, peak: tuple[int, int]) -> float:
    """The largest error among compared pixels in the window around `peak` (NaN if none)."""
    row, col = peak
    r0, c0 = max(row - PEAK_WINDOW, 0), max(col - PEAK_WINDOW, 0)
    window = error_map[r0 : row + PEAK_WINDOW + 1, c0 : col + PEAK_WINDOW + 1]
    inside = mask[r0 : row + PEAK_WINDOW + 1, c0 : col + PEAK_WINDOW + 1]
    return float(window[inside].max()) if inside.any() else float("nan")


# --------------------------------------------------------------------------- the analytic truth


@dataclass(frozen=True)
class Truth:
    """The analytic sphere for one size and reflection model, with its specular peak."""

    image: ReferenceImage
    interior: np.ndarray  # covered, at least SILHOUETTE_BAND pixels inside the silhouette
    peak: tuple[int, int]  # (row, col) where the specular term is largest


def analytic_truth(scene: Scene, obj: SceneObject | None = None) -> Truth:
    """Ray-cast the exact sphere that `obj` (default: the scene's first object, a sphere mesh
    of radius 1) tessellates, and find the pixel where its specular term peaks."""
    obj = obj or scene.objects[0]
    center, radius = sphere_in_world(obj)
    image = render_analytic_sphere(scene, center, radius, obj.surface_material)
    return Truth(image=image, interior=image.covered & (image.edge_margin >= SILHOUETTE_BAND), peak=specular_peak(scene, center, radius, obj.surface_material, image))


def specular_peak(scene: Scene, center, radius: float, material: Material, image: ReferenceImage) -> tuple[int, int]:
    """(row, col) of the covered pixel where the exact sphere's specular part (summed over RGB)
    is largest: the hit point is the pixel's ray scaled to the depth, the normal points away
    from the centre."""
    covered = np.flatnonzero(image.covered)
    if covered.size == 0:
        raise AccuracyError("the analytic sphere covers no pixel")
    rays = pixel_rays(scene.camera, scene.size).reshape(-1, 3)[covered]
    points = rays * image.depth.reshape(-1)[covered, None]  # rays have z = −1: t is the depth
    view = view_matrix(scene.camera)
    center_eye = view[:3, :3] @ np.asarray(center, dtype=np.float64) + view[:3, 3]
    normals = (points - center_eye) / radius
    to_viewer = view_vectors(points, normals, scene.shading.local_viewer)
    _, specular = shade(points, normals, to_viewer, scene, material)
    best = covered[int(np.argmax(specular.sum(axis=1)))]
    row, col = divmod(int(best), scene.size[0])
    return row, col
