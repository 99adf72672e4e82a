"""Several exact spheres and rectangles in one picture, with exact shadows in closed form:
each pixel shows the nearest shape (analytic.py ray-casts each one), and every light that
casts shadows is tested against every shape with float64 ray–sphere and ray–rectangle
intersections — no triangles, no float32 anywhere. This is the ground truth that the
triangle ray cast (visibility.py) and the GPU's tessellated spheres converge to, and what
the closed-form shadow of docs/shadows.md#the-hard-cases (an ellipse on the plane) is
derived from."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...scene import Material, Scene
from .analytic import render_analytic_rectangle, render_analytic_sphere
from .image import ReferenceImage
from .lighting import combine, dot, shade, view_vectors
from .transforms import eye_from_world, pixel_rays, transform_points
from .visibility import segments_to_light

# A sphere's own surface is not its occluder closer than this fraction of its radius: the
# root t = 0 of a ray starting on it, rounded (float64: ~1e-16 relative).
OWN_SURFACE = 1e-9


@dataclass(frozen=True)
class AnalyticSphere:
    center: tuple[float, float, float]  # world space
    radius: float
    material: Material


@dataclass(frozen=True)
class AnalyticRectangle:
    """{center + s·half_u + t·half_v : |s|, |t| <= 1}, half_u ⟂ half_v, normal half_u × half_v."""

    center: tuple[float, float, float]
    half_u: tuple[float, float, float]
    half_v: tuple[float, float, float]
    material: Material


AnalyticShape = AnalyticSphere | AnalyticRectangle


def ray_sphere(origins: np.ndarray, directions: np.ndarray, center, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """(t_near, t_far) of rays o + t·d (unit d) against a sphere; NaN where they miss."""
    offset = origins - np.asarray(center, dtype=np.float64)
    b = dot(offset, directions)
    discriminant = b * b - (dot(offset, offset) - radius * radius)
    root = np.sqrt(np.where(discriminant > 0.0, discriminant, np.nan))
    return -b - root, -b + root


def ray_rectangle(origins: np.ndarray, directions: np.ndarray, shape: AnalyticRectangle) -> np.ndarray:
    """t of rays o + t·d against a rectangle; NaN where they miss or run parallel to it."""
    u, v = np.asarray(shape.half_u, dtype=np.float64), np.asarray(shape.half_v, dtype=np.float64)
    normal = np.cross(u, v)
    along = directions @ normal
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((np.asarray(shape.center) - origins) @ normal) / along
    point = origins + t[:, None] * directions - np.asarray(shape.center)
    inside = (np.abs(point @ u) <= u @ u) & (np.abs(point @ v) <= v @ v) & (along != 0.0)
    return np.where(inside, t, np.nan)


def _occluded(shapes, own: np.ndarray, origins, directions, lengths) -> np.ndarray:
    """(N,) bool: some shape other than a point's own rectangle meets the segment."""
    blocked = np.zeros(len(origins), dtype=bool)
    for index, shape in enumerate(shapes):
        if isinstance(shape, AnalyticSphere):
            near, far = ray_sphere(origins, directions, shape.center, shape.radius)
            least = OWN_SURFACE * shape.radius
            hits = [(near > least) & (near < lengths), (far > least) & (far < lengths)]
            blocked |= hits[0] | hits[1]
        else:
            t = ray_rectangle(origins, directions, shape)
            blocked |= (own != index) & (t > 0.0) & (t < lengths)
    return blocked


def shadow_visibility(scene: Scene, shapes, points: np.ndarray, own: np.ndarray) -> np.ndarray:
    """(lights, N) exact V_i at world points lying on shape `own[k]`, in closed form."""
    result = np.ones((len(scene.lights), len(points)))
    for index, light in enumerate(scene.lights):
        if not light.shadows:
            continue
        directions, lengths = segments_to_light(light, points)
        result[index, _occluded(shapes, own, points, directions, lengths)] = 0.0
    return result


def render_analytic_scene(scene: Scene, shapes: tuple[AnalyticShape, ...]) -> ReferenceImage:
    """Exact spheres and rectangles (world space) with exact shadows, shaded per pixel as
    analytic.py shades one shape. `object` is the index of the shape seen; edge_margin is
    that shape's own (distance to its silhouette, not to an occluding shape's)."""
    singles = [
        render_analytic_sphere(scene, s.center, s.radius, s.material) if isinstance(s, AnalyticSphere)
        else render_analytic_rectangle(scene, s.center, s.half_u, s.half_v, s.material)
        for s in shapes
    ]
    width, height = scene.size
    depth = np.stack([single.depth for single in singles])
    nearest = np.argmin(depth, axis=0)  # ties: the first shape, as the GPU's draw order
    covered = np.isfinite(depth.min(axis=0))
    pick = lambda field: np.take_along_axis(np.stack([getattr(s, field) for s in singles]), nearest[None], 0)[0]
    flat = covered.reshape(-1)
    seen = nearest.reshape(-1)[flat]
    eye_points = pixel_rays(scene.camera, scene.size).reshape(-1, 3)[flat] * pick("depth").reshape(-1)[flat, None]
    to_world = np.linalg.inv(eye_from_world(scene.camera))
    points = transform_points(to_world, eye_points)
    visibility = np.ones((len(scene.lights), height * width))
    visibility[:, flat] = shadow_visibility(scene, shapes, points, seen)

    color = np.broadcast_to(np.asarray(scene.background, dtype=np.float64), (height * width, 4)).copy()
    rotation = eye_from_world(scene.camera)[:3, :3]
    for index, shape in enumerate(shapes):
        mine = seen == index
        if not mine.any():
            continue
        if isinstance(shape, AnalyticSphere):
            center = transform_points(eye_from_world(scene.camera), np.asarray(shape.center, dtype=np.float64)[None])[0]
            normals = (eye_points[mine] - center) / shape.radius
        else:
            normal = rotation @ np.cross(shape.half_u, shape.half_v)
            normals = np.broadcast_to(normal / np.linalg.norm(normal), (int(mine.sum()), 3))
        if scene.shading.two_sided:  # as analytic.py: a surface seen from behind is lit with -N
            normals = np.where((dot(normals, -eye_points[mine]) > 0.0)[:, None], normals, -normals)
        to_viewer = view_vectors(eye_points[mine], normals, scene.shading.local_viewer)
        parts = shade(eye_points[mine], normals, to_viewer, scene, shape.material,
                      visibility=visibility[:, np.flatnonzero(flat)[mine]])
        color[np.flatnonzero(flat)[mine]] = combine(*parts, shape.material)
    return ReferenceImage(
        color=color.reshape(height, width, 4),
        covered=covered,
        triangle=np.full((height, width), -1, dtype=np.int64),
        object=np.where(covered, nearest, -1),
        depth=np.where(covered, pick("depth"), np.inf),
        edge_margin=np.where(covered, pick("edge_margin"), np.inf),
        texel_footprint=np.zeros((height, width)),
        visibility=visibility.reshape(len(scene.lights), height, width),
    )
