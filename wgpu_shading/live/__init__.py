"""Live views: `wgpu-shading view` (a window) and `wgpu_shading.view(...)` (a notebook widget).

Both show what `wgpu-shading render` draws, turned with the mouse as in f3d and changed with
keys (docs/viewer.md). state.py and navigation.py are the pure logic (no window), session.py
draws frames and handles events, window.py and widget.py put them on a screen through
rendercanvas (the optional [view] extra).
"""

from __future__ import annotations

from typing import Any


def __getattr__(name: str) -> Any:
    # The backends import rendercanvas (the [view] extra): only when asked for.
    if name == "view":
        from .widget import view

        return view
    if name == "LiveView":
        from .session import LiveView

        return LiveView
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["LiveView", "view"]
