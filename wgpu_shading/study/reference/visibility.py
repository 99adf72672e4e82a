"""Exact shadows (docs/shadows.md#the-exact-answer): V_i(p) = 0 where the segment
from the surface point p towards light i (to its position; to infinity against a
directional light's direction) meets a shadow-casting triangle of the scene, else 1.

The rays are cast against the same triangles the renderer draws, placed in world space in
float64, with trimesh's ray engine on Embree (`embreex`): a well-kept, exact-to-float32
BVH traversal, where a numpy loop over every (ray, triangle) pair would take minutes.
Embree works in float32, so three things keep the answer to float64 semantics:

- trimesh shifts and scales the triangles into a box about 100 units across before they
  are rounded to float32, so the precision relative to the scene is the same at a scale of
  1e-3 and 1e3 (its `scale_to_box`);
- every hit Embree reports is recomputed in float64 by trimesh (the ray meets the hit
  triangle's plane) and filtered here in float64: hits on the point's own triangle, hits
  closer than `SELF_HIT_DISTANCE` × the scene's size and hits beyond a positional light
  are dropped. A ray starts *on* its own surface, and float32 rounding of its origin may put
  it a hair below that surface, where Embree would report the own triangle (or a neighbour
  sharing the edge the point lies on) at t ≈ 0 — "shadow acne" in the reference itself.
  The origin is *not* moved off the surface: moving it along the normal would move the
  shadow boundary on grazing receivers (by offset / tan(elevation)), and along the ray
  would skip real occluders at contact points;
- all hits along the ray are collected (trimesh steps past each one), so a caster whose
  entry point is dropped as too close (a sphere resting on the plane, near the contact
  point) still shadows through its exit point.

- a point on a closed casting surface (trimesh: watertight and consistently wound once
  coincident vertices are merged; its own test, not the renderer's), on a triangle turned
  from the light, the light outside the solid, is shadowed: its segment enters the solid at
  once and must leave through the surface. The exit is dropped as too close next to the
  edge where the light grazes the surface, and on that edge the segment only touches it;
  the point belongs to its triangle, shadowed up to its edges (random scenes 190, 258).

What is left of float32 is where a ray passes within ~1e-7 of the scene's size of a
triangle's edge: a set of measure zero, far below a pixel.
Single-sided and zero-thickness casters occlude from both sides (no culling); casters
outside the view occlude (every casting object is in the ray scene); objects with
`cast_shadows = false` are not; points of objects with `receive_shadows = false` get V = 1.
"""

from __future__ import annotations

import numpy as np

from ...errors import SceneError
from ...scene import DirectionalLight, Light, Scene
from .transforms import transform_points, world_from_model

# Hits closer to the ray's origin than this fraction of the casters' bounding-box diagonal
# are the origin's own surface (float32 rounding), not an occluder: 10× the float32
# resolution of the scaled box (2⁻²⁴ · 100 / 100 ≈ 6e-8), and trimesh's step past a hit.
SELF_HIT_DISTANCE = 1e-6
MAX_HITS_PER_RAY = 64  # a ray through more surfaces than this is counted as shadowed anyway


def segments_to_light(light: Light, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The segments a shadow test walks from world points (N, 3) towards a light: unit
    directions (N, 3) and lengths (N,) — inf towards a directional light; 0 where a
    positional or spot light stands exactly at the point (its direction is then 0)."""
    if isinstance(light, DirectionalLight):
        towards = -np.asarray(light.direction, dtype=np.float64)
        directions = np.broadcast_to(towards / np.linalg.norm(towards), points.shape)
        return directions, np.full(len(points), np.inf)
    offset = np.asarray(light.position, dtype=np.float64) - points
    lengths = np.linalg.norm(offset, axis=1)
    return offset / np.where(lengths > 0.0, lengths, 1.0)[:, None], lengths


def _ray_engine(vertices: np.ndarray, faces: np.ndarray):
    """trimesh's Embree intersector on these triangles (no merging or cleaning: the
    triangles are exactly the renderer's)."""
    try:
        import embreex  # noqa: F401  (trimesh falls back to a slow engine without it)
    except ImportError as error:  # pragma: no cover - embreex is in the test extra
        raise SceneError(
            "the float64 reference needs embreex for shadows (pip install 'wgpu-shading[reference]')"
        ) from error
    import trimesh
    from trimesh.ray.ray_pyembree import RayMeshIntersector

    mesh = trimesh.Trimesh(vertices=vertices, faces=faces, process=False, validate=False)
    return RayMeshIntersector(mesh, scale_to_box=True)


def _closed_surface(vertices: np.ndarray, faces: np.ndarray):
    """trimesh's own view of a caster's world triangles: (mesh, +1 or −1 for outward or
    inward winding) when they close a volume (watertight, consistently wound once its
    coincident vertices are merged), else None."""
    import trimesh

    if len(faces) == 0:
        return None
    mesh = trimesh.Trimesh(vertices=vertices, faces=faces, process=True)
    if not (mesh.is_watertight and mesh.is_winding_consistent) or mesh.volume == 0.0:
        return None
    return mesh, float(np.sign(mesh.volume))


class ShadowRays:
    """The scene's shadow-casting triangles in world space (float64), ready for shadow rays.

    `visibility(points, objects, triangles)` → (lights, N) V_i at world points that lie on
    triangle `triangles[k]` of object `objects[k]` (their own triangle is never an occluder)."""

    def __init__(self, scene: Scene):
        self.scene = scene
        vertices, faces, self._first_face = [], [], {}
        count = 0
        for index, obj in enumerate(scene.objects):
            if not obj.cast_shadows:
                continue
            self._first_face[index] = sum(len(f) for f in faces)
            vertices.append(transform_points(world_from_model(obj), obj.mesh.positions.astype(np.float64)))
            faces.append(obj.mesh.indices.astype(np.int64) + count)
            count += len(vertices[-1])
        self._solids = {index: _closed_surface(vertices[k], scene.objects[index].mesh.indices.astype(np.int64))
                        for k, index in enumerate(self._first_face)}
        self._engine = None
        if faces:
            self._vertices = np.concatenate(vertices)
            self._faces = np.concatenate(faces)
            lower, upper = self._vertices.min(axis=0), self._vertices.max(axis=0)
            self.min_distance = SELF_HIT_DISTANCE * float(np.linalg.norm(upper - lower))

    def _own_faces(self, objects: np.ndarray, triangles: np.ndarray) -> np.ndarray:
        """Index of each point's own triangle in the ray scene, -1 if its object does not cast."""
        first = np.array([self._first_face.get(i, -1) for i in range(len(self.scene.objects))], dtype=np.int64)
        start = first[objects]
        return np.where(start >= 0, start + triangles, -1)

    def occluded(self, origins: np.ndarray, directions: np.ndarray, lengths: np.ndarray, own: np.ndarray) -> np.ndarray:
        """(N,) bool: the segment origin + t·direction, min_distance < t < length (inf: a ray),
        meets a casting triangle other than `own`. Directions are unit vectors."""
        blocked = np.zeros(len(origins), dtype=bool)
        if not hasattr(self, "_faces") or len(origins) == 0:
            return blocked
        if self._engine is None:
            self._engine = _ray_engine(self._vertices, self._faces)
        tri, ray, locations = self._engine.intersects_id(
            origins, directions, multiple_hits=True, max_hits=MAX_HITS_PER_RAY, return_locations=True
        )
        t = np.einsum("ij,ij->i", locations - origins[ray], directions[ray])  # float64, recomputed by trimesh
        real = (tri != own[ray]) & (t > self.min_distance) & (t < lengths[ray])
        blocked[ray[real]] = True
        return blocked

    def visibility(self, points: np.ndarray, objects: np.ndarray, triangles: np.ndarray) -> np.ndarray:
        """(lights, N) float64: 1 lit, 0 shadowed; 1 for lights without shadows and for
        points of objects that do not receive shadows."""
        scene = self.scene
        points = np.asarray(points, dtype=np.float64)
        result = np.ones((len(scene.lights), len(points)))
        receives = np.array([obj.receive_shadows for obj in scene.objects], dtype=bool)[objects] if len(points) else np.zeros(0, bool)
        own = self._own_faces(objects, triangles) if len(points) else np.zeros(0, np.int64)
        for index, light in enumerate(scene.lights):
            if not light.shadows:
                continue
            directions, lengths = segments_to_light(light, points)
            # A light exactly at the point shadows nothing there (no segment).
            rays = receives & (lengths > 0.0)
            blocked = self.occluded(points[rays], np.ascontiguousarray(directions[rays]), lengths[rays], own[rays])
            result[index, np.flatnonzero(rays)[blocked]] = 0.0
            result[index, rays & self._inside_first(light, directions, objects, own)] = 0.0
        return result

    def _inside_first(self, light: Light, directions: np.ndarray, objects: np.ndarray, own: np.ndarray) -> np.ndarray:
        """(N,) bool: points on a triangle of a closed casting surface that faces away from
        the light, the light outside that solid: the segment enters the solid at once and
        must leave it through the surface. The ray cast finds that exit unless it lies
        nearer than min_distance — a point next to the edge where the light grazes the
        surface — or the point lies on that edge itself, where the ray only touches the
        surface; a pixel's point belongs to its triangle, whose state is this one up to the
        edge (random scenes 190, 258)."""
        hidden = np.zeros(len(own), dtype=bool)
        for index, solid in self._solids.items():
            mine = (objects == index) & (own >= 0)
            if solid is None or not mine.any():
                continue
            mesh, outward = solid
            if not isinstance(light, DirectionalLight) and mesh.contains(np.array([light.position], dtype=np.float64))[0]:
                continue
            corners = self._vertices[self._faces[own[mine]]]
            normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]) * outward
            hidden[mine] = np.einsum("ij,ij->i", normals, directions[mine]) < 0.0
        return hidden
