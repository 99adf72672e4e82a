"""`wgpu_shading.view(...)`: the notebook widget (rendercanvas's Jupyter backend over
jupyter_rfb), driven through its API as the browser drives it (jupyter_rfb events in,
frames out). The reference is the `render` command."""

from __future__ import annotations

import shlex

import numpy as np
import pytest
from PIL import Image

import wgpu_shading
from wgpu_shading.cli import main

pytest.importorskip("rendercanvas.jupyter", reason="the [view] extra (rendercanvas, jupyter_rfb) is not installed")


def rendered(tmp_path, argv: list[str]) -> np.ndarray:
    out = tmp_path / "ref.png"
    assert main([*argv, "-o", str(out), "-q"]) == 0
    return np.asarray(Image.open(out))


def test_widget_frames_follow_browser_events_and_match_render(renderer, tmp_path):
    widget = wgpu_shading.view("builtin:torus", size=(160, 120), material="jade", renderer=renderer)
    assert widget.css_width == "160.0px" and widget.quality == 100  # lossless frames to the browser
    snapshot = widget.snapshot()
    assert np.array_equal(snapshot.color, rendered(tmp_path, ["render", "builtin:torus", "--size", "160x120", "--material", "jade"]))
    assert snapshot._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"  # a notebook shows the Frame as an image

    # What jupyter_rfb hands the widget for a drag and a key (the browser's event names).
    for event in (
        {"event_type": "pointer_down", "x": 40, "y": 60, "button": 1, "buttons": [1], "modifiers": []},
        {"event_type": "pointer_move", "x": 90, "y": 75, "button": 0, "buttons": [1], "modifiers": []},
        {"event_type": "pointer_up", "x": 90, "y": 75, "button": 1, "buttons": [], "modifiers": []},
        {"event_type": "key_down", "key": "F", "modifiers": ["Shift"]},
    ):
        widget.handle_event(event)
    widget.get_frame()  # what jupyter_rfb calls to draw: events are processed first
    assert widget.live.state.settings.frequency == "flat" and "flat shading" in widget.title
    argv = widget.command()
    assert "--frequency=flat" in argv and any(a.startswith("--camera-position=") for a in argv)
    assert np.array_equal(widget.snapshot().color, rendered(tmp_path, argv[1:]))


def test_widget_of_a_scene_object_and_compare(renderer):
    from wgpu_shading.assets.view_loader import load_view

    scene = load_view("builtin:sphere")
    widget = wgpu_shading.view(scene, size=(64, 48), compare="reflection", renderer=renderer)
    assert widget.snapshot().color.shape == (48, 128, 4)
    assert [next(a for a in argv if a.startswith("--reflection=")) for argv in widget.live.commands()] == [
        "--reflection=phong", "--reflection=blinn-phong"]
    assert shlex.join(widget.command()).startswith("wgpu-shading render SCENE")
