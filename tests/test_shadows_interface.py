"""Shadows as a user asks for them (docs/shadows.md#settings, docs/view-options.md): `render`
and `batch` flags, scene-file keys, the lights of a bare mesh and of a glTF file, and clear
errors for bad values."""

from __future__ import annotations

import math

import numpy as np
import pytest
from PIL import Image

from cli_errors import one_line_error, run_cli
from gltf_builder import quad, write_gltf
from wgpu_shading.assets.scenefile import load_scene
from wgpu_shading.assets.view_loader import load_view
from wgpu_shading.cli.main import main
from wgpu_shading.errors import SceneError
from wgpu_shading.scene import ShadowSettings
from wgpu_shading.scene.view.options import ViewOptions

SCENE = """
[output]
size = [64, 48]
[camera]
eye = [0.0, 4.0, 6.0]
target = [0.0, 0.5, 0.0]
[shadows]
map_size = 512
filter = "nearest"
bias = 2.5
[[lights]]
type = "directional"
direction = [0.4, -1.0, -0.3]
shadows = SHADOWS
[[objects]]
mesh = "builtin:sphere"
translate = [0.0, 1.2, 0.0]
[[objects]]
mesh = "builtin:plane"
scale = [8.0, 8.0, 8.0]
rotate = [-90.0, 0.0, 0.0]
receive_shadows = RECEIVES
"""


def scene_file(tmp_path, shadows="true", receives="true", name="scene.toml"):
    path = tmp_path / name
    path.write_text(SCENE.replace("SHADOWS", shadows).replace("RECEIVES", receives))
    return path


def pixels(path) -> np.ndarray:
    return np.asarray(Image.open(path))


def test_scene_file_keys_say_what_casts_receives_and_how(tmp_path):
    scene = load_scene(scene_file(tmp_path))
    assert scene.lights[0].shadows and scene.objects[1].receive_shadows and scene.objects[0].cast_shadows
    assert scene.shadows == ShadowSettings(map_size=512, filter="nearest", bias=2.5)
    assert load_scene(scene_file(tmp_path, "false", name="off.toml")).shadows == scene.shadows


def test_render_draws_the_shadow_the_scene_asks_for_and_the_flags_turn_it_on_and_off(tmp_path):
    lit, shadowed, forced, off = (tmp_path / f"{n}.png" for n in ("lit", "shadowed", "forced", "off"))
    assert main(["render", str(scene_file(tmp_path, "false", name="a.toml")), "-o", str(lit), "-q"]) == 0
    assert main(["render", str(scene_file(tmp_path, "true", name="b.toml")), "-o", str(shadowed), "-q"]) == 0
    assert main(["render", str(scene_file(tmp_path, "false", name="c.toml")), "--shadows", "-o", str(forced), "-q"]) == 0
    assert main(["render", str(scene_file(tmp_path, "true", name="d.toml")), "--no-shadows", "-o", str(off), "-q"]) == 0
    assert np.array_equal(pixels(shadowed), pixels(forced)) and np.array_equal(pixels(lit), pixels(off))
    darker = pixels(shadowed)[..., :3].astype(int).sum(-1) < pixels(lit)[..., :3].astype(int).sum(-1)
    assert 0.02 < darker.mean() < 0.5  # the ball's shadow on the ground, not the whole picture
    receives_none = tmp_path / "none.png"
    assert main(["render", str(scene_file(tmp_path, "true", name="e.toml")), "--no-receive-shadows", "-o", str(receives_none), "-q"]) == 0
    assert np.array_equal(pixels(receives_none), pixels(lit))


def test_batch_draws_the_shadowed_bare_mesh_as_render_does(tmp_path):
    """A bare torus under the viewer's lights shadows itself (its inner ring)."""
    common = ["--size", "48", "--shadows", "--shadow-map-size", "512", "-q"]
    assert main(["render", "builtin:torus", *common, "-o", str(tmp_path / "render.png")]) == 0
    assert main(["batch", "--meshes", "builtin:torus", "--views", "1", *common, "-o", str(tmp_path / "batch")]) == 0
    assert main(["render", "builtin:torus", "--size", "48", "-q", "-o", str(tmp_path / "plain.png")]) == 0
    shadowed = pixels(tmp_path / "render.png")
    (batch_image,) = (tmp_path / "batch").rglob("*.png")
    assert np.array_equal(shadowed, pixels(batch_image))
    assert not np.array_equal(shadowed, pixels(tmp_path / "plain.png"))


def test_the_viewer_lights_and_a_gltf_files_own_lights_take_the_shadows_option(tmp_path):
    bare = load_view("builtin:torus", ViewOptions(shadows=True))
    assert bare.lights and all(light.shadows for light in bare.lights)
    moved = load_view("builtin:torus", ViewOptions(shadows=True, camera_azimuth=40.0))  # the lights follow the camera
    assert all(light.shadows for light in moved.lights)
    positions, indices = quad(-1, -1, 2)
    gltf = write_gltf(tmp_path / "lit.gltf", [[{"positions": positions, "indices": indices, "normals": np.tile([0, 0, 1], (4, 1))}]],
                      nodes=[{"mesh": 0}, {"translation": [0, 0, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
                      extra={"extensionsUsed": ["KHR_lights_punctual"], "scenes": [{"nodes": [0, 1]}],
                             "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 2}]}}})
    file_lights = load_view(str(gltf), ViewOptions(shadows=True)).lights
    assert len(file_lights) == 1 and file_lights[0].shadows and not load_view(str(gltf)).lights[0].shadows


@pytest.mark.parametrize("flags, words", [
    (["--shadow-map-size", "8"], ["--shadow-map-size", "16..8192", "8"]),
    (["--shadow-map-size", "big"], ["--shadow-map-size", "auto or a whole number", "big"]),
    (["--shadow-filter", "gauss"], ["--shadow-filter", "gauss"]),
    (["--shadow-bias", "-1"], ["--shadow-bias", "-1"]),
    (["--shadow-bias", str(math.inf)], ["--shadow-bias"]),
])
def test_bad_shadow_flags_are_one_line_errors(capsys, tmp_path, flags, words):
    code, err = run_cli(capsys, "render", "builtin:sphere", *flags, "-o", str(tmp_path / "x.png"))
    one_line_error(code, err, *words)


@pytest.mark.parametrize("text, words", [
    ("[shadows]\nmap_size = 100000\n", ["shadows.map_size", "100000"]),
    ("[shadows]\nblur = 2\n", ["[shadows]", "blur"]),
    ('[shadows]\nfilter = "soft"\n', ["shadows.filter", "soft"]),
    ('[[lights]]\nshadows = "yes"\n', ["[[lights]] #1", "shadows"]),
    ('[[objects]]\nmesh = "builtin:sphere"\ncast_shadows = 1\n', ["[[objects]] #1", "cast_shadows"]),
])
def test_bad_shadow_keys_in_a_scene_file_name_the_key(tmp_path, text, words):
    path = tmp_path / "bad.toml"
    path.write_text(text + ('[[objects]]\nmesh = "builtin:sphere"\n' if "[[objects]]" not in text else ""))
    with pytest.raises(SceneError) as error:
        load_scene(path)
    for word in words:
        assert word in str(error.value)


def _eight_positional_lights(tmp_path):
    """Eight casting positional lights around a sphere over a floor, a sphere above, one of
    them inside the first sphere: seven need a map each (one view aimed at the scene), the
    one inside a cube map's faces, so at 8192² they are beyond 2 GiB (256 MiB a map)."""
    text = "[output]\nsize = [32, 32]\n"
    for x, y, z in [(3, 0.5, 3), (-3, 0.5, 3), (3, 0.5, -3), (-3, 0.5, -3), (0, 0.5, 4), (4, 0.5, 0), (-4, 0.5, 0), (0, 0, 0)]:
        text += f'[[lights]]\ntype = "positional"\nposition = [{x}, {y}, {z}]\nshadows = true\n'
    text += ('[[objects]]\nmesh = "builtin:sphere"\n[[objects]]\nmesh = "builtin:plane"\ntranslate = [0, -1, 0]\n'
             'scale = [8, 8, 8]\n[[objects]]\nmesh = "builtin:sphere"\ntranslate = [0, 3, 0]\n')
    path = tmp_path / "eight.toml"
    path.write_text(text)
    return path


def test_shadow_maps_beyond_their_memory_limit_are_refused_before_any_is_made(renderer, capsys, tmp_path):
    # Eight positional lights at 8192² asked lavapipe for gigabytes of host memory (12 GiB
    # for all 48 faces); a GPU answered with an internal error. Now one line, exit 2. (A light
    # far enough from the scene needs one view: eight such would be 2 GiB exactly.)
    from wgpu_shading.render.gpu.shadow_maps import MAX_SHADOW_MAP_BYTES

    assert MAX_SHADOW_MAP_BYTES == 2 << 30
    with pytest.raises(SceneError, match=r"9 shadow maps .* of 8192×8192 texels, 2\.25 GiB; at most 2 GiB"):
        renderer.device_cache.shadow_maps(8192, 9)  # refused before the texture is made
    code, err = run_cli(capsys, "render", str(_eight_positional_lights(tmp_path)), "--shadow-map-size", "8192", "-o", str(tmp_path / "x.png"))
    one_line_error(code, err, "shadows.map_size", "shadow maps", "GiB")
    assert not (tmp_path / "x.png").exists()
    code, err = run_cli(capsys, "render", str(_eight_positional_lights(tmp_path)), "--shadow-map-size", "256", "-o", str(tmp_path / "x.png"))
    assert code == 0, err  # the same lights at a size that fits
