"""How many texels an "auto" shadow map gets (render/passes/shadow_resolution.py,
docs/shadows.md#auto): the study's 512, doubled until a texel is no wider than 1/16 of a
pixel on the visible receivers the map may shadow, up to 2048. Closed forms on a camera
and a light looking straight down, where a texel and a pixel have known widths. CPU only:
the hard case that needs it, sliver_shadow, is rendered by tests/test_shadows_gpu.py."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading.render.passes.shadow_resolution import auto_map_size, texels_per_pixel
from wgpu_shading.render.passes.shadow_views import fit_shadow_views
from wgpu_shading.render.passes.visible_regions import common_points
from wgpu_shading.scene import Camera, DirectionalLight, Scene, SceneObject, cube, plane
from wgpu_shading.scene.shadows import AUTO_MAP_SIZE, AUTO_MAP_SIZE_LIMIT, AUTO_TEXELS_PER_PIXEL

MARGIN = 1.0  # the nearest filter's reach + 1 (shadow.py)


def _from_above(pixels: int, view_height: float = 4.0) -> Scene:
    """A unit box 1 above a ground, a light and an orthographic camera straight down: the
    box's shadow is its 1 × 1 top, and a pixel is view_height / pixels wide."""
    return Scene(
        objects=(SceneObject(cube(1.0), translate=(0.0, 1.5, 0.0)), SceneObject(plane(12.0), rotate=(-90.0, 0.0, 0.0))),
        lights=(DirectionalLight(direction=(0.0, -1.0, 0.0), shadows=True),),
        camera=Camera(eye=(0.0, 10.0, 0.0), target=(0.0, 0.0, 0.0), up=(0.0, 0.0, -1.0), near=1.0, far=20.0,
                      projection="orthographic", ortho_height=view_height),
        size=(pixels, pixels),
    )


def test_a_texel_and_a_pixel_straight_down_have_their_closed_form_widths():
    scene = _from_above(200)
    shadows = fit_shadow_views(scene, AUTO_MAP_SIZE, MARGIN)
    texel = 1.0 * AUTO_MAP_SIZE / (AUTO_MAP_SIZE - 2.0 * MARGIN) / AUTO_MAP_SIZE  # the box's 1 unit, padded
    pixel = 4.0 / 200
    assert texels_per_pixel(scene, shadows, AUTO_MAP_SIZE) == pytest.approx(texel / pixel, rel=1e-6)


@pytest.mark.parametrize("pixels", [16, 64, 200, 400, 1000, 4000])
def test_auto_doubles_the_map_until_a_texel_is_a_sixteenth_of_a_pixel(pixels):
    scene = _from_above(pixels)
    ratio = 1.0 / (AUTO_MAP_SIZE - 2.0 * MARGIN) / (4.0 / pixels)  # texels per pixel at AUTO_MAP_SIZE
    expected = AUTO_MAP_SIZE
    while ratio * AUTO_MAP_SIZE / expected * AUTO_TEXELS_PER_PIXEL > 1.0 and expected < AUTO_MAP_SIZE_LIMIT:
        expected *= 2
    assert auto_map_size(scene, fit_shadow_views(scene, AUTO_MAP_SIZE, MARGIN)) == expected
    if pixels == 16:
        assert expected == AUTO_MAP_SIZE
    if pixels == 4000:
        assert expected == AUTO_MAP_SIZE_LIMIT


def test_a_receiver_outside_every_window_asks_for_nothing():
    """Only the receivers a map may shadow count: a far corner of the ground does not."""
    scene = _from_above(200)
    narrow = replace(scene, camera=replace(scene.camera, eye=(5.0, 10.0, 5.0), target=(5.0, 0.0, 5.0), ortho_height=1.0))
    assert texels_per_pixel(narrow, fit_shadow_views(narrow, AUTO_MAP_SIZE, MARGIN), AUTO_MAP_SIZE) == 0.0


def test_the_common_points_of_two_unit_boxes_are_their_overlap():
    def box(lower):
        return np.array([[x, y, z] for x in (lower[0], lower[0] + 1) for y in (lower[1], lower[1] + 1) for z in (lower[2], lower[2] + 1)], float)

    points = common_points(box((0.0, 0.0, 0.0)), box((0.5, 0.25, -0.5)))
    np.testing.assert_allclose(points.min(axis=0), (0.5, 0.25, 0.0), atol=1e-8)  # the planes lean 1e-9 of the size outwards
    np.testing.assert_allclose(points.max(axis=0), (1.0, 1.0, 0.5), atol=1e-8)  # the planes lean 1e-9 of the size outwards
    assert len(common_points(box((0.0, 0.0, 0.0)), box((2.0, 0.0, 0.0)))) == 0
