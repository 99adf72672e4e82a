"""`wgpu_shading.view(...)`: the live view as a notebook widget (rendercanvas's Jupyter
backend over jupyter_rfb; the [view] extra), with the window's mouse and keys.

    import wgpu_shading
    w = wgpu_shading.view("example:gear.ply", up="+Z", material="jade")
    w                       # shows it (drag, wheel, keys as in docs/viewer.md)
    w.snapshot()            # the current picture as a Frame (Jupyter shows it as an image)

Frames go to the browser losslessly (jupyter_rfb quality 100 = PNG), so the widget shows
the very pixels `render` writes; `S` writes the screenshot beside the notebook and `P`
prints the command line in the cell's output.
"""

from __future__ import annotations

from functools import lru_cache

from ..errors import UsageError, install_hint
from ..render.renderer import Frame, Renderer
from ..scene import Scene
from ..scene.view.options import ViewOptions
from .canvas import attach
from .session import LiveView


def jupyter_backend():
    """rendercanvas's Jupyter module, or a UsageError saying how to install it."""
    try:
        import rendercanvas.jupyter as backend
    except ImportError as error:
        raise UsageError(
            f"the notebook view needs rendercanvas and jupyter_rfb ({error}); {install_hint('view')}"
        ) from None
    return backend


@lru_cache(maxsize=1)
def _widget_class():
    backend = jupyter_backend()

    class LiveWidget(backend.RenderCanvas):
        """A notebook widget showing a LiveView. `.live` is the view (settings, options,
        commands); `.snapshot()` the current picture."""

        def __init__(self, live: LiveView, **kwargs):
            super().__init__(size=live.size(), title=live.title(), **kwargs)
            self.live = live
            self.quality = 100  # lossless (PNG): the pixels shown are render's
            attach(live, self)

        def snapshot(self) -> Frame:
            """The current view as a Frame (color: height × width × 4 uint8)."""
            return self.live.frame()

        def command(self) -> list[str]:
            """The `wgpu-shading render` argument list of the current view (first panel)."""
            return self.live.commands()[0]

    return LiveWidget


def view(
    source: str | Scene,
    *,
    compare: str | None = None,
    renderer: Renderer | None = None,
    **options,
):
    """A widget showing `source` (what `render` takes: a scene file, a mesh file, builtin:NAME,
    example:NAME; or a Scene) as `render` would draw it with these view options (keyword
    names of ViewOptions: size=(640, 480), material="jade", frequency="gouraud", up="+Z",
    camera_azimuth=30, ...). compare="frequency" or "reflection" shows the variants side by
    side with one camera."""
    widget_class = _widget_class()  # first: a missing extra is said before any work
    live = LiveView(source, ViewOptions(**options), renderer=renderer, compare=compare)
    return widget_class(live)
