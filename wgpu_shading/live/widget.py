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

import shlex
from contextlib import contextmanager
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


@contextmanager
def _widget_views_only():
    """jupyter_rfb displays an output widget when a widget is made (the place its event
    handlers' errors appear). Its text form, `RFBOutputContext()`, is what a front end without
    widgets shows (and plain Python prints): stray output. Here it is displayed as a widget
    view only, with no text form; outside IPython, where nothing can show it, not at all."""
    try:
        from IPython import get_ipython
        from IPython.display import publish_display_data
        from IPython.utils.capture import capture_output
    except ImportError:  # pragma: no cover - ipywidgets depends on IPython
        yield
        return
    shell = get_ipython()
    with capture_output(stdout=shell is None, stderr=False, display=True) as captured:
        yield
    if shell is None:
        return
    for output in captured.outputs:
        views = {kind: value for kind, value in output.data.items() if kind != "text/plain"}
        if views:
            publish_display_data(views, output.metadata)


@lru_cache(maxsize=1)
def _widget_class():
    backend = jupyter_backend()

    class LiveWidget(backend.RenderCanvas):
        """A notebook widget showing a LiveView. `.live` is the view (settings, options,
        commands); `.snapshot()` the current picture."""

        def __init__(self, live: LiveView, **kwargs):
            with _widget_views_only():
                super().__init__(size=live.size(), title=live.title(), **kwargs)
            self.live = live
            self.quality = 100  # lossless (PNG): the pixels shown are render's
            attach(live, self)

        def __repr__(self) -> str:
            """What is shown and how to get at it, for front ends without widgets (a terminal,
            a notebook converted to text) and `print(w)`."""
            width, height = self.live.size()
            commands = self.live.commands()
            what = "the same picture" if len(commands) == 1 else "its panels"
            lines = "\n".join("  " + shlex.join(argv) for argv in commands)
            return (
                f"wgpu-shading live view, {width}×{height}: {self.live.description()}\n"
                f"{what} from the command line:\n{lines}\n"
                "(interactive where Jupyter widgets are shown; .snapshot() is the picture, .command() the command)"
            )

        def _repr_mimebundle_(self, **kwargs):
            """The widget's bundle, with the whole description as its text form (ipywidgets
            cuts repr() to 110 characters)."""
            bundle = super()._repr_mimebundle_(**kwargs)
            data = bundle[0] if isinstance(bundle, tuple) else bundle
            if isinstance(data, dict):
                data["text/plain"] = repr(self)
            return bundle

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
