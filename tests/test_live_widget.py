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


def test_widget_text_form_describes_the_view_and_nothing_else_is_printed(renderer, capsys):
    """Where widgets are not shown (a terminal, a notebook converted to text, `print(w)`), the
    widget reads as what it shows and the command that draws it, not `LiveWidget object at 0x…`;
    making it prints nothing (jupyter_rfb's output area used to print `RFBOutputContext()`)."""
    widget = wgpu_shading.view("builtin:torus", size=(160, 120), material="jade", renderer=renderer)
    assert capsys.readouterr().out == ""
    text = repr(widget)
    assert text.splitlines()[:3] == [
        "wgpu-shading live view, 160×120: builtin:torus — phong shading — phong reflection — jade",
        "the same picture from the command line:",
        "  wgpu-shading render builtin:torus --size=160x120 --material=jade",
    ]
    assert "object at 0x" not in text and str(widget) == text
    data = widget._repr_mimebundle_()
    data = data[0] if isinstance(data, tuple) else data
    assert data["text/plain"] == text and "application/vnd.jupyter.widget-view+json" in data  # whole, not cut at 110 characters
    widget.live.press("f")  # the text follows the view
    assert "flat shading" in repr(widget) and "--frequency=flat" in repr(widget)


IPYTHON_SESSION = """
import json
from IPython.core.interactiveshell import InteractiveShell
from IPython.utils.capture import capture_output

shell = InteractiveShell.instance()
with capture_output() as captured:
    result = shell.run_cell('import wgpu_shading\\nw = wgpu_shading.view("builtin:torus", size=(64, 48), compare="reflection")\\nw')
assert result.success, result.error_in_exec
print(json.dumps({"stdout": captured.stdout, "outputs": [sorted(o.data) for o in captured.outputs]}))
"""


def test_in_an_ipython_session_the_cell_shows_the_description_and_no_stray_output():
    """IPython as a front end without widgets: the cell's result is the description (what a
    terminal or a text export shows); the only other output is jupyter_rfb's error area as a
    widget view without a text form (a front end with widgets shows it, others show nothing)."""
    import json
    import subprocess
    import sys

    run = subprocess.run([sys.executable, "-c", IPYTHON_SESSION], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    shown = json.loads(run.stdout.strip().splitlines()[-1])
    assert shown["outputs"] == [["application/vnd.jupyter.widget-view+json"]]
    out = shown["stdout"]
    assert "RFBOutputContext" not in out and "object at 0x" not in out
    assert "wgpu-shading live view, 128×48: builtin:torus — phong shading — compare phong | blinn-phong — gold" in out
    assert "its panels from the command line:" in out and "--reflection=blinn-phong" in out
