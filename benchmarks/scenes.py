"""The benchmark scenes, and the plain arrays every peer renderer draws them from.

Three meshes (the seed's gold torus, the Stanford bunny, a 1.3M-triangle sphere), each
framed and lit the same way for every renderer: one white positional light, a gold
material, global ambient, the same camera. `GeometryDraw` carries exactly what a peer
needs (float32 positions, normals, uint32 indices, float64 matrices, light and material),
so all renderers rasterize identical triangles at identical screen positions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from wgpu_shading import Scene, load_scene
from wgpu_shading.assets.mesh_scene import mesh_scene
from wgpu_shading.scene import sphere_for_triangles

REPO = Path(__file__).resolve().parent.parent
# The shared models sit beside the checkout, or beside the folder of worktrees.
BUNNY = next(
    (path for path in (base / "shared" / "models" / "stanford-bunny.obj" for base in (REPO.parent, REPO.parent.parent)) if path.exists()),
    REPO.parent / "shared" / "models" / "stanford-bunny.obj",
)
TORUS_SCENE = REPO / "examples" / "gold_torus_phong.toml"


@dataclass(frozen=True)
class GeometryDraw:
    """One mesh, one light, one material: the common ground of all peers."""

    name: str
    positions: np.ndarray  # (N, 3) float32, relative to the mesh origin
    normals: np.ndarray  # (N, 3) float32
    indices: np.ndarray  # (F, 3) uint32
    eye_from_model: np.ndarray  # float64 4x4, column vectors
    world_from_model: np.ndarray
    camera_eye: tuple[float, float, float]
    camera_target: tuple[float, float, float]
    camera_up: tuple[float, float, float]
    fov_y: float
    near: float
    far: float
    light_eye_position: np.ndarray  # (3,)
    light_world_position: tuple[float, float, float]
    light_ambient: tuple[float, float, float, float]
    light_diffuse: tuple[float, float, float, float]
    light_specular: tuple[float, float, float, float]
    global_ambient: tuple[float, float, float, float]
    material_ambient: tuple[float, float, float, float]
    material_diffuse: tuple[float, float, float, float]
    material_specular: tuple[float, float, float, float]
    shininess: float
    size: tuple[int, int]

    @property
    def triangle_count(self) -> int:
        return len(self.indices)

    def gl_projection(self) -> np.ndarray:
        """gluPerspective (OpenGL's -1..1 depth), float64, column vectors."""
        width, height = self.size
        focal = 1.0 / math.tan(math.radians(self.fov_y) / 2.0)
        near, far = self.near, self.far
        projection = np.zeros((4, 4))
        projection[0, 0] = focal * height / width
        projection[1, 1] = focal
        projection[2, 2] = (far + near) / (near - far)
        projection[2, 3] = 2.0 * far * near / (near - far)
        projection[3, 2] = -1.0
        return projection


def geometry_draw(scene: Scene, name: str) -> GeometryDraw:
    """The arrays and matrices of a one-object, one-positional-light scene."""
    (obj,) = scene.objects
    (light,) = scene.lights
    camera = scene.camera
    eye_from_world = camera.eye_from_world()
    world_from_model = obj.world_from_model()
    return GeometryDraw(
        name=name,
        positions=obj.mesh.positions,
        normals=obj.mesh.normals,
        indices=obj.mesh.indices,
        eye_from_model=eye_from_world @ world_from_model,
        world_from_model=world_from_model,
        camera_eye=camera.eye,
        camera_target=camera.target,
        camera_up=camera.up,
        fov_y=camera.fov_y,
        near=camera.near,
        far=camera.far,
        light_eye_position=(eye_from_world @ np.append(light.position, 1.0))[:3],
        light_world_position=light.position,
        light_ambient=light.ambient,
        light_diffuse=light.diffuse,
        light_specular=light.specular,
        global_ambient=scene.ambient,
        material_ambient=obj.material.ambient,
        material_diffuse=obj.material.diffuse,
        material_specular=obj.material.specular,
        shininess=obj.material.shininess,
        size=scene.size,
    )


# The smoke run's stand-ins (python -m benchmarks --smoke): the same scenes with meshes
# small enough that every benchmark runs in moments.
TINY_TORUS_SEGMENTS = 8  # 128 triangles
TINY_SPHERE_TRIANGLES = 20_000  # above CLUSTER_MIN_TRIANGLES: the smoke run culls its clusters too


def torus_scene(size: int, segments: int = 72) -> Scene:
    """The classic gold torus scene (examples/gold_torus_phong.toml: Phong shading, one white
    positional light) with the issue's ~10K triangles: 72×72 segments = 10,368 triangles
    instead of the seed's 48×48 = 4,608; same shape and framing."""
    scene = load_scene(TORUS_SCENE)
    (obj,) = scene.objects
    from wgpu_shading.assets import load_mesh

    mesh = load_mesh(f"builtin:torus?major=0.5&minor=0.2&segments={segments}")
    return replace(scene, objects=(replace(obj, mesh=mesh),), size=(size, size))


def bunny_scene(size: int) -> Scene | None:
    """The Stanford bunny (~70K triangles), framed by the CLI's camera; None without shared/."""
    if not BUNNY.exists():
        return None
    return _cached_mesh_scene(str(BUNNY), size)


def sphere_scene(size: int, triangles: int = 1_300_000) -> Scene:
    scene = _cached_mesh_scene("builtin:sphere", size)  # camera and light for a unit sphere
    mesh = _sphere(triangles)
    (obj,) = scene.objects
    return replace(scene, objects=(replace(obj, mesh=mesh),))


def _one_light(scene: Scene) -> Scene:
    """The scene lit by one white positional light up, right and in front (the CLI's bare-mesh
    light before it got a key light plus headlight): the peers (moderngl, pygfx) implement
    exactly one positional light, and the numbers in docs/performance.md were measured so."""
    from wgpu_shading import PositionalLight
    from wgpu_shading.scene.view.bare_mesh import bounding_sphere

    center, radius = bounding_sphere(scene.objects[0].mesh)
    position = center + np.array([5.0, 2.0, 2.0]) * radius * 1.5
    return replace(scene, lights=(PositionalLight(position=tuple(float(v) for v in position)),))


_MESH_SCENES: dict[tuple[str, int], Scene] = {}
_SPHERES: dict[int, object] = {}


def _cached_mesh_scene(source: str, size: int) -> Scene:
    key = (source, size)
    if key not in _MESH_SCENES:
        same_mesh = next((s for (src, _), s in _MESH_SCENES.items() if src == source), None)
        if same_mesh is None:
            _MESH_SCENES[key] = _one_light(mesh_scene(source, (size, size), None))
        else:
            _MESH_SCENES[key] = replace(same_mesh, size=(size, size))
    return _MESH_SCENES[key]


def _sphere(triangles: int):
    if triangles not in _SPHERES:
        _SPHERES[triangles] = sphere_for_triangles(triangles)
    return _SPHERES[triangles]


def settle(renderer, scene: Scene) -> None:
    """Draw the scene until its upload is the steady one of a mesh drawn many times: a closed
    mesh's with clusters (render/gpu/clusters.py, whose build starts at the
    CLUSTERS_AFTER_FRAMES-th frame on the renderer's worker: render/gpu/cluster_builds.py),
    waiting for that build, so that no frame timed is one before or during it."""
    from wgpu_shading.render.gpu.clusters import CLUSTERS_AFTER_FRAMES

    for _ in range(CLUSTERS_AFTER_FRAMES + 1):
        renderer.render(scene)
    renderer.device_cache.cluster_builds.wait()
    renderer.render(scene)  # the frame that swaps to the clustered upload


def benchmark_scenes(sizes: tuple[int, ...], *, tiny: bool = False) -> list[tuple[str, int, Scene]]:
    """(label, size, scene) for every scene × size; the bunny only when shared/ exists.
    tiny: the smoke run's stand-ins instead (a 128-triangle torus, a 20K sphere; no bunny)."""
    result = []
    if tiny:
        for size in sizes:
            torus = torus_scene(size, TINY_TORUS_SEGMENTS)
            result.append((f"torus {torus.objects[0].mesh.triangle_count}", size, torus))
            result.append((f"sphere {TINY_SPHERE_TRIANGLES // 1000}K", size, sphere_scene(size, TINY_SPHERE_TRIANGLES)))
        return result
    for size in sizes:
        result.append(("torus 10K", size, torus_scene(size)))
        bunny = bunny_scene(size)
        if bunny is not None:
            result.append(("bunny 70K", size, bunny))
        result.append(("sphere 1.3M", size, sphere_scene(size)))
    return result
