"""Hard cases (docs/hard-cases.md): each renders to a float32 target, so a NaN or
Inf cannot hide behind the 8-bit clamp, and is compared with its correct limit.

This file holds the cases whose correct answer is "the same picture as the well-behaved
scene" (placement, scale, mirroring, depth precision) or an error; the cases whose limit
is a value of the lighting equation are in test_hard_cases_lighting.py."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading import (
    Camera,
    Material,
    PositionalLight,
    Scene,
    SceneObject,
    Shading,
    load_mesh,
    material,
)
from wgpu_shading.scene import Mesh

SIZE = (96, 96)
SPHERE = load_mesh("builtin:sphere?slices=32&stacks=16")


def assert_finite_unit(image: np.ndarray) -> None:
    assert np.isfinite(image).all(), "NaN or Inf reached the image"
    assert image.min() >= 0.0 and image.max() <= 1.0


def base_scene(frequency: str = "phong", **shading) -> Scene:
    return Scene(
        objects=(SceneObject(SPHERE, material("gold")),),
        lights=(PositionalLight(position=(4.0, 3.0, 5.0)),),
        camera=Camera(eye=(0.0, 0.5, 3.0), near=0.5, far=10.0),
        shading=Shading(frequency=frequency, reflection="blinn-phong", **shading),
        size=SIZE,
    )


def shifted(scene: Scene, offset: np.ndarray) -> Scene:
    """The same scene moved rigidly by `offset`: must render the same picture."""
    camera = scene.camera
    move = lambda point: tuple(np.asarray(point) + offset)  # noqa: E731
    return replace(
        scene,
        objects=tuple(replace(o, translate=move(o.translate)) for o in scene.objects),
        lights=tuple(replace(light, position=move(light.position)) for light in scene.lights),
        camera=replace(camera, eye=move(camera.eye), target=move(camera.target)),
    )


@pytest.mark.parametrize("frequency", ["flat", "gouraud", "phong"])
def test_far_from_the_origin_renders_like_near_it(renderer, frequency):
    """1e5 units from the origin, seen from 3 units away: model-view is formed in float64,
    so eye-space coordinates stay small. Without that (float32 world coordinates, spacing
    ~0.008 at 1e5) the sphere's surface and lighting visibly break up."""
    scene = base_scene(frequency)
    expected = renderer.render(scene, float32=True)
    far = renderer.render(shifted(scene, np.array([1e5, -1e5, 1e5])), float32=True)
    assert_finite_unit(far)
    assert np.abs(far - expected).max() <= 2 / 255


def test_mesh_data_far_from_the_origin(renderer):
    """Vertex data itself at 1e5: the mesh stores float32 offsets from a float64 origin."""
    offset = np.array([1e5, 1e5, -1e5])
    moved = Mesh.from_arrays(SPHERE.world_positions() + offset, SPHERE.indices, normals=SPHERE.normals)
    scene = base_scene()
    far_scene = shifted(scene, offset)
    far_scene = replace(far_scene, objects=(replace(far_scene.objects[0], mesh=moved, translate=(0.0, 0.0, 0.0)),))
    np.testing.assert_allclose(renderer.render(far_scene, float32=True), renderer.render(scene, float32=True), atol=2 / 255)


@pytest.mark.parametrize("frequency", ["flat", "gouraud", "phong"])
def test_tiny_geometry_renders_like_unit_geometry(renderer, frequency):
    """The whole scene scaled by 1e-5 (mesh data 1e-5 in size): same picture. Guards with
    absolute thresholds (|v|² ≤ 1e-30) must not mistake small for zero."""
    scene = base_scene(frequency)
    scale = 1e-5
    tiny_mesh = Mesh.from_arrays(SPHERE.world_positions() * scale, SPHERE.indices, normals=SPHERE.normals)
    camera = scene.camera
    tiny = replace(
        scene,
        objects=(replace(scene.objects[0], mesh=tiny_mesh),),
        lights=tuple(replace(light, position=tuple(np.asarray(light.position) * scale)) for light in scene.lights),
        camera=replace(camera, eye=tuple(np.asarray(camera.eye) * scale), near=camera.near * scale, far=camera.far * scale),
    )
    image = renderer.render(tiny, float32=True)
    assert_finite_unit(image)
    assert np.abs(image - renderer.render(scene, float32=True)).max() <= 2 / 255


@pytest.mark.parametrize("frequency", ["flat", "gouraud", "phong"])
def test_mirrored_transform_keeps_normals_outward(renderer, frequency):
    """scale (-1, 1, 1) mirrors the sphere (which is symmetric, so the picture is the same).
    The negative determinant flips the winding on screen; with two-sided lighting, a
    renderer that does not flip its front-face rule would light the visible outside as a
    back face (with -N) and draw it dark."""
    scene = base_scene(frequency, two_sided=True)
    mirrored = replace(scene, objects=(replace(scene.objects[0], scale=(-1.0, 1.0, 1.0)),))
    image = renderer.render(mirrored, float32=True)
    assert_finite_unit(image)
    # The mirror image of a symmetric sphere about x: compare with the unmirrored render
    # mirrored in the image (the light is not symmetric, so mirror the light too).
    light = scene.lights[0]
    mirrored_light = replace(scene, lights=(replace(light, position=(-light.position[0], *light.position[1:])),))
    expected = renderer.render(mirrored_light, float32=True)[:, ::-1]
    # Rasterization differs by a pixel at the silhouette; compare the interior.
    interior = (expected[:, :, :3].sum(axis=2) > 0) & (image[:, :, :3].sum(axis=2) > 0)
    interior[1:-1, 1:-1] &= interior[:-2, 1:-1] & interior[2:, 1:-1] & interior[1:-1, :-2] & interior[1:-1, 2:]
    difference = np.abs(image - expected)[interior]
    assert difference.max() <= 3 / 255 or frequency == "flat" and np.mean(difference <= 3 / 255) > 0.97


def test_nonuniform_scale_uses_the_inverse_transpose(renderer):
    """A unit sphere scaled (1, 3, 1) is an ellipsoid. Its correct normals come from the
    inverse transpose; the same ellipsoid built directly (positions scaled, normals the
    normalized gradient of x² + y²/9 + z²) must render identically. Transforming normals
    with the model matrix itself would tilt them towards Y and change the shading."""
    scene = base_scene()
    scaled = replace(scene, objects=(replace(scene.objects[0], scale=(1.0, 3.0, 1.0)),))
    positions = SPHERE.world_positions() * [1.0, 3.0, 1.0]
    gradient = positions * [1.0, 1.0 / 9.0, 1.0]
    ellipsoid = Mesh.from_arrays(positions, SPHERE.indices, normals=gradient)
    built = replace(scene, objects=(replace(scene.objects[0], mesh=ellipsoid),))
    camera = replace(scene.camera, eye=(0.0, 0.5, 7.0), far=20.0)
    a = renderer.render(replace(scaled, camera=camera), float32=True)
    b = renderer.render(replace(built, camera=camera), float32=True)
    # Not bit-identical: the scaled path interpolates the unnormalized M^-T·n (lengths differ
    # per vertex, as in the seed's shader) where the built mesh interpolates unit normals.
    assert np.abs(a - b).max() <= 4 / 255
    # and it is not the wrong (model-matrix) normal transform:
    wrong_normals = Mesh.from_arrays(positions, SPHERE.indices, normals=SPHERE.normals * [1.0, 3.0, 1.0])
    c = renderer.render(replace(scene, objects=(replace(scene.objects[0], mesh=wrong_normals),), camera=camera), float32=True)
    assert np.abs(a - c).max() > 20 / 255


def test_near_far_ratio_of_1e7_does_not_z_fight(renderer):
    """near = 1e-5, far = 100, two planes 1e-3 apart at distance 10. Reversed Z with a
    float32 depth buffer keeps ~1e-13 absolute depth resolution there; a conventional
    depth mapping would have ~6e-8 resolution for a 1e-10 depth difference and fight."""
    plane = load_mesh("builtin:plane?size=4")
    red = Material(ambient=(0, 0, 0, 1), diffuse=(0, 0, 0, 1), emission=(1, 0, 0, 1))
    blue = Material(ambient=(0, 0, 0, 1), diffuse=(0, 0, 0, 1), emission=(0, 0, 1, 1))
    scene = Scene(
        objects=(
            SceneObject(plane, blue, translate=(0.0, 0.0, -10.001)),
            SceneObject(plane, red, translate=(0.0, 0.0, -10.0)),
        ),
        camera=Camera(eye=(0.0, 0.0, 0.0), target=(0.0, 0.0, -1.0), near=1e-5, far=100.0, fov_y=10.0),
        size=(64, 64),
    )
    image = renderer.render(scene, float32=True)
    assert_finite_unit(image)
    assert (image[:, :, 0] == 1.0).all() and (image[:, :, 2] == 0.0).all(), "the farther plane showed through"
    # Drawing order must not matter either.
    flipped = renderer.render(replace(scene, objects=scene.objects[::-1]), float32=True)
    assert (flipped[:, :, 0] == 1.0).all()


def test_degenerate_triangles_change_nothing(renderer):
    """Zero-area triangles (repeated and collinear vertices) mixed into a mesh cover no
    pixels and must not disturb vertex normals or produce NaN (flat shading takes their
    normal from a cross product of length zero)."""
    positions = SPHERE.world_positions()
    faces = SPHERE.indices.astype(np.int64)
    degenerate = np.array([[0, 0, 0], [5, 5, 6], [10, 11, 10], [20, 20, 20]])
    mesh = Mesh.from_arrays(positions, np.concatenate([faces, degenerate]))
    clean = Mesh.from_arrays(positions, faces)
    assert np.isfinite(mesh.normals).all()
    for frequency in ("flat", "gouraud", "phong"):
        scene = base_scene(frequency)
        with_degenerate = renderer.render(replace(scene, objects=(replace(scene.objects[0], mesh=mesh),)), float32=True)
        without = renderer.render(replace(scene, objects=(replace(scene.objects[0], mesh=clean),)), float32=True)
        assert_finite_unit(with_degenerate)
        np.testing.assert_array_equal(with_degenerate, without)
