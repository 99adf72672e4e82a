"""A LiveView on a rendercanvas canvas: its events in, its frames out (any backend).

The frame is presented as a bitmap (`canvas.get_context("bitmap")`): the uint8 RGBA image
the Renderer read back, so the window shows exactly the pixels `render` writes (rendercanvas
uploads it to a texture of the same format and draws it unscaled at the canvas's size).
"""

from __future__ import annotations

from .session import LiveView

EVENT_TYPES = ("pointer_down", "pointer_move", "pointer_up", "wheel", "key_down", "resize")


def attach(view: LiveView, canvas) -> None:
    """Draw `view` on `canvas` and let the canvas's mouse and keys drive it."""
    context = canvas.get_context("bitmap")

    def draw() -> None:
        context.set_bitmap(view.frame().color)
        canvas.set_title(view.title())

    def on_event(event: dict) -> None:
        if view.handle_event(event):
            canvas.request_draw()

    view.on_quit = canvas.close
    canvas.add_event_handler(on_event, *EVENT_TYPES)
    canvas.request_draw(draw)
