"""`wgpu-shading view` in a real window: a glfw window on a virtual X server (Xvfb), driven
by xdotool as a user would (keys, a mouse drag). `S` right after opening must save the
pixels `render` writes with the same options, and `S` after the drag the pixels of the
command `P` printed; and the window itself (captured with xwd) must show render's pixels.
(`./run tests` installs Xvfb, xauth, xdotool and x11-apps with apt.)"""

from __future__ import annotations

import shlex
import shutil
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from wgpu_shading.cli import main

pytest.importorskip("rendercanvas.glfw", reason="the [view] extra (rendercanvas, glfw) is not installed")

MISSING = [tool for tool in ("xvfb-run", "Xvfb", "xauth", "xdotool") if shutil.which(tool) is None]
pytestmark = pytest.mark.skipif(
    bool(MISSING), reason=f"no virtual X server to open a window on: {', '.join(MISSING)} not installed (apt: xvfb xauth xdotool)"
)

# Runs under xvfb-run. Waits are polls with a bound, not fixed sleeps: the machine is slow
# and shared. The title ends in the frame time once a frame has been drawn.
DRIVER = r"""
set -u
"$PYTHON" -c 'import sys; from wgpu_shading.cli import main; sys.exit(main())' \
    view builtin:torus --size 160x120 -q > viewer.out 2> viewer.err &
viewer=$!
window=$(timeout 60 xdotool search --sync --name ' ms$' | head -1)
[ -n "$window" ] || { echo "no window"; cat viewer.err; exit 3; }
wait_for() { for _ in $(seq 300); do [ -e "$1" ] && return 0; sleep 0.1; done; echo "no $1"; exit 4; }
xdotool mousemove --window "$window" 80 60
xdotool key s
wait_for torus-001.png
# What the window shows (the frame was presented before S was handled): xwd, when there.
if command -v xwd >/dev/null; then xwd -id "$window" -silent > shown.xwd; fi
xdotool mousemove --window "$window" 40 60 mousedown 1 mousemove --window "$window" 70 70 \
    mousemove --window "$window" 100 80 mouseup 1
xdotool key p s
wait_for torus-002.png
xdotool key q
for _ in $(seq 100); do kill -0 "$viewer" 2>/dev/null || break; sleep 0.1; done
kill "$viewer" 2>/dev/null && echo "viewer did not quit on Q"
wait "$viewer"
echo "viewer exit $?"
"""


def _png(path) -> np.ndarray:
    return np.asarray(Image.open(path))


def _drive(tmp_path, driver: str) -> str:
    """Run a driver script on a 640×480 Xvfb screen; the log (skips where Xvfb cannot start)."""
    script = tmp_path / "driver.sh"
    script.write_text(driver)
    try:
        run = subprocess.run(
            ["xvfb-run", "-a", "-s", "-screen 0 640x480x24", "bash", str(script)],
            cwd=tmp_path, env={**_environment(), "PYTHON": sys.executable},
            capture_output=True, text=True, timeout=150,
        )
    except subprocess.TimeoutExpired:
        pytest.fail("the window test did not finish in 150 s")
    log = f"{run.stdout}\n{run.stderr}\n{_read(tmp_path / 'viewer.err')}"
    if run.returncode != 0 and "xvfb-run: error" in run.stderr:
        pytest.skip(f"Xvfb could not start here: {run.stderr.strip()}")
    assert run.returncode == 0 and "viewer exit 0" in run.stdout, log
    return log


def test_window_saves_renders_pixels_then_the_printed_commands(tmp_path):
    log = _drive(tmp_path, DRIVER)

    render = tmp_path / "render.png"
    assert main(["render", "builtin:torus", "--size", "160x120", "-o", str(render), "-q"]) == 0
    assert np.array_equal(_png(tmp_path / "torus-001.png"), _png(render)), "S right after opening differs from render"
    if shutil.which("xwd"):  # the window's own pixels (x11-apps' xwd)
        shown = read_xwd((tmp_path / "shown.xwd").read_bytes())
        assert np.array_equal(shown, _png(render)[:, :, :3]), "the window shows other pixels than render writes"

    lines = (tmp_path / "viewer.out").read_text().splitlines()
    assert "wrote torus-001.png" in lines and "wrote torus-002.png" in lines, log
    (command,) = [line for line in lines if line.startswith("wgpu-shading render ")]
    argv = shlex.split(command)
    assert any(a.startswith("--camera-position=") for a in argv), "the drag did not move the camera: " + command
    printed = tmp_path / "printed.png"
    assert main([*argv[1:], "-o", str(printed), "-q"]) == 0
    assert np.array_equal(_png(tmp_path / "torus-002.png"), _png(printed)), "S after the drag differs from P's command"
    assert not np.array_equal(_png(printed), _png(render))


def read_xwd(data: bytes) -> np.ndarray:
    """The RGB pixels of an X window dump (xwd's format: a header of 25 big-endian 32-bit
    fields, the window name, a colour map, then the rows; X11/XWDFile.h). Only the layout a
    24-bit TrueColor Xvfb screen writes: 32 bits a pixel, least significant byte first."""
    import struct

    fields = struct.unpack(">25I", data[:100])
    header_size, width, height, byte_order, bits_per_pixel, bytes_per_line = (
        fields[0], fields[4], fields[5], fields[7], fields[11], fields[12])
    assert bits_per_pixel == 32 and byte_order == 0, f"unexpected xwd layout: {bits_per_pixel} bpp, byte order {byte_order}"
    start = header_size + 12 * fields[19]  # the colour map: ncolors entries of 12 bytes
    rows = np.frombuffer(data[start:start + bytes_per_line * height], np.uint8).reshape(height, bytes_per_line)
    return rows[:, : width * 4].reshape(height, width, 4)[:, :, [2, 1, 0]]  # B, G, R, pad → R, G, B


def _environment() -> dict:
    import os

    return {key: value for key, value in os.environ.items() if key not in ("DISPLAY", "WAYLAND_DISPLAY")}


def _read(path) -> str:
    return path.read_text() if path.exists() else ""


# `view --compare` of three 400×300 panels (1200×300) on a 640×480 screen: the window opens
# scaled to fit (90 % of the screen's width: 576×144); S still saves the whole 1200×300 picture.
COMPARE_DRIVER = r"""
set -u
"$PYTHON" -c 'import sys; from wgpu_shading.cli import main; sys.exit(main())' \
    view builtin:torus --size 400x300 --compare frequency -q > viewer.out 2> viewer.err &
viewer=$!
window=$(timeout 60 xdotool search --sync --name ' ms$' | head -1)
[ -n "$window" ] || { echo "no window"; cat viewer.err; exit 3; }
xdotool getwindowgeometry --shell "$window" > geometry.txt
xdotool mousemove --window "$window" 100 50
xdotool key s
for _ in $(seq 300); do [ -e torus-001.png ] && break; sleep 0.1; done
xdotool key q
for _ in $(seq 100); do kill -0 "$viewer" 2>/dev/null || break; sleep 0.1; done
kill "$viewer" 2>/dev/null && echo "viewer did not quit on Q"
wait "$viewer"
echo "viewer exit $?"
"""


def test_compare_window_fits_the_screen_it_opens_on(tmp_path):
    log = _drive(tmp_path, COMPARE_DRIVER)  # (fails with the viewer's output)
    geometry = dict(line.split("=", 1) for line in _read(tmp_path / "geometry.txt").split())
    assert (int(geometry["WIDTH"]), int(geometry["HEIGHT"])) == (576, 144), (geometry, log)  # 0.48 × (1200, 300)
    assert _png(tmp_path / "torus-001.png").shape == (300, 1200, 4), "S saves the panels at their own size"


def test_fitted_size_scales_down_only_and_keeps_the_aspect():
    from wgpu_shading.live.window import fitted_size

    assert fitted_size((1536, 512), (1920, 1080)) == (1536, 512)  # fits: unchanged
    assert fitted_size((1536, 512), (1280, 1024)) == (1152, 384)  # 0.9 × 1280 wide
    assert fitted_size((600, 2000), (1920, 1080)) == (291, 972)  # too tall: 0.9 × 1080 high
    assert fitted_size((800, 600), None) == (800, 600)  # no monitor known
