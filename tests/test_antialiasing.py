"""Antialiasing (`[output] samples = 1 | 4`, MSAA: docs/conventions.md#projection-pixels-and-depth) and the background's alpha.

The expected values come from the standard 4-sample pattern every Vulkan/WebGPU
implementation uses for 4× MSAA: sample offsets (0.375, 0.125), (0.875, 0.375),
(0.125, 0.625), (0.625, 0.875) within the pixel. An orthographic camera with one world
unit per pixel puts a square's edges at known sub-pixel positions, so the resolved edge
pixels must hold exactly the covered share of the samples."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wgpu_shading import Camera, Material, Scene, SceneObject, load_mesh
from wgpu_shading.assets import parse_scene
from wgpu_shading.cli import main
from wgpu_shading.errors import SceneError

SAMPLE_OFFSETS = np.array([(0.375, 0.125), (0.875, 0.375), (0.125, 0.625), (0.625, 0.875)])
GLOW = Material(ambient=(0, 0, 0, 1), diffuse=(0, 0, 0, 1), specular=(0, 0, 0, 1), emission=(1, 1, 1, 1))


def _square_scene(samples: int) -> Scene:
    # 64×64 pixels, 64 world units tall: pixel column c covers world x in [c − 32, c − 31].
    # The 20.5-unit square spans x and y in [−10.25, 10.25]: edges a quarter into a pixel.
    return Scene(
        objects=(SceneObject(load_mesh("builtin:plane?size=20.5"), GLOW),),
        camera=Camera(eye=(0.0, 0.0, 5.0), projection="orthographic", ortho_height=64.0),
        size=(64, 64),
        samples=samples,
    )


def test_default_is_one_sample_and_hard_edges(renderer):
    assert Scene().samples == 1
    image = renderer.render(_square_scene(1))
    assert set(np.unique(image[:, :, 0])) == {0, 255}


def test_four_samples_resolve_to_the_covered_share(renderer):
    image = renderer.render(_square_scene(4))[:, :, 0].astype(int)
    # Right edge at x = 42.25 (column 42): samples with x offset < 0.25 are inside: one of four.
    right = np.mean(SAMPLE_OFFSETS[:, 0] < 0.25)
    left = np.mean(SAMPLE_OFFSETS[:, 0] > 0.75)  # left edge at x = 21.75 (column 21)
    assert right == left == 0.25
    assert np.all(np.abs(image[25:39, 42] - 255 * right) <= 1)
    assert np.all(np.abs(image[25:39, 21] - 255 * left) <= 1)
    # Rows: the top edge at y = 10.25 is 21.75 pixels from the top (row 21), y offsets > 0.75.
    assert np.all(np.abs(image[21, 25:39] - 255 * np.mean(SAMPLE_OFFSETS[:, 1] > 0.75)) <= 1)
    assert np.all(image[22:42, 22:42] == 255) and np.all(image[:20] == 0) and np.all(image[:, 44:] == 0)
    # The same everywhere else as without antialiasing.
    hard = renderer.render(_square_scene(1))[:, :, 0].astype(int)
    edges = np.zeros_like(hard, dtype=bool)
    edges[21:43, [21, 42]] = edges[[21, 42], 21:43] = True
    assert np.array_equal(image[~edges], hard[~edges])


def test_depth_with_antialiasing_is_the_pixel_centre_depth(renderer):
    multi = renderer.render_frame(_square_scene(4), depth=True)
    single = renderer.render_frame(_square_scene(1), depth=True)
    assert np.array_equal(multi.depth, single.depth)
    assert np.array_equal(multi.color, renderer.render(_square_scene(4)))


def test_render_many_antialiases_like_render_frame(renderer):
    scenes = [_square_scene(4), _square_scene(1), _square_scene(4)]
    for scene, frame in zip(scenes, renderer.render_many(scenes)):
        assert np.array_equal(frame.color, renderer.render(scene))


def test_samples_must_be_1_or_4():
    with pytest.raises(SceneError, match="output.samples: expected 1"):
        Scene(samples=2)
    with pytest.raises(SceneError, match="output.samples: expected 1"):
        parse_scene({"output": {"samples": 8}})
    assert parse_scene({"output": {"samples": 4}}).samples == 4


def test_float_target_refuses_antialiasing(renderer):
    with pytest.raises(SceneError, match="8-bit target"):
        renderer.render(_square_scene(4), float32=True)


def test_transparent_background(tmp_path, renderer):
    scene = parse_scene({"output": {"transparent": True, "background": [0.2, 0.3, 0.4]}})
    assert scene.background == (0.2, 0.3, 0.4, 0.0)
    image = renderer.render(replace(_square_scene(4), background=scene.background))
    assert image[0, 0, 3] == 0 and image[32, 32, 3] == 255 and tuple(image[0, 0, :3]) == (51, 76, 102)
    assert abs(int(image[30, 42, 3]) - 64) <= 1  # the edge is partly transparent
    out = tmp_path / "t.png"
    assert main(["render", "builtin:torus", "--size", "32", "--no-background", "-q", "-o", str(out)]) == 0
    from PIL import Image

    written = np.asarray(Image.open(out))
    assert written.shape[2] == 4 and written[0, 0, 3] == 0 and written[16, 16, 3] == 255 and (written[:, :, 3] == 0).mean() > 0.3


def test_background_color_flag(tmp_path):
    out = tmp_path / "b.png"
    assert main(["render", "builtin:torus", "--size", "32", "--background-color", "1,0.5,0", "-q", "-o", str(out)]) == 0
    from PIL import Image

    assert tuple(np.asarray(Image.open(out))[0, 0]) == (255, 128, 0, 255)
