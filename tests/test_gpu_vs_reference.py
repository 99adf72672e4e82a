"""The GPU (WGSL, float32, lavapipe) against the float64 reference (numpy).

Acceptance criteria:
- where the exact answer is computable (a plane facing the camera, a sphere), GPU Phong
  shading with both reflection models agrees with the float64 evaluation of the lighting
  equation within 1/255 on at least 99.9 % of the covered pixels;
- every frequency agrees with the same-mesh reference (the same triangles, rasterized and
  shaded in float64 by wgpu_shading.study.reference) within 1/255 on at least 99.9 % of the
  covered pixels, over scenes with every light kind, attenuation, a texture in each
  combine mode, two-sided lighting, mirrored objects and both viewer models.

Which pixels are compared: those the reference covers, minus a thin band around edges
(`edge_margin`, the distance from the pixel centre to the nearest edge of the visible
triangle, or to the exact silhouette for analytic shapes). On that band the GPU's float32
vertex positions may legitimately snap to the other side of a pixel centre, giving the
pixel to the neighbouring triangle or to the background; nowhere else may coverage differ.
"""

from __future__ import annotations


import numpy as np
import pytest

from wgpu_shading.study import reference as ref
from wgpu_shading.scene import Mesh, cube, plane, sphere_for_triangles, torus, uv_sphere
from wgpu_shading.scene import (
    Camera,
    DirectionalLight,
    Material,
    PositionalLight,
    Scene,
    SceneObject,
    Shading,
    SpotLight,
    Texture,
)

from support import EDGE_BAND, SILHOUETTE_BAND, compare, smooth_texture  # noqa: E402


def lights_of_every_kind() -> tuple:
    return (
        DirectionalLight(direction=(-1.0, -0.6, -1.0), ambient=(0.05, 0.05, 0.05, 1), diffuse=(0.35, 0.35, 0.3, 1), specular=(0.5, 0.5, 0.5, 1)),
        PositionalLight(position=(1.5, 1.2, 2.5), diffuse=(0.5, 0.45, 0.4, 1), specular=(0.6, 0.6, 0.6, 1), attenuation=(1.0, 0.1, 0.05)),
        SpotLight(
            position=(-1.5, 1.5, 2.5), direction=(0.5, -0.5, -1.0), cutoff=25.0, exponent=6.0,
            ambient=(0.05, 0.0, 0.0, 1), diffuse=(0.5, 0.2, 0.2, 1), specular=(0.5, 0.3, 0.3, 1), attenuation=(0.6, 0.1, 0.0),
        ),
    )


def material(texture: Texture | None = None, mode: str = "modulate", **overrides) -> Material:
    settings = dict(
        ambient=(0.25, 0.2, 0.15, 1), diffuse=(0.7, 0.6, 0.5, 0.9), specular=(0.5, 0.5, 0.5, 1),
        emission=(0.03, 0.02, 0.05, 1), shininess=24.0, texture=texture, texture_mode=mode,
    )
    settings.update(overrides)
    return Material(**settings)


def same_mesh_scene(configuration: str, frequency: str) -> Scene:
    texture = smooth_texture()
    if configuration == "three-light-kinds":
        objects = (
            SceneObject(uv_sphere(0.6, 24, 12), material(), translate=(-0.55, 0.35, 0)),
            SceneObject(cube(0.8), material(shininess=60.0), rotate=(30, 40, 0), translate=(0.6, 0.4, -0.3)),
            SceneObject(torus(0.5, 0.18, 24, 12), material(ambient=(0.1, 0.2, 0.25, 1)), rotate=(60, 0, 20), translate=(0.0, -0.55, 0.2)),
        )
        shading = Shading(frequency=frequency, reflection="phong", local_viewer=True)
    elif configuration == "blinn-infinite-modulate":
        objects = (
            SceneObject(cube(1.1), material(texture, "modulate"), rotate=(30, 40, 0), translate=(-0.5, 0.1, 0)),
            SceneObject(uv_sphere(0.5, 20, 10), material(shininess=40.0), translate=(0.7, -0.3, 0.2)),
        )
        shading = Shading(frequency=frequency, reflection="blinn-phong", blinn_exponent_scale=3.0, local_viewer=False)
    elif configuration == "two-sided-modulate_all":
        objects = (
            # The plane's back faces the camera: lit with −N only because the scene is two-sided.
            SceneObject(plane(1.4, 3), material(texture, "modulate_all", specular=(0.2, 0.2, 0.2, 1)), rotate=(10, 160, 0), translate=(-0.5, 0.2, 0)),
            # Mirrored: the winding flips on screen, the normals stay outward.
            SceneObject(uv_sphere(0.5, 20, 10), material(), scale=(-1.0, 1.0, 1.0), translate=(0.65, 0.3, 0.1)),
            SceneObject(torus(0.45, 0.15, 20, 10), material(), rotate=(70, 0, 0), scale=(1.0, -1.0, 1.0), translate=(0.4, -0.6, 0)),
        )
        shading = Shading(frequency=frequency, reflection="phong", local_viewer=True, two_sided=True)
    elif configuration == "blend-spot-attenuation":
        objects = (
            SceneObject(plane(1.6, 2), material(texture, "blend"), rotate=(-55, 20, 0), translate=(0, -0.3, -0.2)),
            SceneObject(cube(0.7), material(texture, "modulate", specular=(0.3, 0.3, 0.3, 1)), rotate=(40, -35, 5), translate=(0.45, 0.45, 0.2)),
        )
        shading = Shading(frequency=frequency, reflection="blinn-phong", blinn_exponent_scale=1.0, local_viewer=True)
    elif configuration == "hard-cases":
        return hard_cases_scene(frequency)
    else:  # pragma: no cover
        raise ValueError(configuration)
    return Scene(
        objects=objects, lights=lights_of_every_kind(), shading=shading, ambient=(0.15, 0.15, 0.2, 1),
        camera=Camera(eye=(0.2, 0.3, 3.2), target=(0, 0, 0)), size=(112, 96), background=(0.1, 0.1, 0.1, 1),
    )


def hard_cases_scene(frequency: str) -> Scene:
    """The hard cases of docs/hard-cases.md, all far from the world origin (1e5): a non-uniform scale (the normal
    matrix must be the inverse transpose), shininess 0 (x^0 = 1) and 1e4, a 90° spot with
    exponent 0, a pure inverse-square light close to a surface, Blinn-Phong with k_blinn 0.5."""
    far = np.array([1e5, -2e5, 5e4])
    at = lambda *p: tuple(far + np.array(p, dtype=float))
    objects = (
        SceneObject(uv_sphere(0.5, 24, 12), material(shininess=0.0, specular=(0.2, 0.2, 0.2, 1)), scale=(1.4, 0.6, 0.9), rotate=(0, 0, 30), translate=at(-0.55, 0.3, 0)),
        SceneObject(torus(0.45, 0.18, 32, 16), material(shininess=1e4, specular=(1, 1, 1, 1)), rotate=(50, 10, 0), translate=at(0.6, 0.25, 0)),
        SceneObject(cube(0.6), material(), scale=(1.5, 0.5, 1.0), rotate=(20, 30, 0), translate=at(0.0, -0.6, 0.1)),
    )
    lights = (
        DirectionalLight(direction=(-0.3, -1.0, -0.5), diffuse=(0.3, 0.3, 0.3, 1), specular=(0.5, 0.5, 0.5, 1)),
        SpotLight(position=at(0, 0, 3), direction=(0, 0, -1), cutoff=90.0, exponent=0.0, diffuse=(0.3, 0.25, 0.2, 1), specular=(0.4, 0.4, 0.4, 1)),
        PositionalLight(position=at(0.6, 0.9, 0.4), attenuation=(0.0, 0.0, 1.0), diffuse=(0.15, 0.15, 0.2, 1), specular=(0.3, 0.3, 0.3, 1)),
    )
    return Scene(
        objects=objects, lights=lights, ambient=(0.1, 0.1, 0.1, 1), size=(112, 96), background=(0.1, 0.1, 0.1, 1),
        camera=Camera(eye=at(0.2, 0.4, 3.0), target=at(0, 0, 0), near=0.01, far=1e3),
        shading=Shading(frequency=frequency, reflection="blinn-phong", blinn_exponent_scale=0.5, local_viewer=True),
    )


CONFIGURATIONS = ["three-light-kinds", "blinn-infinite-modulate", "two-sided-modulate_all", "blend-spot-attenuation", "hard-cases"]


# --------------------------------------------------------------------------- exact answers


@pytest.mark.parametrize("local_viewer", [True, False], ids=["local-viewer", "infinite-viewer"])
@pytest.mark.parametrize("reflection", ["phong", "blinn-phong"])
def test_phong_shading_of_a_plane_matches_the_exact_answer(renderer, reflection, local_viewer):
    """A plane facing the camera, a positional light with attenuation (and its highlight in view)."""
    surface = material(emission=(0, 0, 0, 1), shininess=20.0, specular=(0.8, 0.8, 0.8, 1))
    scene = Scene(
        objects=(SceneObject(plane(2.0), surface),),
        lights=(PositionalLight(position=(0.4, 0.3, 1.2), diffuse=(0.9, 0.9, 0.9, 1), specular=(1, 1, 1, 1), attenuation=(1.0, 0.3, 0.1)),),
        shading=Shading(frequency="phong", reflection=reflection, local_viewer=local_viewer, blinn_exponent_scale=2.0),
        camera=Camera(eye=(0, 0, 2.5)), size=(96, 96),
    )
    exact = ref.render_analytic_rectangle(scene, (0, 0, 0), (1, 0, 0), (0, 1, 0), surface)
    assert exact.color[exact.covered, :3].max() > 0.9, "the highlight should be in view"
    gpu = renderer.render_frame(scene, float32=True, depth=True)
    max_error, _ = compare(gpu, exact, SILHOUETTE_BAND, f"plane {reflection}")
    assert max_error < 0.1 / 255


@pytest.mark.parametrize("local_viewer", [True, False], ids=["local-viewer", "infinite-viewer"])
@pytest.mark.parametrize("reflection", ["phong", "blinn-phong"])
def test_phong_shading_of_a_sphere_matches_the_exact_answer(renderer, reflection, local_viewer):
    """A finely tessellated sphere against the ray-cast exact sphere: as the tessellation is
    refined, Phong shading converges to the lighting equation evaluated at the exact surface."""
    surface = material(shininess=50.0, specular=(0.8, 0.8, 0.8, 1))
    obj = SceneObject(sphere_for_triangles(100_000), surface, rotate=(20, 30, 0), translate=(0.1, -0.1, 0), scale=(0.9, 0.9, 0.9))
    scene = Scene(
        objects=(obj,), lights=lights_of_every_kind(), size=(128, 128),
        shading=Shading(frequency="phong", reflection=reflection, local_viewer=local_viewer, blinn_exponent_scale=3.0),
    )
    center, radius = ref.sphere_in_world(obj)
    exact = ref.render_analytic_sphere(scene, center, radius, surface)
    assert exact.color[exact.covered, :3].max() > 0.9, "a highlight should be in view"
    gpu = renderer.render_frame(scene, float32=True, depth=True)
    # 100k triangles: the flat facets lie within r·(1 − cos(h/2)) ≈ 1e-4·r of the sphere.
    compare(gpu, exact, SILHOUETTE_BAND, f"sphere {reflection}", depth_tolerance=5e-4)


# --------------------------------------------------------------------------- same mesh


@pytest.mark.parametrize("configuration", CONFIGURATIONS)
@pytest.mark.parametrize("frequency", ["flat", "gouraud", "phong"])
def test_gpu_matches_the_same_mesh_reference(renderer, frequency, configuration):
    scene = same_mesh_scene(configuration, frequency)
    reference = ref.render_reference(scene)
    gpu = renderer.render_frame(scene, float32=True, depth=True)
    compare(gpu, reference, EDGE_BAND, f"{frequency} / {configuration}")


# --------------------------------------------------------------------------- rasterization rules

SIZE = 16
PIXEL_CAMERA = Camera(eye=(0, 0, 1), target=(0, 0, 0), fov_y=90.0)  # world (x, y, 0) → NDC (x, y)
COLORS = [(1, 0, 0, 1), (0, 1, 0, 1), (0, 0, 1, 1), (1, 1, 0, 1)]


def window_triangle(corners, index: int) -> SceneObject:
    """A triangle given in window coordinates (pixels, y down), glowing in its own color."""
    positions = np.array([(2.0 * x / SIZE - 1.0, 1.0 - 2.0 * y / SIZE, 0.0) for x, y in corners])
    glow = Material(ambient=(0, 0, 0, 1), diffuse=(0, 0, 0, 1), emission=COLORS[index])
    return SceneObject(Mesh.from_arrays(positions, np.array([[0, 1, 2]])), glow)


def object_ids(renderer, triangles) -> tuple[np.ndarray, np.ndarray]:
    scene = Scene(
        objects=tuple(window_triangle(t, k) for k, t in enumerate(triangles)), lights=(), ambient=(0, 0, 0, 1),
        camera=PIXEL_CAMERA, size=(SIZE, SIZE), shading=Shading(frequency="flat"),
    )
    image = renderer.render(scene, float32=True)
    gpu = np.full((SIZE, SIZE), -1)
    for k in range(len(triangles)):
        gpu[np.all(np.abs(image - np.asarray(COLORS[k])) < 1e-6, axis=-1)] = k
    return gpu, ref.render_reference(scene).object


@pytest.mark.parametrize(
    "triangles",
    [
        # Edges through pixel centres: vertical, horizontal, diagonal, in both windings.
        [[(1, 2.5), (5.5, 2.5), (5.5, 10.5)], [(5.5, 2.5), (9, 10.5), (5.5, 10.5)]],
        [[(2.5, 2), (12.5, 7.5), (2.5, 7.5)], [(2.5, 7.5), (12.5, 7.5), (7.5, 13)]],
        [[(2.5, 12.5), (12.5, 12.5), (12.5, 2.5)], [(2.5, 12.5), (12.5, 2.5), (2.5, 2.5)]],
        [[(2.5, 12.5), (12.5, 2.5), (12.5, 12.5)], [(2.5, 12.5), (2.5, 2.5), (12.5, 2.5)]],
        # Edges 1/512 pixel off a centre (ties of the 1/256 snapping round to even) and 3/512.
        [[(1, 2), (5.5 + 1 / 512, 2), (5.5 + 1 / 512, 10)], [(5.5 + 1 / 512, 2), (9, 10), (5.5 + 1 / 512, 10)]],
        [[(1, 2), (5.5 + 3 / 512, 2), (5.5 + 3 / 512, 10)], [(5.5 + 3 / 512, 2), (9, 10), (5.5 + 3 / 512, 10)]],
        [[(1, 2), (5.5 - 3 / 512, 2), (5.5 - 3 / 512, 10)], [(5.5 - 3 / 512, 2), (9, 10), (5.5 - 3 / 512, 10)]],
    ],
    ids=["vertical", "horizontal", "diagonal", "diagonal-other-winding", "tie+1/512", "tie+3/512", "tie-3/512"],
)
def test_gpu_coverage_follows_the_top_left_rule_and_snapping(renderer, triangles):
    """Pixel centres exactly on edges: the GPU and the reference give every pixel to the same triangle."""
    gpu, reference = object_ids(renderer, triangles)
    assert (reference >= 0).sum() > 20
    np.testing.assert_array_equal(gpu, reference)
