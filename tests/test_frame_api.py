"""The public frame API: Renderer.submit(scene, ...) -> PendingFrame, Renderer.read(pending)
-> Frame. Extra outputs (normals, ids) ride on the same path: the same targets, within the
same bound, and the same frames whether rendered alone, together or pipelined."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading import Camera, PositionalLight, Renderer, Scene, SceneObject, load_mesh, material
from wgpu_shading.errors import SceneError
from wgpu_shading.render.gpu.caches import TARGET_CACHE_ENTRIES


@pytest.fixture(scope="module")
def scene() -> Scene:
    return Scene(
        objects=(
            SceneObject(load_mesh("builtin:torus?segments=16"), material("gold"), rotate=(35, 0, 0)),
            SceneObject(load_mesh("builtin:cube"), material("silver"), translate=(0.0, 0.0, -2.0)),
        ),
        lights=(PositionalLight(position=(5, 2, 2)),),
        camera=Camera(eye=(0, 0, 3), fov_y=50),
        size=(40, 32),
    )


def test_submit_then_read_equals_render_frame(renderer, scene):
    pending = [renderer.submit(scene, depth=True), renderer.submit(replace(scene, size=(24, 24)))]
    frames = [renderer.read(p) for p in reversed(pending)]  # read in any order
    expected = renderer.render_frame(scene, depth=True)
    np.testing.assert_array_equal(frames[1].color, expected.color)
    np.testing.assert_array_equal(frames[1].depth, expected.depth)
    assert frames[0].color.shape == (24, 24, 4)


def test_the_frame_api_types_are_public_names_of_the_package(renderer, scene):
    """Type hints and isinstance checks need no render/ import path (issue 18)."""
    import wgpu_shading

    for name in ("Renderer", "PendingFrame", "Frame"):
        assert name in wgpu_shading.__all__ and name in dir(wgpu_shading)
    pending = renderer.submit(scene)
    assert isinstance(pending, wgpu_shading.PendingFrame)
    assert isinstance(renderer.read(pending), wgpu_shading.Frame)


def test_a_pending_frame_is_read_once(renderer, scene):
    pending = renderer.submit(scene)
    renderer.read(pending)
    with pytest.raises(ValueError, match="read already"):
        renderer.read(pending)


def test_normals_and_ids_cover_the_colour_image(renderer, scene):
    frame = renderer.render_frame(scene, depth=True, normals="world", ids=True)
    assert frame.ids.dtype == np.uint16 and set(np.unique(frame.ids)) == {0, 1, 2}
    assert np.array_equal(frame.ids > 0, np.isfinite(frame.depth))
    lengths = np.linalg.norm(frame.normals[frame.ids > 0], axis=1)
    np.testing.assert_allclose(lengths, 1.0, atol=1e-5)
    assert not frame.normals[frame.ids == 0].any()
    # The cube faces +z in world space where it is seen head-on, whatever the camera.
    cube_normals = frame.normals[frame.ids == 2]
    assert (np.abs(cube_normals - [0, 0, 1]).max(axis=1) < 1e-6).mean() > 0.9


def test_extra_outputs_alone_pipelined_or_with_colour_are_the_same(renderer, scene):
    scenes = [replace(scene, camera=replace(scene.camera, eye=(x, 0.0, 3.0))) for x in (-0.5, 0.0, 0.5)]
    alone = [renderer.render_frame(s, normals="eye", ids=True, color=False) for s in scenes]
    assert alone[0].color is None
    many = list(renderer.render_many(scenes, normals="eye", ids=True, parallel=2))
    for single, pipelined in zip(alone, many):
        np.testing.assert_array_equal(single.normals, pipelined.normals)
        np.testing.assert_array_equal(single.ids, pipelined.ids)
        assert pipelined.color is not None


def test_extra_outputs_keep_the_target_bound(scene):
    """Every new size leaves targets behind; idle ones are kept up to the bound."""
    fresh = Renderer()
    for width in range(8, 8 + 3 * TARGET_CACHE_ENTRIES):
        fresh.render_frame(replace(scene, size=(width, 8)), normals="eye", ids=True)
    assert fresh.device_cache.free_target_count == TARGET_CACHE_ENTRIES


def test_bad_requests_fail_before_any_work(renderer, scene):
    with pytest.raises(SceneError, match="expected eye or world"):
        renderer.submit(scene, normals="camera")
    with pytest.raises(SceneError, match="output.size"):
        renderer.check_size((10**6, 8))
