"""What a live view shows, and how the keys and the mouse change it: pure logic, no window.

A ViewState is the view's settings: its view options (scene/view/options.py: the ones
`render` takes, which the keys change: frequency, reflection, material, shininess, crease
angle, two-sided, samples, shadows) and the camera the mouse moved. Every key of the viewer is a transition of it
(`press`), every drag or wheel turn a camera move (`drag`, `wheel`); the window, the
notebook widget and the tests drive the same object. The scene drawn and the `render`
command printed are both made from the settings (viewer.py), never from each other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..scene import FREQUENCIES, MATERIALS, REFLECTIONS, Scene
from ..scene.camera import Camera
from ..scene.view.apply import scene_value
from ..scene.view.options import OPTIONS_BY_NAME, ViewOptions
from . import navigation

CREASE_ANGLES = (0.0, 30.0, 60.0, 180.0)  # the `C` key's cycle, degrees
SHININESS_STEP = math.sqrt(2.0)  # `[` / `]`: half an octave of the exponent per press
MIN_SHININESS, MAX_SHININESS = 0.5, 4096.0
SAMPLE_CYCLE = (1, 4)

# key → (action, what it does): the `H` key prints this table; docs/viewer.md lists it too.
KEYS: dict[str, tuple[str, str]] = {
    "f": ("frequency", "shading frequency: flat → Gouraud → Phong"),
    "b": ("reflection", "reflection model: Phong ↔ Blinn-Phong"),
    "m": ("material", "next material of the table (`wgpu-shading materials`)"),
    "[": ("shininess_down", "shininess down (÷√2)"),
    "]": ("shininess_up", "shininess up (×√2)"),
    "c": ("crease", "crease angle: 0 → 30 → 60 → 180 degrees (mesh files without normals)"),
    "t": ("two_sided", "two-sided lighting on/off"),
    "e": ("edges", "the triangles' edges over the surfaces on/off (f3d's E key)"),
    "a": ("samples", "antialiasing: 1 ↔ 4 samples"),
    "d": ("shadows", "shadows on/off: every light casts"),
    "enter": ("reset", "reset the camera"),
    "s": ("save", "save a screenshot NAME-NNN.png in the current folder"),
    "p": ("print", "print the `wgpu-shading render` command of this view"),
    "h": ("help", "print these keys"),
    "q": ("quit", "quit"),
    "escape": ("quit", "quit"),
}
MOUSE_HELP = (
    "left drag: orbit · right drag or wheel: zoom · middle drag: pan (as in f3d)"
)


@dataclass(frozen=True)
class Settings(ViewOptions):
    """One view: every view option (None: as the scene has it, e.g. the file's materials,
    its normals) and the camera the mouse moved (None: the one `render` places)."""

    camera: Camera | None = None


# Options whose keys step from the value the scene has, so the settings hold it from the start.
SCENE_VALUED = ("frequency", "reflection", "two_sided", "edges", "samples", "shadows")


def opening_settings(options: ViewOptions, scene: Scene) -> Settings:
    """The settings of a view opened with `options`, which drew `scene`."""
    values = options.given()
    values.update({name: scene_value(scene, OPTIONS_BY_NAME[name]) for name in SCENE_VALUED})
    return Settings(**values)


def key_name(key: str) -> str:
    """rendercanvas's key names ("f", "F", "Enter", "Escape", "[") as the KEYS table spells them."""
    return key.lower()


def help_text() -> str:
    lines = ["keys:"]
    for key, (_, text) in KEYS.items():
        lines.append(f"  {key.upper() if len(key) == 1 else key.capitalize():7} {text}")
    lines.append("mouse: " + MOUSE_HELP)
    return "\n".join(lines)


class ViewState:
    """The settings of a live view and their transitions.

    `opened` is the view as it opens (render's picture with the same options); `camera` is
    the camera that view's scene has (what Enter goes back to); `shininess` the material's
    shininess when no override is set (where `[`/`]` start from); `material` the name of the
    scene's material when it is one of the table (where `M` starts from)."""

    def __init__(self, opened: Settings, camera: Camera, *, shininess: float = 51.2, material: str | None = None):
        self.opened = opened
        self.settings = opened
        self.home_camera = camera
        self.scene_shininess = shininess
        self.scene_material = material

    # ------------------------------------------------------------------ keys

    def press(self, key: str) -> str | None:
        """Apply a key; returns its action name (KEYS), or None for a key that does nothing.
        Actions that are not transitions of the settings (save, print, help, quit) are
        only named: the viewer carries them out."""
        entry = KEYS.get(key_name(key))
        if entry is None:
            return None
        action = entry[0]
        change = getattr(self, f"_key_{action}", None)
        if change is not None:
            self.settings = change(self.settings)
        return action

    @staticmethod
    def _key_frequency(s: Settings) -> Settings:
        return replace(s, frequency=_next(FREQUENCIES, s.frequency))

    @staticmethod
    def _key_reflection(s: Settings) -> Settings:
        return replace(s, reflection="blinn-phong" if s.reflection == "phong" else "phong")

    def _key_material(self, s: Settings) -> Settings:
        names = list(MATERIALS)
        current = s.material or self.scene_material
        following = names[(names.index(current) + 1) % len(names)] if current in names else names[0]
        # A new material brings its own shininess: an override set before would hide it.
        return replace(s, material=following, shininess=None)

    def _current_shininess(self, s: Settings) -> float:
        if s.shininess is not None:
            return s.shininess
        if s.material is not None:
            return MATERIALS[s.material].shininess
        return self.scene_shininess

    def _key_shininess_up(self, s: Settings) -> Settings:
        return replace(s, shininess=min(max(self._current_shininess(s), 1.0) * SHININESS_STEP, MAX_SHININESS))

    def _key_shininess_down(self, s: Settings) -> Settings:
        return replace(s, shininess=max(self._current_shininess(s) / SHININESS_STEP, MIN_SHININESS))

    @staticmethod
    def _key_crease(s: Settings) -> Settings:
        # From "the file's normals / the default" the cycle starts after the default 60.
        current = 60.0 if s.crease_angle is None else s.crease_angle
        return replace(s, crease_angle=_next(CREASE_ANGLES, current))

    @staticmethod
    def _key_two_sided(s: Settings) -> Settings:
        return replace(s, two_sided=not s.two_sided)

    @staticmethod
    def _key_edges(s: Settings) -> Settings:
        return replace(s, edges=not s.edges)

    @staticmethod
    def _key_samples(s: Settings) -> Settings:
        return replace(s, samples=_next(SAMPLE_CYCLE, s.samples))

    @staticmethod
    def _key_shadows(s: Settings) -> Settings:
        # From a scene where some lights cast (None) the first press makes every light cast.
        return replace(s, shadows=not s.shadows)

    def _key_reset(self, s: Settings) -> Settings:
        return replace(s, camera=self.opened.camera)

    # ------------------------------------------------------------------ mouse

    @property
    def camera(self) -> Camera:
        return self.settings.camera or self.home_camera

    def drag(self, button: int, dx: float, dy: float, size: tuple[int, int]) -> bool:
        """A drag of (dx, dy) pixels with `button` held (1 left: orbit, 2 right: zoom,
        3 middle: pan; rendercanvas's numbers). Returns whether the camera moved."""
        if not (dx or dy):
            return False
        if button == 1:
            camera = navigation.orbit(self.camera, dx, dy, size)
        elif button == 2:
            camera = navigation.dolly(self.camera, navigation.drag_zoom_factor(dy, size))
        elif button == 3:
            camera = navigation.pan(self.camera, dx, dy, size)
        else:
            return False
        self.settings = replace(self.settings, camera=camera)
        return True

    def wheel(self, dy: float) -> bool:
        if not dy:
            return False
        camera = navigation.dolly(self.camera, navigation.wheel_zoom_factor(dy))
        self.settings = replace(self.settings, camera=camera)
        return True


def _next(cycle, current):
    return cycle[(cycle.index(current) + 1) % len(cycle)] if current in cycle else cycle[0]


__all__ = ["CREASE_ANGLES", "KEYS", "REFLECTIONS", "Settings", "ViewState", "help_text", "key_name", "opening_settings"]
