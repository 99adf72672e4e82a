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


def open_window(view: LiveView, *, max_fps: float = 60.0):
    """A window on `view` (not yet shown until the loop runs); returns the canvas."""
    backend = glfw_backend()
    width, height = view.size()
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
