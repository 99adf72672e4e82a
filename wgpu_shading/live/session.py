"""A live view without its window: settings → scene → frame, events → settings.

LiveView holds a ViewState, a Renderer and the view's source. The scene it draws is made
from the settings as ViewOptions through the one vocabulary (scene/view/options.py):
`load_source` reads the file once per set of options that act when a file is read (size,
crease angle, up axis), and `apply_view_options` applies everything else, so that

    load_view(source, options) == apply_view_options(load_source(source, options), options)

and the command `P` prints (`render_command(source, options)`) draws the very scene shown.
Moving the camera therefore re-reads nothing and changes only uniforms; a key that changes
the feature set (frequency, reflection, two-sided, a material with or without specular...)
gets its pipeline from the renderer's cache, compiled once (Renderer.pipeline_count).

The window (window.py) and the notebook widget (widget.py) feed rendercanvas events to
`handle_event` and show `frame().color`; tests call the same methods.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable

import numpy as np

from ..assets.view_loader import load_source, source_name
from ..errors import SceneError, WgpuShadingError
from ..render.renderer import Frame, Renderer
from ..scene import FREQUENCIES, MATERIALS, REFLECTIONS, Scene
from ..scene.view.apply import apply_view_options, scene_value
from ..scene.view.options import OPTIONS_BY_NAME, ViewOptions, render_command
from .state import ViewState, help_text, opening_settings

COMPARE_AXES = {"frequency": FREQUENCIES, "reflection": REFLECTIONS}
LOAD_CACHE_ENTRIES = 4  # scenes read with different load options (crease angles...), kept


@dataclass(frozen=True)
class Panel:
    """One picture of the view: its options and, with --compare, the value it shows."""

    options: ViewOptions
    label: str


class LiveView:
    """The scene, frames and interaction of one live view (a window, a widget or a test).

    source: a scene file, mesh file, builtin:NAME or example:NAME (what `render` takes), or
    a Scene. options: the view options it opens with (render's flags). compare: None,
    "frequency" or "reflection": one panel per value, side by side, one camera."""

    def __init__(
        self,
        source: str | Scene,
        options: ViewOptions = ViewOptions(),
        *,
        renderer: Renderer | None = None,
        compare: str | None = None,
        out: Callable[[str], None] | None = None,
    ):
        if compare is not None and compare not in COMPARE_AXES:
            raise SceneError(f"compare: expected one of {sorted(COMPARE_AXES)}, got {compare!r}")
        self.source = source
        self.user_options = options
        self.compare = compare
        self.renderer = renderer or Renderer()
        self.out = out or (lambda text: print(text, flush=True))
        self._loaded: dict[tuple, Scene] = {}
        self._drag: tuple[float, float, int] | None = None  # pointer position and button
        self.shown_size: tuple[float, float] | None = None  # the canvas's, when it differs
        self.frame_ms: float | None = None
        self.closed = False
        self.on_quit: Callable[[], None] = lambda: None  # the window's close (canvas.attach)
        opened = self._scene_for(options)
        self._panel = opened.size
        material = scene_value(opened, OPTIONS_BY_NAME["material"])
        shininess = scene_value(opened, OPTIONS_BY_NAME["shininess"])
        self.state = ViewState(
            opening_settings(options, opened),
            opened.camera,
            shininess=MATERIALS["gold"].shininess if shininess is None else float(shininess),
            material=material if material in MATERIALS else None,
        )
        self._drawn = self.state.settings  # the last settings a frame was drawn with

    # ------------------------------------------------------------------ scenes

    @property
    def name(self) -> str:
        """The source's stem (screenshots are NAME-NNN.png)."""
        if isinstance(self.source, Scene):
            return "view"
        return source_name(self.source, "view")

    def options(self) -> ViewOptions:
        """The view options of what is shown now: the opening options changed by the keys and
        the mouse (a setting left as it opened leaves the option as the user gave it)."""
        s, opened, options = self.state.settings, self.state.opened, self.user_options
        # (a new material drops an older --shininess: the M key sets shininess to None)
        changes = {name: getattr(s, name) for name in OPTIONS_BY_NAME if getattr(s, name) != getattr(opened, name)}
        if s.camera is not None:
            camera = s.camera
            changes.update(
                camera_position=camera.eye, camera_focal_point=camera.target, camera_view_up=camera.up,
                camera_view_angle=camera.fov_y, camera_direction=None, camera_azimuth=None,
                camera_elevation=None, camera_distance=None,
            )
            if camera.orthographic:
                changes.update(camera_projection="orthographic", camera_ortho_height=camera.view_height())
        return replace(options, **changes) if changes else options

    def panels(self) -> list[Panel]:
        options = self.options()
        if self.compare is None:
            return [Panel(options, "")]
        return [Panel(replace(options, **{self.compare: value}), value) for value in COMPARE_AXES[self.compare]]

    def _scene_for(self, options: ViewOptions) -> Scene:
        if isinstance(self.source, Scene):
            return apply_view_options(self.source, options)
        # Only the options that act when a file is read (the table's `load` ones: size, crease
        # angle, up axis, file or viewer lights) select, and key, the scene read.
        load = options.loading()
        key = tuple(sorted(load.given().items()))
        base = self._loaded.get(key)
        if base is None:
            base = load_source(self.source, load)
            if len(self._loaded) >= LOAD_CACHE_ENTRIES:
                self._loaded.pop(next(iter(self._loaded)))
            self._loaded[key] = base
        return apply_view_options(base, options)

    def scenes(self) -> list[Scene]:
        return [self._scene_for(panel.options) for panel in self.panels()]

    def commands(self) -> list[list[str]]:
        """`wgpu-shading render …` argument lists reproducing each panel exactly."""
        source = "SCENE" if isinstance(self.source, Scene) else self.source
        return [render_command(source, panel.options) for panel in self.panels()]

    # ------------------------------------------------------------------ frames

    def frame(self) -> Frame:
        """The picture shown now (panels side by side with --compare), timed for the title."""
        start = time.perf_counter()
        try:
            scenes = self.scenes()
        except WgpuShadingError as error:
            # A setting the scene refuses (a camera the mouse pushed out of float32's range,
            # a file that no longer reads): say so and go back to the last view that drew.
            self.out(f"wgpu-shading: {error}; back to the last view")
            self.state.settings = self._drawn
            scenes = self.scenes()
        # All panels submitted before the first is read: lavapipe draws one while the next is
        # encoded (each pending frame holds its own target until it is read).
        pending = [self.renderer.submit(scene) for scene in scenes]
        frames = [self.renderer.read(frame) for frame in pending]
        self._drawn = self.state.settings
        self.frame_ms = (time.perf_counter() - start) * 1000.0
        if len(frames) == 1:
            return frames[0]
        return Frame(color=np.ascontiguousarray(np.concatenate([f.color for f in frames], axis=1)))

    def size(self) -> tuple[int, int]:
        """The whole picture's size in pixels (all panels side by side). No key changes it."""
        width, height = self._panel
        return width * len(self.panels()), height

    def title(self) -> str:
        """The window's title: what is shown (`description`) and the last frame's time."""
        parts = [self.description()]
        if self.frame_ms is not None:
            parts.append(f"{self.frame_ms:.1f} ms")
        return " — ".join(parts)

    def description(self) -> str:
        """What is shown: source, frequency, reflection (or the compared variants), material."""
        s = self.state.settings
        source = "scene" if isinstance(self.source, Scene) else self.source
        material = s.material or self.state.scene_material or "file materials"
        parts = [source]
        if self.compare != "frequency":
            parts.append(f"{s.frequency} shading")
        if self.compare != "reflection":
            parts.append(f"{s.reflection} reflection")
        if self.compare:
            parts.append("compare " + " | ".join(COMPARE_AXES[self.compare]))
        parts.append(material)
        return " — ".join(parts)

    # ------------------------------------------------------------------ events

    def handle_event(self, event: dict) -> bool:
        """One rendercanvas event (pointer_down/move/up, wheel, key_down). Returns whether the
        picture changed (the caller asks for a redraw). A move the camera refuses (pushed out
        of float32's range by the wheel, say) is said and left undone."""
        before = self.state.settings
        try:
            return self._handle(event)
        except WgpuShadingError as error:
            self.state.settings = before
            self.out(f"wgpu-shading: {error}; the view stays as it was")
            return False

    def _handle(self, event: dict) -> bool:
        kind = event.get("event_type")
        if kind == "pointer_down":
            self._drag = (event["x"], event["y"], event.get("button", 0))
            return False
        if kind == "pointer_up":
            self._drag = None
            return False
        if kind == "resize":  # the window's size in logical pixels (rendercanvas scales the picture)
            self.shown_size = (float(event["width"]), float(event["height"]))
            return False
        if kind == "pointer_move" and self._drag is not None:
            x0, y0, button = self._drag
            self._drag = (event["x"], event["y"], button)
            # Pointer motion in picture pixels: a window stretched to twice the picture's size
            # turns the view by the same angle for the same fraction of its width.
            width, height = self.size()
            shown_width, shown_height = self.shown_size or (width, height)
            dx = (event["x"] - x0) * width / max(shown_width, 1.0)
            dy = (event["y"] - y0) * height / max(shown_height, 1.0)
            return self.state.drag(button, dx, dy, self._panel)
        if kind == "wheel":
            return self.state.wheel(event.get("dy", 0.0))
        if kind == "key_down":
            return self.press(event.get("key", ""))
        return False

    def press(self, key: str) -> bool:
        """A key: settings keys change the view (True), the others act now (False)."""
        action = self.state.press(key)
        if action == "save":
            self.out(f"wrote {self.save()}")
        elif action == "print":
            for argv in self.commands():
                self.out(_shell_line(argv))
        elif action == "help":
            self.out(help_text())
        elif action == "quit":
            self.closed = True
            self.on_quit()
        return action not in (None, "save", "print", "help", "quit")

    def save(self, folder: str | os.PathLike = ".") -> Path:
        """The current picture as NAME-NNN.png in `folder` (the first free NNN; an existing
        file is never replaced), written completely under a temporary name and then linked
        into place (os.link fails rather than replace a file made meanwhile)."""
        from ..assets.image_writers import write_image

        color = self.frame().color
        folder = Path(folder)
        temporary = folder / f".{self.name}-{os.getpid()}.tmp.png"
        write_image(temporary, color)
        try:
            number = 1
            while True:
                target = folder / f"{self.name}-{number:03d}.png"
                try:
                    os.link(temporary, target)
                    return target
                except FileExistsError:
                    number += 1
        finally:
            temporary.unlink(missing_ok=True)


def _shell_line(argv: list[str]) -> str:
    import shlex

    return " ".join(shlex.quote(part) for part in argv)


__all__ = ["COMPARE_AXES", "LiveView", "Panel"]
