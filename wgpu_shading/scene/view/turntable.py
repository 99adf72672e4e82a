"""Turntables: the same scene seen from a camera (and lights) orbiting the target."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Iterator, Sequence, overload

from pyglm import glm

from ...errors import SceneError
from ..lights import DirectionalLight, PositionalLight, SpotLight
from ..objects import Scene


def spun(scene: Scene, degrees: float) -> Scene:
    """The scene as if every object were turned by `degrees` about the camera's up axis
    through the camera target (a turntable), with camera and lights left where they are.

    Implemented as the equivalent rigid motion of the viewer: camera and lights orbit by
    −degrees. Objects keep their own transforms, so this works for any scene.
    """
    camera = scene.camera
    rotation = glm.dmat3(glm.rotate(-math.radians(degrees), glm.normalize(glm.dvec3(*camera.up))))
    pivot = glm.dvec3(*camera.target)

    def point(p) -> tuple[float, float, float]:
        return tuple(rotation * (glm.dvec3(*p) - pivot) + pivot)

    def direction(d) -> tuple[float, float, float]:
        return tuple(rotation * glm.dvec3(*d))

    lights = []
    for light in scene.lights:
        if isinstance(light, DirectionalLight):
            lights.append(replace(light, direction=direction(light.direction)))
        elif isinstance(light, SpotLight):
            lights.append(replace(light, position=point(light.position), direction=direction(light.direction)))
        elif isinstance(light, PositionalLight):
            lights.append(replace(light, position=point(light.position)))
        else:  # pragma: no cover - Scene validates its lights
            raise SceneError(f"cannot turn a {type(light).__name__}")
    return replace(scene, camera=replace(camera, eye=point(camera.eye)), lights=tuple(lights))


class Turntable(Sequence[Scene]):
    """`frames` views of a scene turning by `degrees` in equal steps, made on demand: a
    sequence of a hundred million frames costs nothing until a frame is asked for, and
    iterating it (render_many does) holds one view at a time."""

    def __init__(self, scene: Scene, frames: int, degrees: float = 360.0):
        if isinstance(frames, bool) or not isinstance(frames, int) or frames < 1:
            raise SceneError(f"turntable: frames must be at least 1, got {frames!r}")
        if isinstance(degrees, bool) or not isinstance(degrees, (int, float)) or not math.isfinite(degrees):
            raise SceneError(f"turntable: degrees must be a finite number, got {degrees!r}")
        self.scene, self.frames, self.degrees = scene, frames, float(degrees)

    def __len__(self) -> int:
        return self.frames

    @overload
    def __getitem__(self, index: int) -> Scene: ...
    @overload
    def __getitem__(self, index: slice) -> list[Scene]: ...
    def __getitem__(self, index):
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(self.frames))]
        if index < 0:
            index += self.frames
        if not 0 <= index < self.frames:
            raise IndexError(f"turntable frame {index} of {self.frames}")
        return self.scene if index == 0 else spun(self.scene, self.degrees * index / self.frames)

    def __iter__(self) -> Iterator[Scene]:
        for index in range(self.frames):
            yield self[index]


def turntable(scene: Scene, frames: int, degrees: float = 360.0) -> Turntable:
    """`frames` views of the scene turning by `degrees` in equal steps (the first is the
    scene itself; a full turn does not repeat the first view at the end, so it loops).
    The views are made lazily, as they are used (see Turntable)."""
    return Turntable(scene, frames, degrees)
