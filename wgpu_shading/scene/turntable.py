"""Turntables: the same scene seen from a camera (and lights) orbiting the target."""

from __future__ import annotations

import math
from dataclasses import replace

from pyglm import glm

from ..errors import SceneError
from .lights import DirectionalLight, PositionalLight, SpotLight
from .objects import Scene


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


def turntable(scene: Scene, frames: int, degrees: float = 360.0) -> list[Scene]:
    """`frames` views of the scene turning by `degrees` in equal steps (the first is the
    scene itself; a full turn does not repeat the first view at the end, so it loops)."""
    if frames < 1:
        raise SceneError(f"turntable: frames must be at least 1, got {frames}")
    return [scene if i == 0 else spun(scene, degrees * i / frames) for i in range(frames)]


