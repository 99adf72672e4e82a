"""Long sequences are streamed: turntable views are made as they are used, and GIF frames
are written to the file as they come, not held until the end."""

from __future__ import annotations

import itertools
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image, ImageSequence

from wgpu_shading import SceneError, load_scene
from wgpu_shading.assets.animation import write_animation
from wgpu_shading.scene.view.turntable import spun, turntable

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture(scope="module")
def small_scene():
    from dataclasses import replace

    return replace(load_scene(EXAMPLES / "gold_torus_phong.toml"), size=(40, 32))


def test_a_hundred_million_frame_turntable_costs_nothing_up_front(small_scene):
    start = time.perf_counter()
    views = turntable(small_scene, 100_000_000)
    assert time.perf_counter() - start < 0.05
    assert len(views) == 100_000_000
    middle = views[50_000_000]
    expected = spun(small_scene, 180.0)
    np.testing.assert_allclose(middle.camera.eye, expected.camera.eye, atol=1e-12)
    assert views[-1].camera.eye == views[99_999_999].camera.eye
    with pytest.raises(IndexError):
        views[100_000_000]


def test_turntable_degrees_and_frames_are_checked(small_scene):
    with pytest.raises(SceneError, match="degrees must be a finite number, got inf"):
        turntable(small_scene, 4, float("inf"))
    with pytest.raises(SceneError, match="frames must be at least 1, got 2.5"):
        turntable(small_scene, 2.5)


def test_gif_frames_are_on_disk_before_the_sequence_ends(tmp_path, renderer, small_scene):
    """The first frames of a (practically endless) turntable reach the disk while rendering
    goes on (in the temporary file beside the output, renamed at the end: the output name
    itself never holds a partial GIF); 8 frames of 100,000,000 are taken and the file holds
    exactly those."""
    path = tmp_path / "spin.gif"
    sizes: list[int] = []
    rendered: list[np.ndarray] = []

    def frames():
        views = turntable(small_scene, 100_000_000)
        for frame in renderer.render_many(itertools.islice(iter(views), 8), parallel=1):
            assert not path.exists()
            temporaries = list(tmp_path.glob(".spin.gif.wgpu-shading-tmp-*.gif"))
            if temporaries:
                sizes.append(temporaries[0].stat().st_size)
            rendered.append(frame.color)
            yield frame.color

    assert write_animation(path, frames(), fps=20) == 8
    grown = [size for size in sizes if size > 0]  # (the first look may come before the header is written)
    assert len(grown) >= 2 and grown[-1] > grown[0]  # the file grew while frames were still coming
    assert [p.name for p in tmp_path.iterdir()] == ["spin.gif"]
    with Image.open(path) as gif:
        assert gif.n_frames == 8 and gif.info["loop"] == 0 and gif.info["duration"] == 50
        read = [np.array(frame.convert("RGB")) for frame in ImageSequence.Iterator(gif)]
    for original, decoded in zip(rendered, read):
        # per-frame adaptive palette: within a few levels, everywhere
        assert np.abs(original[:, :, :3].astype(int) - decoded).max() <= 24
        assert np.abs(original[:, :, :3].astype(int) - decoded).mean() < 2.0
    assert (read[0].max(axis=2) > 40).mean() > 0.1  # the torus is there, not a blank frame


def test_a_failed_animation_leaves_no_half_written_file(tmp_path):
    path = tmp_path / "broken.gif"

    def frames():
        yield np.zeros((8, 8, 4), np.uint8)
        raise RuntimeError("renderer failed")

    with pytest.raises(RuntimeError, match="renderer failed"):
        write_animation(path, frames())
    assert not path.exists()
