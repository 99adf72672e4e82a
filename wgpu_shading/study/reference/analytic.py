"""Analytic ground truth: an exact sphere or rectangle ray-cast through every pixel centre and
shaded per pixel with its exact normal, which is what Phong shading of a tessellation
converges to as the mesh is refined. No triangles, so edge_margin is the distance to the
silhouette."""

from __future__ import annotations

import math

import numpy as np

from ...scene import Material, Scene
from .image import ReferenceImage
from .lighting import dot, combine, shade, view_vectors
from .transforms import transform_points, pixel_rays, view_matrix


def _analytic_image(
    scene: Scene,
    hit: np.ndarray,
    points: np.ndarray,
    normals: np.ndarray,
    margins: np.ndarray,
    material: Material,
) -> ReferenceImage:
    """Shade analytic hits (flattened pixel mask, eye points, outward unit normals) per pixel,
    as Phong shading converges to when the tessellation is refined."""
    width, height = scene.size
    shading = scene.shading
    if material.texture is not None:
        raise ValueError("analytic shapes take untextured materials")
    depth = -points[:, 2]
    # A surface seen from behind is back-facing; two-sided lighting then uses -N.
    facing_viewer = dot(normals, -points) > 0.0
    if shading.two_sided:
        normals = np.where(facing_viewer[:, None], normals, -normals)
    ambient_diffuse, specular = shade(
        points, normals, view_vectors(points, normals, shading.local_viewer), scene, material
    )
    color = np.broadcast_to(np.asarray(scene.background, dtype=np.float64), (height * width, 4)).copy()
    color[hit] = combine(ambient_diffuse, specular, material)

    def image(values, fill, dtype):
        result = np.full(height * width, fill, dtype=dtype)
        result[hit] = values
        return result.reshape(height, width)

    return ReferenceImage(
        color=color.reshape(height, width, 4),
        covered=hit.reshape(height, width),
        triangle=image(-1, -1, np.int64),
        object=image(0, -1, np.int64),
        depth=image(depth, np.inf, np.float64),
        edge_margin=image(margins, np.inf, np.float64),
        texel_footprint=np.zeros((height, width)),
    )


def render_analytic_sphere(scene: Scene, center, radius: float, material: Material) -> ReferenceImage:
    """Ray-cast an exact sphere (world-space centre and radius) through every pixel centre,
    with the exact normal; the nearest intersection in [near, far] is shaded.

    edge_margin is the angle between the pixel's ray and the silhouette cone, in pixels (as
    at the image centre), so tests can leave the rim out."""
    camera = scene.camera
    view = view_matrix(camera)
    c = transform_points(view, np.asarray(center, dtype=np.float64)[None])[0]
    rays = pixel_rays(camera, scene.size).reshape(-1, 3)
    # |t·d − c|² = r²  →  (d·d) t² − 2 (d·c) t + (c·c − r²) = 0
    a = dot(rays, rays)
    b = rays @ c
    discriminant = b * b - a * (c @ c - radius * radius)
    root = np.sqrt(np.maximum(discriminant, 0.0))
    # The rays have z = −1, so the parameter t of a hit t·d is also its eye depth.
    near_t, far_t = (b - root) / a, (b + root) / a
    use_near = (near_t >= camera.near) & (near_t <= camera.far)
    t = np.where(use_near, near_t, far_t)
    hit = (discriminant > 0.0) & (t >= camera.near) & (t <= camera.far)
    points = rays[hit] * t[hit, None]
    normals = (points - c) / radius
    # Angle between the ray and the silhouette cone, converted to pixels on the image plane.
    distance_to_center = np.linalg.norm(c)
    ray_unit = rays[hit] / np.sqrt(a[hit])[:, None]
    angle_to_center = np.arccos(np.clip(ray_unit @ c / distance_to_center, -1.0, 1.0))
    silhouette_angle = math.asin(min(radius / distance_to_center, 1.0))
    pixels_per_radian = scene.size[1] / (2.0 * math.tan(math.radians(camera.fov_y) / 2.0))
    margins = (silhouette_angle - angle_to_center) * pixels_per_radian
    return _analytic_image(scene, hit, points, normals, margins, material)


def render_analytic_rectangle(scene: Scene, center, half_u, half_v, material: Material) -> ReferenceImage:
    """Ray-cast the rectangle {center + s·half_u + t·half_v : |s|, |t| <= 1} (world space,
    half_u ⟂ half_v) with normal normalize(half_u × half_v), shaded per pixel."""
    camera = scene.camera
    view = view_matrix(camera)
    c = transform_points(view, np.asarray(center, dtype=np.float64)[None])[0]
    u = view[:3, :3] @ np.asarray(half_u, dtype=np.float64)
    v = view[:3, :3] @ np.asarray(half_v, dtype=np.float64)
    normal = np.cross(u, v)
    normal /= np.linalg.norm(normal)
    rays = pixel_rays(camera, scene.size).reshape(-1, 3)
    along = rays @ normal
    t = np.where(along != 0.0, (c @ normal) / np.where(along != 0.0, along, 1.0), -1.0)
    points = rays * t[:, None]
    s = (points - c) @ u / (u @ u)
    r = (points - c) @ v / (v @ v)
    hit = (along != 0.0) & (t >= camera.near) & (t <= camera.far) & (np.abs(s) <= 1.0) & (np.abs(r) <= 1.0)
    # Margin: distance to the rectangle's border measured on the image plane (pixels), by
    # scaling the in-plane distance with the local magnification (focal / depth).
    focal_pixels = scene.size[1] / (2.0 * math.tan(math.radians(camera.fov_y) / 2.0))
    in_plane = np.minimum((1.0 - np.abs(s[hit])) * np.linalg.norm(u), (1.0 - np.abs(r[hit])) * np.linalg.norm(v))
    margins = in_plane * focal_pixels / t[hit]
    return _analytic_image(scene, hit, points[hit], np.broadcast_to(normal, (int(hit.sum()), 3)), margins, material)
