"""`wgpu-shading view`'s window: a glfw window through rendercanvas (the [view] extra).

rendercanvas's glfw backend presents the bitmap with wgpu, so the window works wherever the
renderer does: on lavapipe under an X server (Xvfb included) as on a GPU.
"""

from __future__ import annotations

import warnings

from ..errors import UsageError, install_hint
from .canvas import attach
from .session import LiveView


def glfw_backend():
    """rendercanvas's glfw module, or a UsageError saying how to install it / what is missing."""
    try:
        import glfw
        import rendercanvas.glfw as backend
    except ImportError as error:
        raise UsageError(f"the view window needs rendercanvas and glfw ({error}); {install_hint('view')}") from None
    with warnings.catch_warnings(record=True) as said:  # glfw warns, then init returns False
        warnings.simplefilter("always")
        ready = glfw.init()
    if not ready:  # rendercanvas would go on and abort inside glfw without a display
        reason = "; ".join(str(w.message) for w in said) or "glfw could not initialise"
        raise UsageError(
            f"the view window cannot open: no display ({reason}); set DISPLAY, or run it under `xvfb-run -a`"
        )
    return backend


# The share of the monitor's work area a window may take (room for its title bar and frame).
SCREEN_SHARE = 0.9


def fitted_size(size: tuple[int, int], available: tuple[int, int] | None) -> tuple[int, int]:
    """The window size showing a picture of `size` whole on a screen area of `available`
    pixels: the picture's own size when it fits, else scaled down, aspect kept. The frames
    are still rendered at `size` (S saves them whole); the window shows them scaled."""
    width, height = size
    if not available or min(available) <= 0:
        return width, height
    scale = min(1.0, SCREEN_SHARE * available[0] / width, SCREEN_SHARE * available[1] / height)
    return max(1, int(width * scale)), max(1, int(height * scale))


def work_area() -> tuple[int, int] | None:
    """The primary monitor's work area (the screen less task bars) in screen pixels, from glfw;
    None when glfw knows no monitor."""
    import glfw

    monitor = glfw.get_primary_monitor()
    if not monitor:
        return None
    _, _, width, height = glfw.get_monitor_workarea(monitor)
    if width <= 0 or height <= 0:  # no window manager says: the whole screen
        mode = glfw.get_video_mode(monitor)
        width, height = mode.size.width, mode.size.height
    return width, height


def open_window(view: LiveView, *, max_fps: float = 60.0):
    """A window on `view` (not yet shown until the loop runs), as large as the picture or as
    the screen allows (`--compare` puts three panels side by side); returns the canvas."""
    backend = glfw_backend()
    width, height = fitted_size(view.size(), work_area())
    canvas = backend.RenderCanvas(
        size=(width, height), title=view.title(), update_mode="ondemand", max_fps=max_fps, vsync=False
    )
    attach(view, canvas)
    return canvas


def run_window(view: LiveView) -> None:
    """Open the window and handle it until it is closed (Q, Esc or the window's close button)."""
    backend = glfw_backend()
    open_window(view)
    backend.loop.run()
