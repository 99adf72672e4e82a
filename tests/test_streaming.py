"""Long sequences are streamed: turntable views are made as they are used, and GIF frames
are written to the file as they come, not held until the end."""

from __future__ import annotations

import itertools
import sys
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

    def written(larger_than: int) -> int:
        """The temporary's size once it exceeds `larger_than` (waits for the encoder thread,
        which a loaded machine may run late; a writer holding frames until the end never gets there)."""
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            for temporary in tmp_path.glob(".spin.gif.wgpu-shading-tmp-*.gif"):
                if (size := temporary.stat().st_size) > larger_than:
                    return size
            time.sleep(0.01)
        raise AssertionError(f"the GIF did not grow past {larger_than} bytes while frames were still coming")

    def frames():
        views = turntable(small_scene, 100_000_000)
        for index, frame in enumerate(renderer.render_many(itertools.islice(iter(views), 8), parallel=1)):
            assert not path.exists()
            if index in (2, 5):  # frames 0..index-1 are with the encoder by now
                sizes.append(written(sizes[-1] if sizes else 0))
            rendered.append(frame.color)
            yield frame.color

    assert write_animation(path, frames(), fps=20) == 8
    assert len(sizes) == 2 and sizes[1] > sizes[0] > 0  # the file grew while frames were still coming
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


# --------------------------------------------------------------------------- GIF colours


def _gif_frames(path) -> list[np.ndarray]:
    with Image.open(path) as gif:
        return [np.array(frame.convert("RGB")).astype(int) for frame in ImageSequence.Iterator(gif)]


def _gradient(phase: int) -> np.ndarray:
    """A closed-form smooth frame with 49,152 colours (more than a GIF palette holds)."""
    y, x = np.mgrid[0:192, 0:256]
    return np.stack([x, (y * 4 // 3 + phase) % 256, (x + y) // 2], axis=2).astype(np.uint8)


def test_gif_gradients_show_no_contour_rings(tmp_path):
    """A GIF frame holds 256 colours; a smooth gradient must not turn into bands. Measured
    against the frames themselves after a 5 × 5 blur (what the eye sees from a normal distance:
    dither noise averages out, bands stay). This gradient spans most of the colour cube
    (49,152 colours), so even the best palette leaves some error; without dithering it bands
    (7–8/255 after the blur; 22/255 with the fast octree palette of before), with it ≤ 3.5/255."""
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the repository's benchmarks/
    from benchmarks.gif_palette import box_blur

    frames = [_gradient(phase) for phase in (0, 40)]
    path = tmp_path / "gradient.gif"
    assert write_animation(path, iter(frames), fps=10) == 2
    for frame, decoded in zip(frames, _gif_frames(path)):
        banding = np.percentile(np.abs(box_blur(decoded) - box_blur(frame)), 99)
        assert banding <= 3.5 and np.abs(decoded - frame).mean() < 6.0, banding
        undithered = np.array(Image.fromarray(frame).quantize(256, method=Image.Quantize.MAXCOVERAGE).convert("RGB")).astype(int)
        assert np.percentile(np.abs(box_blur(undithered) - box_blur(frame)), 99) > 2 * banding


def test_gif_of_few_colours_is_exact_and_smooth_shading_within_two_levels(tmp_path, renderer, small_scene):
    rng = np.random.default_rng(3)
    palette = rng.integers(0, 256, (256, 3), dtype=np.uint8)
    few = palette[rng.integers(0, 256, (40, 50))]
    assert write_animation(tmp_path / "few.gif", [few, few[::-1]], fps=10) == 2
    assert [np.array_equal(d, f) for d, f in zip(_gif_frames(tmp_path / "few.gif"), [few, few[::-1]])] == [True, True]
    # A rendered torus of one material: hundreds of colours, each within 2/255 and no dither noise.
    from dataclasses import replace

    frame = renderer.render(replace(small_scene, size=(160, 128)))[:, :, :3]
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 256
    write_animation(tmp_path / "torus.gif", [frame], fps=10)
    assert np.abs(_gif_frames(tmp_path / "torus.gif")[0] - frame).max() <= 2
