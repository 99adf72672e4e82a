"""What the camera may see of each object: the part of its world bounding box inside the
view volume, as points whose convex hull it is (float64). The shadow maps are fitted to
these regions (shadow_views.py), so their texels go where the image needs them."""

from __future__ import annotations

import numpy as np

from ...scene import Scene, SceneObject
from ..shaders.uniforms import clip_from_eye

# The faces of a box or frustum given as 8 corners indexed 4x + 2y + z (x, y, z ∈ {0, 1}).
_FACES = ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3))


def world_box(obj: SceneObject) -> np.ndarray:
    """(8, 3) corners of the object's model-space bounding box in world space, indexed 4x + 2y + z.

    The box of the *stored* positions (relative to mesh.origin): world_from_model puts the
    origin back itself, so mesh.bounds() here counted it twice and a mesh not centred on its
    own origin (a loaded model) got its maps fitted where it is not (tests/test_shadow_views.py)."""
    lower, upper = obj.mesh.relative_bounds
    corners = np.array([[x, y, z] for x in (lower[0], upper[0]) for y in (lower[1], upper[1]) for z in (lower[2], upper[2])])
    model = obj.world_from_model()
    return corners @ model[:3, :3].T + model[:3, 3]


def camera_frustum(scene: Scene) -> np.ndarray:
    """(8, 3) world-space corners of the camera's view volume, indexed 4x + 2y + z over the
    clip box (x, y from −1 to 1; z from the far plane to the near one)."""
    width, height = scene.size
    world_from_clip = np.linalg.inv(clip_from_eye(scene.camera, width / height) @ scene.camera.eye_from_world())
    corners = np.array([[x, y, z, 1.0] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (0.0, 1.0)])
    world = corners @ world_from_clip.T
    return world[:, :3] / world[:, 3:]


def planes(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Outward unit normals (K, 3) and offsets (K,) of the faces of a convex hexahedron (8
    corners indexed 4x + 2y + z): inside is normal·p <= offset. Faces of zero area (a flat
    box) are left out."""
    quads = corners[np.array(_FACES)]  # (6, 4, 3)
    normals = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
    lengths = np.linalg.norm(normals, axis=1)
    keep = lengths > 0.0
    normals = normals[keep] / lengths[keep, None]
    offsets = np.einsum("ij,ij->i", normals, quads[keep, 0])
    flip = normals @ corners.mean(axis=0) > offsets  # point every normal away from the centre
    return np.where(flip[:, None], -normals, normals), np.where(flip, -offsets, offsets)


def _clip_polygon(polygon: np.ndarray, normal: np.ndarray, offset: float) -> np.ndarray:
    """Sutherland–Hodgman: the part of a convex polygon where normal·p <= offset."""
    if len(polygon) == 0:
        return polygon
    distance = polygon @ normal - offset
    kept = []
    for k in range(len(polygon)):
        following = (k + 1) % len(polygon)
        if distance[k] <= 0.0:
            kept.append(polygon[k])
        if (distance[k] < 0.0) != (distance[following] < 0.0) and distance[k] != distance[following]:
            kept.append(polygon[k] + (polygon[following] - polygon[k]) * (distance[k] / (distance[k] - distance[following])))
    return np.array(kept).reshape(-1, 3)


def clipped_box(box: np.ndarray, frustum: np.ndarray, frustum_planes: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """(K, 3) points whose convex hull is the box (8 corners) within the frustum (8 corners):
    the box's faces clipped by the frustum's planes, and the frustum's corners inside the
    box. Every vertex of the intersection is one of them. Empty when they do not meet."""
    normals, offsets = planes(frustum) if frustum_planes is None else frustum_planes
    extent = float(np.ptp(box, axis=0).max() + np.ptp(frustum, axis=0).max())
    offsets = offsets + 1e-9 * extent  # a point on a face is inside
    distance = box @ normals.T - offsets  # (8, K)
    if (distance <= 0.0).all():
        return box  # wholly inside
    if (distance > 0.0).all(axis=0).any():
        return np.zeros((0, 3))  # wholly outside one plane
    points = []
    for face in _FACES:
        polygon = box[list(face)]
        for normal, offset in zip(normals, offsets):
            polygon = _clip_polygon(polygon, normal, offset)
        points.append(polygon)
    box_normals, box_offsets = planes(box)
    inside = (frustum @ box_normals.T <= box_offsets + 1e-9 * extent).all(axis=1)
    inside &= np.all((frustum >= box.min(axis=0) - 1e-9 * extent) & (frustum <= box.max(axis=0) + 1e-9 * extent), axis=1)
    points.append(frustum[inside])
    return np.concatenate(points)


def visible_receivers(scene: Scene) -> dict[int, np.ndarray]:
    """For each object that receives shadows and that the camera may see, by its index:
    points whose convex hull holds the part of its bounding box inside the view volume."""
    frustum = camera_frustum(scene)
    frustum_planes = planes(frustum)
    regions = {}
    for index, obj in enumerate(scene.objects):
        if obj.receive_shadows:
            points = clipped_box(world_box(obj), frustum, frustum_planes)
            if len(points):
                regions[index] = points
    return regions


def common_points(*solids: np.ndarray) -> np.ndarray:
    """(K, 3) points whose convex hull is the intersection of convex hexahedra (8 corners
    each, indexed 4x + 2y + z): each solid's faces clipped by every other solid's planes.
    A vertex of the intersection lies on a face of one solid and inside the others, so it
    is a vertex of that face so clipped. Empty when they do not all meet."""
    bounds = [planes(solid) for solid in solids]
    extent = max(float(np.ptp(solid, axis=0).max()) for solid in solids)
    points = []
    for index, solid in enumerate(solids):
        for face in _FACES:
            polygon = solid[list(face)]
            for other, (normals, offsets) in enumerate(bounds):
                if other != index:
                    for normal, offset in zip(normals, offsets + 1e-9 * extent):
                        polygon = _clip_polygon(polygon, normal, offset)
            points.append(polygon)
    return np.concatenate(points) if points else np.zeros((0, 3))
