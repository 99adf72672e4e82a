"""Mesh and Texture are snapshots of the caller's arrays: copied on construction, never made
read-only behind the caller's back, so a renderer's identity-keyed upload cache can never
show a picture the arrays no longer describe."""

from __future__ import annotations

import numpy as np

from wgpu_shading import Camera, Material, Mesh, Renderer, Scene, SceneObject, Texture
from wgpu_shading.render.device import default_device


def quad(uvs: bool = False):
    positions = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
    indices = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
    return positions, indices, (np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32) if uvs else None)


def scene_of(mesh: Mesh, texture: Texture | None = None) -> Scene:
    material = Material(ambient=(1, 1, 1), diffuse=(0, 0, 0), specular=(0, 0, 0), texture=texture)
    camera = Camera(eye=(0, 0, 4), target=(0, 0, 0), up=(0, 1, 0), fov_y=60.0)
    return Scene(objects=[SceneObject(mesh, material)], camera=camera, lights=[], size=(16, 16), ambient=(1, 1, 1))


def coverage(image: np.ndarray) -> int:
    return int((image[:, :, :3].max(axis=2) > 0).sum())


def test_the_callers_mesh_arrays_stay_writable_and_a_rewrite_never_shows_stale(renderer):
    positions, indices, _ = quad()
    mesh = Mesh.from_arrays(positions, indices, name="quad")
    before = renderer.render(scene_of(mesh))
    assert positions.flags.writeable and indices.flags.writeable  # not frozen behind the caller's back
    positions *= 0.25  # the caller rewrites its own array in place
    # The Mesh made before is a snapshot: the warm renderer and a fresh one agree on it.
    again = renderer.render(scene_of(mesh))
    fresh = Renderer(device=default_device()).render(scene_of(mesh))
    np.testing.assert_array_equal(again, before)
    np.testing.assert_array_equal(fresh, before)
    # A Mesh made from the rewritten array shows the change, on the same renderer.
    smaller = renderer.render(scene_of(Mesh.from_arrays(positions, indices, name="quad")))
    assert 0 < coverage(smaller) < coverage(before) / 4


def test_mesh_constructed_directly_copies_writable_arrays():
    positions, indices, _ = quad()
    normals = np.tile(np.float32([0, 0, 1]), (4, 1))
    mesh = Mesh(positions=positions, normals=normals, indices=indices)
    assert positions.flags.writeable and normals.flags.writeable and indices.flags.writeable
    assert not mesh.positions.flags.writeable and not np.shares_memory(mesh.positions, positions)
    positions[0] = 9.0
    assert mesh.positions[0, 0] == -1.0


def test_the_callers_texture_pixels_stay_writable_and_a_rewrite_never_shows_stale(renderer):
    positions, indices, uvs = quad(uvs=True)
    mesh = Mesh.from_arrays(positions, indices, uvs=uvs, name="quad")
    pixels = np.zeros((4, 4, 4), np.uint8)
    pixels[..., 0] = 255
    pixels[..., 3] = 255  # red, RGBA8 and contiguous: the case that was kept without a copy
    texture = Texture(pixels, name="red")
    red = renderer.render(scene_of(mesh, texture))
    assert pixels.flags.writeable
    pixels[..., 0], pixels[..., 2] = 0, 255  # now blue
    np.testing.assert_array_equal(renderer.render(scene_of(mesh, texture)), red)
    blue = renderer.render(scene_of(mesh, Texture(pixels, name="blue")))
    centre = blue[8, 8]
    assert centre[2] > 200 and centre[0] < 20 and red[8, 8][0] > 200


def test_a_loaded_mesh_is_not_copied_twice():
    """Arrays from_arrays computes itself are kept as they are (no second copy of a big mesh)."""
    positions, indices, _ = quad()
    mesh = Mesh.from_arrays(positions.astype(np.float64), indices.astype(np.int64), name="quad")
    again = Mesh(positions=mesh.positions, normals=mesh.normals, indices=mesh.indices)
    assert again.positions is mesh.positions and again.indices is mesh.indices
