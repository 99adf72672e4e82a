"""Many frames: render_many, the turntable, animation files and `wgpu-shading turntable`."""

from __future__ import annotations

import os
import sys
from dataclasses import replace

import imageio.v3 as iio
import numpy as np
import pytest

from wgpu_shading import Camera, PositionalLight, Renderer, Scene, SceneObject, SpotLight, DirectionalLight, load_mesh, material
from wgpu_shading.assets.animation import write_animation
from wgpu_shading.render.frames_in_flight import default_parallelism
from wgpu_shading.scene.view.turntable import spun, turntable
from wgpu_shading.cli import main

from test_cli import run_cli


@pytest.fixture(scope="module")
def torus_scene() -> Scene:
    """The classic gold torus set-up, small: camera target = torus centre, so spinning about the
    camera's up axis equals turning the torus about world Y."""
    return Scene(
        objects=(
            SceneObject(load_mesh("builtin:torus?segments=24"), material("gold"), translate=(0, 0, -1), rotate=(35, 0, 0)),
        ),
        lights=(PositionalLight(position=(5, 2, 2)),),
        camera=Camera(eye=(0, 0, 1), target=(0, 0, -1), fov_y=60, near=0.1, far=100),
        ambient=(0.7, 0.7, 0.7, 1.0),
        size=(80, 64),
    )


@pytest.mark.parametrize("in_flight, parallel", [(1, 1), (2, 1), (3, 1), (1, 2), (2, 2), (2, 3), (2, None)])
def test_render_many_equals_single_renders(renderer, torus_scene, in_flight, parallel):
    scenes = turntable(torus_scene, 7)
    expected = [renderer.render(scene) for scene in scenes]
    frames = list(renderer.render_many(scenes, in_flight=in_flight, parallel=parallel))
    assert len(frames) == len(scenes)
    for frame, image in zip(frames, expected):
        np.testing.assert_array_equal(frame.color, image)  # pixel-exact: same pipeline, same uniforms


def test_render_many_float_depth_and_mixed_sizes(renderer, torus_scene):
    scenes = [torus_scene, replace(spun(torus_scene, 40), size=(33, 47)), spun(torus_scene, 80), replace(torus_scene, size=(33, 47))]
    frames = list(renderer.render_many(iter(scenes), float32=True, depth=True))  # a plain iterator is enough
    for frame, scene in zip(frames, scenes):
        single = renderer.render_frame(scene, float32=True, depth=True)
        assert frame.color.shape == (scene.size[1], scene.size[0], 4) and frame.color.dtype == np.float32
        np.testing.assert_array_equal(frame.color, single.color)
        np.testing.assert_array_equal(frame.depth, single.depth)


@pytest.mark.parametrize("parallel", [1, 2])
def test_render_many_is_lazy(renderer, torus_scene, parallel):
    consumed = []

    def scenes():
        for index in range(10):
            consumed.append(index)
            yield spun(torus_scene, 10 * index)

    stream = renderer.render_many(scenes(), in_flight=2, parallel=parallel)
    next(stream)
    assert len(consumed) <= 2 * parallel + 1  # at most in_flight per device, + 1, before the first frame
    assert len(list(stream)) == 9


def test_render_many_rejects_bad_in_flight_and_parallel(renderer, torus_scene):
    with pytest.raises(ValueError, match="in_flight"):
        list(renderer.render_many([torus_scene], in_flight=0))
    with pytest.raises(ValueError, match="parallel"):
        list(renderer.render_many([torus_scene], parallel=0))


def test_lavapipe_batches_use_two_devices(renderer, torus_scene):
    assert default_parallelism(renderer) == (2 if (os.cpu_count() or 1) >= 2 else 1)
    list(renderer.render_many(turntable(torus_scene, 4), parallel=2))
    helper = renderer.parallel_renderers(2)[1]
    assert helper.device is not renderer.device and helper.pipeline_count >= 1  # it really drew
    list(renderer.render_many(turntable(torus_scene, 4), parallel=2))
    assert renderer.parallel_renderers(2)[1] is helper  # made once, then reused


def test_spinning_the_view_equals_turning_the_object(renderer, torus_scene):
    (obj,) = torus_scene.objects
    for degrees in (30.0, 135.0):
        turned_object = replace(torus_scene, objects=(replace(obj, rotate=(35, degrees, 0)),))
        a = renderer.render(spun(torus_scene, degrees)).astype(int)
        b = renderer.render(turned_object).astype(int)
        difference = np.abs(a - b).max(axis=2)
        assert (difference > 1).mean() < 0.005, degrees  # float rounding moves a few edge pixels only
        assert np.median(difference[(a[:, :, :3] > 0).any(axis=2)]) <= 1


def test_turntable_steps_and_every_light_kind(torus_scene):
    scene = replace(
        torus_scene,
        lights=(
            PositionalLight(position=(5, 2, 2)),
            DirectionalLight(direction=(0, 0, -1)),
            SpotLight(position=(0, 3, -1), direction=(0, -1, 0)),
        ),
    )
    views = turntable(scene, 4)
    assert len(views) == 4 and views[0] is scene
    quarter = views[1]  # the scene turns +90° about +Y (its front moves to +x): the viewer orbits by −90°
    np.testing.assert_allclose(quarter.camera.eye, (-2.0, 0.0, -1.0), atol=1e-12)
    np.testing.assert_allclose(quarter.lights[0].position, (-3.0, 2.0, 4.0), atol=1e-12)
    np.testing.assert_allclose(quarter.lights[1].direction, (1.0, 0.0, 0.0), atol=1e-12)
    np.testing.assert_allclose(quarter.lights[2].position, (0.0, 3.0, -1.0), atol=1e-12)  # on the axis
    np.testing.assert_allclose(quarter.lights[2].direction, (0.0, -1.0, 0.0), atol=1e-12)
    np.testing.assert_allclose(spun(scene, 360).camera.eye, scene.camera.eye, atol=1e-12)
    with pytest.raises(Exception, match="frames must be at least 1"):
        turntable(scene, 0)


def test_write_gif_has_the_frames_and_size(tmp_path):
    frames = [np.full((24, 40, 4), (i * 20, 100, 200 - i * 20, 255), np.uint8) for i in range(6)]
    path = tmp_path / "a.gif"
    assert write_animation(path, iter(frames), fps=12) == 6
    read = list(iio.imiter(path))
    assert len(read) == 6 and read[0].shape[:2] == (24, 40)
    np.testing.assert_allclose(read[3][0, 0, :3], (60, 100, 140), atol=2)  # one flat color survives the palette


def test_write_mp4_has_the_frames_and_size(tmp_path):
    pytest.importorskip("imageio_ffmpeg")
    frames = [np.full((32, 48, 4), (i * 20, 100, 50, 255), np.uint8) for i in range(5)]
    path = tmp_path / "a.mp4"
    assert write_animation(path, frames, fps=10) == 5
    read = list(iio.imiter(path, plugin="FFMPEG"))
    assert len(read) == 5 and read[0].shape[:2] == (32, 48)


def test_cli_turntable_writes_a_gif(tmp_path, capsys, renderer):
    out = tmp_path / "spin.gif"
    assert main(["turntable", "builtin:torus?segments=16", "--size", "48x40", "--frames", "5", "-o", str(out)]) == 0
    assert "5 frames" in capsys.readouterr().out
    read = list(iio.imiter(out))
    assert len(read) == 5 and read[0].shape[:2] == (40, 48)
    assert not np.array_equal(read[1], read[2])  # it turns


def test_cli_turntable_from_a_new_process(tmp_path):
    out = tmp_path / "spin.gif"
    result = run_cli("turntable", "builtin:cube", "--size", "32", "--frames", "3", "--degrees", "90", "-o", str(out), "-q")
    assert result.returncode == 0, result.stderr
    assert result.stdout == "" and len(list(iio.imiter(out))) == 3


@pytest.mark.parametrize(
    "args, message",
    [
        (["-o", "spin.png"], "unsupported format; use one of .gif, .mp4"),
        (["-o", "/nonexistent/dir/spin.gif"], "folder '/nonexistent/dir' does not exist"),
        (["--frames", "0"], "--frames must be at least 1"),
        (["--fps", "0"], "--fps must be between 0.01 and 1000 frames per second"),
        (["--material", "goldd"], "did you mean 'gold'"),
    ],
)
def test_cli_turntable_errors_are_one_line(args, message):
    result = run_cli("turntable", "builtin:torus", *args)
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0 and "Traceback" not in result.stderr, result.stderr
    assert result.stderr.startswith("wgpu-shading: error: ") and message in result.stderr


def test_cli_mp4_without_imageio_ffmpeg_is_a_one_line_error(monkeypatch, capsys, tmp_path):
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)  # as if not installed
    assert main(["turntable", "builtin:cube", "-o", str(tmp_path / "spin.mp4")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "needs imageio-ffmpeg" in err and "[video]" in err
    assert not (tmp_path / "spin.mp4").exists()


def test_uniform_writes_skipped_only_when_unchanged(torus_scene):
    """A renderer rewrites a uniform buffer only when its bytes change: alternating and
    repeated scenes on one renderer must match each scene rendered by a fresh renderer
    (its own buffers), and the two views must really differ (else the test proves nothing)."""
    other = spun(torus_scene, 90)
    expected = {id(torus_scene): Renderer().render(torus_scene), id(other): Renderer().render(other)}
    assert not np.array_equal(expected[id(torus_scene)], expected[id(other)])
    shared = Renderer()
    for scene in (torus_scene, torus_scene, other, torus_scene, other, other):
        np.testing.assert_array_equal(shared.render(scene), expected[id(scene)])
    frame = shared.render_frame(torus_scene, depth=True)  # the depth store is kept when depth is read
    drawn = np.isfinite(frame.depth)
    assert drawn.any() and (frame.depth[drawn] > 0.1).all() and (frame.depth[drawn] < 100).all()
