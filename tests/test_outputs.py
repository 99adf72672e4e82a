"""Outputs (issue 13): `-o -` to a pipe, depth files by extension, every output path checked
before any work, Jupyter's PNG of a Frame."""

from __future__ import annotations

import io
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from cli_errors import one_line_error, run_cli
from wgpu_shading.assets.image_writers import read_depth_png
from wgpu_shading.assets.mesh_scene import mesh_scene
from wgpu_shading.cli import main

BIN = Path(sys.executable).parent


def test_output_dash_writes_png_to_stdout_and_reports_on_stderr(tmp_path):
    result = subprocess.run(
        [str(BIN / "wgpu-shading"), "render", "builtin:torus", "--size", "48x32", "-o", "-"],
        capture_output=True, cwd=tmp_path, timeout=120,
    )
    assert result.returncode == 0, result.stderr
    image = np.asarray(Image.open(io.BytesIO(result.stdout)))
    assert image.shape == (32, 48, 4) and image[:, :, 0].max() > 100
    assert b"wrote standard output" in result.stderr and list(tmp_path.iterdir()) == []
    expected = tmp_path / "t.png"
    assert main(["render", "builtin:torus", "--size", "48x32", "-q", "-o", str(expected)]) == 0
    assert np.array_equal(image, np.asarray(Image.open(expected)))


def test_depth_by_extension(tmp_path, renderer):
    scene = mesh_scene("builtin:torus", (48, 32), None)
    exact = renderer.render_frame(scene, depth=True).depth
    paths = {suffix: tmp_path / f"d{suffix}" for suffix in (".npy", ".tiff", ".png")}
    for path in paths.values():
        assert main(["render", "builtin:torus", "--size", "48x32", "-q", "-o", str(tmp_path / "c.png"), "--depth", str(path)]) == 0
    as_npy = np.load(paths[".npy"])
    assert as_npy.dtype == np.float32 and np.array_equal(as_npy, exact.astype(np.float32))
    as_tiff = np.asarray(Image.open(paths[".tiff"]))
    assert as_tiff.dtype == np.float32 and np.array_equal(as_tiff, as_npy)
    png = Image.open(paths[".png"])
    near, far = float(png.text["near"]), float(png.text["far"])
    assert (near, far) == (scene.camera.near, scene.camera.far)
    levels = np.asarray(png)
    assert levels.dtype == np.uint16
    covered = np.isfinite(exact)
    assert np.all(levels[~covered] == 0) and np.all(levels[covered] >= 1)  # 0 = background
    decoded = near + (levels[covered] - 1.0) / 65534.0 * (far - near)  # the stated mapping (docs/conventions.md)
    assert np.abs(decoded - exact[covered]).max() <= (far - near) / 65534.0
    assert "0 = background" in png.text["depth_encoding"]


def test_render_and_batch_write_the_same_depth_png(tmp_path):
    """One 16-bit depth encoding: `render --depth d.png` and `batch --depth png16` write the
    same values and the same text chunks for the same view."""
    assert main(["render", "builtin:torus", "--size", "48x32", "-q", "-o", str(tmp_path / "c.png"),
                 "--camera-azimuth-angle", "30", "--depth", str(tmp_path / "d.png")]) == 0
    assert main(["batch", "--meshes", "builtin:torus", "--views", "1", "--size", "48x32", "--camera-azimuth-angle", "30",
                 "--depth", "png16", "-o", str(tmp_path / "out"), "-q"]) == 0
    rendered, batched = Image.open(tmp_path / "d.png"), Image.open(tmp_path / "out" / "torus" / "view_000_depth.png")
    assert np.array_equal(np.asarray(rendered), np.asarray(batched))
    assert rendered.text == batched.text and set(rendered.text) == {"near", "far", "depth_encoding"}
    levels = np.asarray(rendered)
    assert levels.min() == 0 and 1 <= levels[levels > 0].min() < levels.max() <= 65535
    decoded = read_depth_png(tmp_path / "d.png")
    exact = np.load(_npy_depth(tmp_path))
    assert np.array_equal(np.isinf(decoded), np.isinf(exact))
    near, far = float(rendered.text["near"]), float(rendered.text["far"])
    assert np.abs(decoded[np.isfinite(exact)] - exact[np.isfinite(exact)]).max() <= (far - near) / 65534.0


def _npy_depth(folder):
    path = folder / "d.npy"
    assert main(["render", "builtin:torus", "--size", "48x32", "-q", "-o", str(folder / "c.png"),
                 "--camera-azimuth-angle", "30", "--depth", str(path)]) == 0
    return path


@pytest.mark.parametrize(
    "argv, message",
    [
        (["-o", "/proc/nope.png"], "output '/proc/nope.png' cannot be written"),
        (["-o", "{tmp}/no/such/a.png"], "does not exist"),
        (["-o", "{tmp}/a.png", "--depth", "{tmp}/d.exr"], "--depth '{tmp}/d.exr': unsupported format"),
        (["-o", "{tmp}/a.png", "--depth", "/proc/d.npy"], "--depth '/proc/d.npy' cannot be written"),
        (["-o", "{tmp}"], "unsupported format"),
        (["-o", "-", "--float"], "-o - writes an 8-bit PNG"),
    ],
)
def test_outputs_are_checked_before_any_work(argv, message, tmp_path, capsys, monkeypatch):
    import wgpu_shading.assets.mesh_scene as mesh_scene_module

    def never(*args, **kwargs):  # the scene must not even be loaded
        raise AssertionError("rendering started before the outputs were checked")

    monkeypatch.setattr(mesh_scene_module, "read_mesh", never)
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert main(["render", "builtin:torus", *argv]) == 2
    err = capsys.readouterr().err
    assert message.replace("{tmp}", str(tmp_path)) in err and err.count("\n") == 1
    assert not any(p.name != "no" for p in tmp_path.iterdir())  # the probe left nothing behind


def test_check_and_bench_check_their_folders_first(capsys):
    assert main(["check", "builtin:torus", "--ref", "/proc/x.png", "--update"]) == 2
    assert "files cannot be written there" in capsys.readouterr().err
    assert main(["bench", "accuracy", "--quick", "--out", "/proc/study"]) == 2
    assert "--out '/proc'" in capsys.readouterr().err


def test_frame_shows_itself_in_jupyter(renderer):
    frame = renderer.render_frame(mesh_scene("builtin:torus", (40, 30), None))
    shown = np.asarray(Image.open(io.BytesIO(frame._repr_png_())))
    assert np.array_equal(shown, frame.color)
    linear = renderer.render_frame(mesh_scene("builtin:torus", (40, 30), None), float32=True)
    assert np.abs(np.asarray(Image.open(io.BytesIO(linear._repr_png_()))).astype(int) - frame.color).max() <= 1


def test_depth_and_colour_to_the_same_file_is_refused(tmp_path, capsys):
    # Before, the depth PNG silently replaced the colour image (exit 0).
    out = str(tmp_path / "same.png")
    code, err = run_cli(capsys, "render", "builtin:cube", "--size", "16", "-o", out, "--depth", out)
    one_line_error(code, err, "--depth", "same.png", "same file")
    assert not Path(out).exists()
