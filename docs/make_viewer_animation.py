"""docs/images/viewer_compare.gif: `wgpu-shading view --compare frequency` as a drag turns it.

The frames are those the viewer window presents (LiveView.frame(), the bitmap it hands the
window), for the same synthetic events the window would get: a left drag across the window
(orbit, one pointer move per frame) after two wheel notches (zoom), then a few presses of `B` and `]`. Run:

    .venv/bin/python docs/make_viewer_animation.py     (needs the [view] extra)
"""

from __future__ import annotations

from pathlib import Path

from wgpu_shading.assets.animation import write_animation
from wgpu_shading.live.session import LiveView
from wgpu_shading.scene.view.options import ViewOptions

SOURCE = "builtin:torus?segments=24&rings=12"  # coarse: the three frequencies differ visibly
OUTPUT = Path(__file__).resolve().parent / "images" / "viewer_compare.gif"


def frames(view: LiveView):
    width, height = view.size()
    y = height / 2
    for _ in range(2):  # two wheel notches forward: 1.21² closer
        view.handle_event({"event_type": "wheel", "dx": 0.0, "dy": -100.0, "x": width / 2, "y": y})
    view.handle_event({"event_type": "pointer_down", "x": 10.0, "y": y, "button": 1})
    for step in range(24):  # 24 moves of 6 px: 144 px × 200° / 160 px = 180 degrees of azimuth
        view.handle_event({"event_type": "pointer_move", "x": 10.0 + 6 * (step + 1), "y": y + (1.0 if step < 8 else 0)})
        yield view.frame().color
    view.handle_event({"event_type": "pointer_up", "x": 0.0, "y": y, "button": 1})
    for key in ("b", "]", "]"):  # Blinn-Phong, then a sharper highlight
        view.press(key)
        for _ in range(3):
            yield view.frame().color


def main() -> None:
    view = LiveView(SOURCE, ViewOptions(size=(160, 120), samples=4), compare="frequency", out=lambda text: None)
    count = write_animation(OUTPUT, frames(view), fps=12)
    print(f"wrote {OUTPUT} ({count} frames, {OUTPUT.stat().st_size // 1024} KiB)")


if __name__ == "__main__":
    main()
