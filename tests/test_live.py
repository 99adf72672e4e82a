"""The live view's logic (wgpu_shading/live/) driven through rendercanvas's offscreen
backend: synthetic drags and keys change the camera and the settings as docs/viewer.md
says, the canvas shows the pixels `render` writes, and `P` prints a command that draws
exactly what is shown. References: `wgpu-shading render` run as a command, and camera
positions computed here by hand (rotations about the up vector, VTK's dolly factors)."""

from __future__ import annotations

import math
import shlex

import numpy as np
import pytest
from PIL import Image

from wgpu_shading.cli import main
from wgpu_shading.scene.view.options import ViewOptions

offscreen = pytest.importorskip("rendercanvas.offscreen", reason="the [view] extra (rendercanvas) is not installed")

from wgpu_shading.live.canvas import attach  # noqa: E402
from wgpu_shading.live.session import LiveView  # noqa: E402

SIZE = (160, 120)


def rendered(tmp_path, argv: list[str], name: str = "ref.png") -> np.ndarray:
    """What the `render` command writes for `argv` (["render", SOURCE, flags...])."""
    out = tmp_path / name
    assert main([*argv, "-o", str(out), "-q"]) == 0
    return np.asarray(Image.open(out))


@pytest.fixture
def live(renderer):
    view = LiveView("builtin:torus", ViewOptions(size=SIZE), renderer=renderer, out=lambda text: None)
    canvas = offscreen.RenderCanvas(size=view.size())
    attach(view, canvas)
    view.canvas = canvas
    return view


def drag(view: LiveView, button: int, start: tuple[float, float], end: tuple[float, float], steps: int = 2) -> None:
    """The events rendercanvas emits for a drag (positions in logical pixels)."""
    view.handle_event({"event_type": "pointer_down", "x": start[0], "y": start[1], "button": button, "buttons": (button,)})
    points = [(start[0] + (end[0] - start[0]) * k / steps, start[1] + (end[1] - start[1]) * k / steps) for k in range(1, steps + 1)]
    for x, y in points:
        view.handle_event({"event_type": "pointer_move", "x": x, "y": y, "button": 0, "buttons": (button,)})
    view.handle_event({"event_type": "pointer_up", "x": end[0], "y": end[1], "button": button, "buttons": ()})


def key(view: LiveView, name: str) -> None:
    view.handle_event({"event_type": "key_down", "key": name, "modifiers": ()})


def test_the_window_opens_on_renders_picture(live, tmp_path):
    shown = live.canvas.draw()  # the bitmap the canvas presents
    assert np.array_equal(np.asarray(shown), rendered(tmp_path, ["render", "builtin:torus", "--size", "160x120"]))


def test_left_drag_orbits_about_the_up_vector_as_f3d(live):
    before = live.state.camera
    # 40 px to the right, a quarter of the width, in one motion event (each event turns about
    # the view-up of the moment, which VTK re-orthogonalises after every step)
    drag(live, 1, (50, 60), (90, 60), steps=1)
    after = live.state.camera
    # VTK's trackball: Azimuth(-40 * 200 / 160) = -50 degrees about the view-up through the target.
    turn = math.radians(-50.0)
    axis = np.array(before.up) / np.linalg.norm(before.up)
    offset = np.subtract(before.eye, before.target)
    expected = (  # Rodrigues' rotation formula
        offset * math.cos(turn) + np.cross(axis, offset) * math.sin(turn) + axis * axis.dot(offset) * (1 - math.cos(turn))
    )
    assert np.allclose(np.subtract(after.eye, after.target), expected, atol=1e-9)
    assert after.target == before.target
    # Dragging right brings the camera round to the viewer's left: eye x decreases from 0.
    assert after.eye[0] < before.eye[0] - 0.5


def test_a_stretched_window_turns_by_the_same_fraction_of_its_width(live):
    before = live.state.camera
    live.handle_event({"event_type": "resize", "width": 320.0, "height": 240.0, "pixel_ratio": 1.0})
    drag(live, 1, (100, 120), (180, 120), steps=1)  # a quarter of the 320-wide window
    turned = np.subtract(live.state.camera.eye, live.state.camera.target)
    start = np.subtract(before.eye, before.target)
    horizontal = lambda v: np.array([v[0], v[2]])  # noqa: E731  (the turn is about +Y here)
    cosine = horizontal(turned) @ horizontal(start) / np.linalg.norm(horizontal(turned)) / np.linalg.norm(horizontal(start))
    assert math.isclose(math.degrees(math.acos(cosine)), 50.0, abs_tol=1e-6)  # as 40 px of the 160-wide picture


def test_vertical_drag_raises_the_camera_and_keeps_up_orthogonal(live):
    before = live.state.camera
    drag(live, 1, (80, 40), (80, 70), steps=1)  # 30 px down: Elevation(+50 degrees): seen from higher
    after = live.state.camera
    offset = np.subtract(after.eye, after.target)
    assert after.eye[1] > before.eye[1]
    assert abs(np.dot(offset, after.up)) < 1e-9 and math.isclose(np.linalg.norm(after.up), 1.0)
    assert math.isclose(np.linalg.norm(offset), np.linalg.norm(np.subtract(before.eye, before.target)))


def test_right_drag_and_wheel_zoom_by_vtks_dolly_factors(live):
    distance = lambda camera: float(np.linalg.norm(np.subtract(camera.eye, camera.target)))  # noqa: E731
    start = distance(live.state.camera)
    drag(live, 2, (80, 60), (80, 30))  # up by a quarter of the height: 1.1 ** (10 * 30 / 60)
    assert math.isclose(distance(live.state.camera), start / 1.1**5, rel_tol=1e-12)
    live.handle_event({"event_type": "wheel", "dx": 0.0, "dy": -100.0, "x": 80, "y": 60})  # one notch forward
    assert math.isclose(distance(live.state.camera), start / 1.1**5 / 1.1**2, rel_tol=1e-12)


def test_a_zoom_the_camera_refuses_is_said_and_undone(live):
    printed = []
    live.out = printed.append
    for _ in range(12):  # each event at most 1.1^100 farther: soon past float32's range
        live.handle_event({"event_type": "wheel", "dx": 0.0, "dy": 1e9, "x": 80, "y": 60})
    assert printed and "the view stays as it was" in printed[-1]
    distance = np.linalg.norm(np.subtract(live.state.camera.eye, live.state.camera.target))
    assert math.isfinite(distance) and distance < 1e30
    assert np.asarray(live.canvas.draw()).shape == (120, 160, 4)  # and it still draws


def test_middle_drag_pans_the_target_with_the_pointer(live):
    before = live.state.camera
    drag(live, 3, (80, 60), (100, 60))  # 20 px right: the scene follows, the camera moves left
    after = live.state.camera
    per_pixel = 2 * np.linalg.norm(np.subtract(before.eye, before.target)) * math.tan(math.radians(before.fov_y / 2)) / 120
    shift = np.subtract(after.target, before.target)
    assert np.allclose(shift, [-20 * per_pixel, 0.0, 0.0], atol=1e-12)
    assert np.allclose(np.subtract(after.eye, before.eye), shift, atol=1e-12)


def test_keys_change_the_settings_as_documented(live):
    s = lambda: live.state.settings  # noqa: E731
    assert (s().frequency, s().reflection, s().two_sided, s().samples) == ("phong", "phong", False, 1)
    for expected in ("flat", "gouraud", "phong"):
        key(live, "f")
        assert s().frequency == expected
    key(live, "b")
    assert s().reflection == "blinn-phong"
    key(live, "B")  # with Shift too
    assert s().reflection == "phong"
    key(live, "m")
    assert s().material == "silver"  # gold's successor in the table
    key(live, "]")
    assert math.isclose(s().shininess, 51.2 * math.sqrt(2))  # silver: 0.4 × 128
    key(live, "[")
    key(live, "[")
    assert math.isclose(s().shininess, 51.2 / math.sqrt(2))
    for expected in (180.0, 0.0, 30.0, 60.0):
        key(live, "c")
        assert s().crease_angle == expected
    key(live, "t")
    assert s().two_sided
    assert s().edges is False
    plain = live.frame().color.copy()
    key(live, "e")  # f3d's E: the triangles' edges over the surface (docs/primitives.md#edges)
    assert s().edges is True and not np.array_equal(live.frame().color, plain)
    key(live, "e")
    assert s().edges is False and np.array_equal(live.frame().color, plain)
    key(live, "a")
    assert s().samples == 4
    assert s().shadows is False  # the torus's lights cast none
    key(live, "d")
    assert s().shadows is True
    drag(live, 1, (10, 10), (60, 30))
    moved = live.state.camera
    key(live, "Enter")
    assert live.state.camera != moved and live.state.camera == live.state.home_camera
    key(live, "Escape")
    assert live.canvas.get_closed()


def test_p_prints_a_command_that_draws_what_is_shown(live, tmp_path):
    printed = []
    live.out = printed.append
    drag(live, 1, (40, 50), (95, 80))
    drag(live, 3, (80, 60), (70, 52))
    live.handle_event({"event_type": "wheel", "dx": 0.0, "dy": 100.0, "x": 80, "y": 60})
    for name in ("f", "m", "m", "]", "t", "a", "d"):
        key(live, name)
    key(live, "p")
    (line,) = printed
    argv = shlex.split(line)
    assert argv[:3] == ["wgpu-shading", "render", "builtin:torus"]
    assert any(a.startswith("--camera-position=") for a in argv) and any(a.startswith("--camera-view-up=") for a in argv)
    shown = np.asarray(live.canvas.draw())
    assert np.array_equal(shown, rendered(tmp_path, argv[1:]))
    assert not np.array_equal(shown, rendered(tmp_path, ["render", "builtin:torus", "--size", "160x120"], "opened.png"))


def test_s_saves_numbered_screenshots_without_overwriting(live, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "torus-001.png").write_bytes(b"someone else's")
    printed = []
    live.out = printed.append
    key(live, "s")
    drag(live, 1, (10, 10), (50, 10))
    key(live, "s")
    assert printed == ["wrote torus-002.png", "wrote torus-003.png"]
    assert (tmp_path / "torus-001.png").read_bytes() == b"someone else's"
    assert np.array_equal(np.asarray(Image.open(tmp_path / "torus-003.png")), np.asarray(live.canvas.draw()))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["torus-001.png", "torus-002.png", "torus-003.png"]


def test_the_camera_costs_uniforms_and_a_feature_key_one_pipeline(live):
    live.canvas.draw()
    mesh = live.scenes()[0].objects[0].mesh
    pipelines = live.renderer.pipeline_count
    for step in range(5):
        drag(live, 1 + step % 3, (20, 20), (40 + step, 30))
        live.canvas.draw()
    assert live.renderer.pipeline_count == pipelines  # nothing compiled for a camera move
    assert live.scenes()[0].objects[0].mesh is mesh  # nor a mesh read or uploaded again
    key(live, "f")
    live.canvas.draw()
    flat = live.renderer.pipeline_count
    assert flat <= pipelines + 1
    for _ in range(3):  # round the cycle again: every pipeline is in the cache
        key(live, "f")
        live.canvas.draw()
    key(live, "f")
    live.canvas.draw()
    after_cycle = live.renderer.pipeline_count
    for _ in range(3):
        key(live, "f")
        live.canvas.draw()
    assert live.renderer.pipeline_count == after_cycle


def test_compare_shows_each_frequency_side_by_side_with_one_camera(renderer, tmp_path):
    view = LiveView("builtin:torus", ViewOptions(size=SIZE), renderer=renderer, compare="frequency", out=lambda t: None)
    canvas = offscreen.RenderCanvas(size=view.size())
    attach(view, canvas)
    drag(view, 1, (40, 50), (60, 40))
    shown = np.asarray(canvas.draw())
    assert shown.shape == (120, 480, 4)
    commands = view.commands()
    assert [next(a for a in c if a.startswith("--frequency=")) for c in commands] == [
        "--frequency=flat", "--frequency=gouraud", "--frequency=phong"]
    for index, argv in enumerate(commands):
        panel = shown[:, index * 160:(index + 1) * 160]
        assert np.array_equal(panel, rendered(tmp_path, argv[1:], f"panel{index}.png"))
    assert "flat | gouraud | phong" in view.title()


def test_a_scene_file_and_a_reread_mesh_reproduce_too(renderer, tmp_path):
    """A scene file (its own camera and lights: nothing follows the camera) and a key that
    re-reads the file (C, the crease angle) still print a command that draws what is shown."""
    for source, options, keys in (
        ("example:gold_torus_phong.toml", ViewOptions(size=SIZE), ("b", "]")),
        ("example:knot.obj", ViewOptions(size=SIZE), ("c", "c", "f", "f")),
        ("example:knot.obj", ViewOptions(size=SIZE, up="+Z"), ("m",)),  # an option read with the file
    ):
        view = LiveView(source, options, renderer=renderer, out=lambda text: None)
        canvas = offscreen.RenderCanvas(size=view.size())
        attach(view, canvas)
        drag(view, 1, (30, 40), (70, 55))
        drag(view, 2, (80, 60), (80, 50))
        for name in keys:
            key(view, name)
        (argv,) = view.commands()
        assert np.array_equal(np.asarray(canvas.draw()), rendered(tmp_path, argv[1:])), (source, argv)


def test_view_command_says_what_is_missing(monkeypatch, capsys):
    import sys

    monkeypatch.setitem(sys.modules, "rendercanvas.glfw", None)  # the [view] extra is not installed
    assert main(["view", "builtin:torus"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("wgpu-shading: error: the view window needs rendercanvas and glfw") and "[view]" in err
    assert "-m pip install" in err and len(err.splitlines()) == 1
    monkeypatch.delitem(sys.modules, "rendercanvas.glfw")
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert main(["view", "builtin:torus"]) == 2
    err = capsys.readouterr().err.strip()
    assert "no display" in err and "xvfb-run -a" in err and len(err.splitlines()) == 1


def test_file_or_viewer_lights_are_read_with_the_file(renderer, tmp_path):
    """--viewer-lights acts when a glTF file is read: the live view reads the file with it."""
    from gltf_builder import quad, write_gltf

    positions, indices = quad(-1, -1, 2)
    path = write_gltf(
        tmp_path / "lit.gltf", [[{"positions": positions, "indices": indices, "normals": np.tile([0, 0, 1], (4, 1))}]],
        nodes=[{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}}],
        extra={"extensionsUsed": ["KHR_lights_punctual"], "scenes": [{"nodes": [0, 1]}],
               "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "color": [1, 0, 0]}]}}},
    )
    pictures = []
    for viewer_lights in (None, True):  # the file's red light, then the viewer's white ones
        view = LiveView(str(path), ViewOptions(size=SIZE, viewer_lights=viewer_lights), renderer=renderer, out=lambda t: None)
        (argv,) = view.commands()
        shown = view.frame().color
        assert np.array_equal(shown, rendered(tmp_path, argv[1:])), argv
        pictures.append(shown)
    assert not np.array_equal(*pictures)
