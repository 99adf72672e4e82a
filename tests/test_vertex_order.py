"""Meshes are uploaded in vertex-cache order (render/gpu/vertex_order.py): the same pixels.

The reference is the same scene drawn from the mesh's own order (WGPU_SHADING_VERTEX_ORDER=0):
images must be bit-identical, for shuffled meshes (so the reorder really changes the
order), every shading frequency (flat shading pulls vertices from storage buffers by
corner index), several parts with a blended one, vertex colors and texture coordinates.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading import Camera, Renderer, Scene, SceneObject, load_mesh
from wgpu_shading.render.gpu.vertex_order import cache_order
from wgpu_shading.scene import Material, Mesh, PositionalLight, Shading
from wgpu_shading.scene.geometry.mesh import MeshPart

RED = Material(ambient=(0.2, 0.0, 0.0, 1.0), diffuse=(0.8, 0.1, 0.1, 1.0), specular=(1, 1, 1, 1), shininess=30.0)
GLASS = Material(diffuse=(0.1, 0.8, 0.2, 0.4), specular=(1, 1, 1, 1), shininess=60.0, alpha_mode="blend")
# The real meshes beside the checkout (../shared/models), also from a worktree deeper down.
SHARED_MODELS = next(
    (p / "shared" / "models" for p in Path(__file__).resolve().parents if (p / "shared" / "models").is_dir()), Path("missing")
)
GOLD = Material(diffuse=(0.75, 0.6, 0.2, 1.0), specular=(0.6, 0.6, 0.5, 1.0), shininess=51.0)


def shuffled(mesh: Mesh, seed: int = 1, parts=None) -> Mesh:
    """The mesh with its triangles and vertices in random order (same surface)."""
    rng = np.random.default_rng(seed)
    vertex_order = rng.permutation(mesh.vertex_count)
    new_number = np.empty_like(vertex_order)
    new_number[vertex_order] = np.arange(mesh.vertex_count)
    indices = new_number[mesh.indices][rng.permutation(mesh.triangle_count)].astype(np.uint32)
    colors = rng.random((mesh.vertex_count, 4), dtype=np.float32)
    colors[:, 3] = 1.0
    uvs = None if mesh.uvs is None else mesh.uvs[vertex_order]
    return Mesh(
        positions=mesh.positions[vertex_order], normals=mesh.normals[vertex_order], indices=indices, uvs=uvs,
        colors=colors[vertex_order] if parts else None, parts=parts or (), name=f"shuffled {mesh.name}",
    )


def scene_of(mesh: Mesh, frequency: str = "phong", material: Material | None = GOLD) -> Scene:
    return Scene(
        objects=(SceneObject(mesh, material=material),),
        lights=(PositionalLight(position=(2.0, 3.0, 4.0)),),
        camera=Camera(eye=(0.0, 0.4, 2.2), fov_y=45.0, near=0.5, far=10.0),
        shading=Shading(frequency=frequency),
        size=(96, 80),
    )


def both_orders(device, scene: Scene, monkeypatch) -> tuple[np.ndarray, np.ndarray]:
    """The scene from the mesh's own order and in cache order, each on fresh caches."""
    monkeypatch.setenv("WGPU_SHADING_VERTEX_ORDER", "0")
    own = Renderer(device).render(scene)
    monkeypatch.delenv("WGPU_SHADING_VERTEX_ORDER")
    reordered = Renderer(device).render(scene)
    return own, reordered


def test_each_part_keeps_its_triangles_and_corner_order_and_blended_parts_keep_their_order():
    torus = load_mesh("builtin:torus?segments=12")
    parts = (MeshPart(0, 100), MeshPart(100, 88, GLASS), MeshPart(188, torus.triangle_count - 188))
    mesh = shuffled(torus, parts=parts)
    scratch, order = cache_order(mesh.indices, mesh.vertex_count, mesh.parts, frozenset({1}))
    new_indices = scratch.array.reshape(-1, 3).copy()
    scratch.close()
    as_old = order.gather[new_indices]  # every corner as the old vertex number
    for number, part in enumerate(parts):
        before = mesh.indices[part.first : part.first + part.count]
        after = as_old[part.first : part.first + part.count]
        if number == 1:
            np.testing.assert_array_equal(after, before)  # blended: same triangles, same order
        else:
            assert sorted(map(tuple, after)) == sorted(map(tuple, before))  # same corners, same order in each
            assert not np.array_equal(after, before)
    np.testing.assert_array_equal(order.vertices(mesh.positions)[new_indices], mesh.positions[as_old])
    first_use = np.unique(new_indices.reshape(-1), return_index=True)[1]
    assert np.all(np.diff(first_use) > 0)  # vertices numbered in the order the triangles first use them


@pytest.mark.parametrize("frequency", ["phong", "gouraud", "flat"])
def test_same_pixels_for_every_frequency(renderer, monkeypatch, frequency):
    scene = scene_of(shuffled(load_mesh("builtin:torus?segments=24")), frequency)
    own, reordered = both_orders(renderer.device, scene, monkeypatch)
    assert (own[..., :3] > 0).any(axis=2).mean() > 0.1  # the torus is in view
    np.testing.assert_array_equal(reordered, own)


def test_same_pixels_with_parts_a_blended_part_and_vertex_colors(renderer, monkeypatch):
    torus = load_mesh("builtin:torus?segments=24")
    third = torus.triangle_count // 3
    parts = (MeshPart(0, third, RED), MeshPart(third, third, GLASS), MeshPart(2 * third, torus.triangle_count - 2 * third, GOLD))
    scene = scene_of(shuffled(torus, seed=2, parts=parts), material=None)
    own, reordered = both_orders(renderer.device, scene, monkeypatch)
    np.testing.assert_array_equal(reordered, own)


def test_same_pixels_textured(renderer, monkeypatch):
    from wgpu_shading import load_scene

    scene = load_scene("example:checker_sphere_modulate.toml")
    (obj,) = scene.objects
    mesh = shuffled(obj.mesh, seed=3)
    assert mesh.uvs is not None
    scene = replace(scene, objects=(replace(obj, mesh=mesh),), size=(96, 96))
    own, reordered = both_orders(renderer.device, scene, monkeypatch)
    np.testing.assert_array_equal(reordered, own)


@pytest.mark.skipif(not (SHARED_MODELS / "stanford-bunny.obj").exists(), reason="shared models not beside the checkout")
def test_same_pixels_on_a_scan(renderer, monkeypatch):
    from wgpu_shading.assets.mesh_scene import mesh_scene

    scene = mesh_scene(str(SHARED_MODELS / "stanford-bunny.obj"), (128, 128), None)
    own, reordered = both_orders(renderer.device, scene, monkeypatch)
    np.testing.assert_array_equal(reordered, own)


def test_the_devices_of_render_many_share_one_order_per_mesh(renderer, monkeypatch):
    """render_many's helper devices take the order the first device computed (meshoptimizer
    runs once per mesh, not once per device), and every frame is still render()'s."""
    from wgpu_shading.render.gpu import mesh_uploads

    calls = []
    real = mesh_uploads.cache_order
    monkeypatch.setattr(mesh_uploads, "cache_order", lambda *args, **kwargs: calls.append(1) or real(*args, **kwargs))
    torus = load_mesh("builtin:torus?segments=20")
    meshes = [shuffled(torus, seed) for seed in (1, 2)]
    scenes = [replace(scene_of(mesh), camera=Camera(eye=(0.3 * k, 0.4, 2.2), near=0.5, far=10.0))
              for mesh in meshes for k in range(3)]
    fresh = Renderer(renderer.device)
    frames = [frame.color for frame in fresh.render_many(scenes, parallel=2)]
    assert len(calls) == 2  # two meshes, each ordered once for both devices
    alone = Renderer(renderer.device)
    for scene, frame in zip(scenes, frames):
        assert np.array_equal(frame, alone.render(scene))
