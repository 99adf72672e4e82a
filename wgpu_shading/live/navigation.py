"""Mouse navigation as f3d does it (VTK's vtkInteractorStyleTrackballCamera), on a Camera.

f3d hands its mouse to VTK's trackball-camera style; these are that style's rules, so the
view turns by the same amount for the same drag:

- left drag orbits: Azimuth(−dx·200/width) then Elevation(dy·200/height) degrees (VTK's
  Rotate: delta = −20/size × MotionFactor 10; screen y grows downwards, VTK's upwards), the
  view-up turned with it (Camera.orbited follows VTK's Azimuth/Elevation);
- right drag zooms: Dolly(1.1^(10·dy_up/(height/2))), dragging up moves in;
- the wheel zooms: Dolly(1.1^(±2)) a notch (MotionFactor 10 × MouseWheelMotionFactor 0.2);
- middle drag pans: the target point follows the pointer, so eye and target move in the
  view plane by the pixel motion times the world size of a pixel at the target.

Dolly moves the eye towards the target (distance / factor), or shrinks an orthographic
view's height, as VTK's vtkCamera::Dolly / SetParallelScale do.
"""

from __future__ import annotations

import math
from dataclasses import replace

from pyglm import glm

from ..scene.camera import Camera

ORBIT_DEGREES_PER_WINDOW = 200.0  # VTK: 20 / size × MotionFactor 10
DOLLY_BASE = 1.1
DOLLY_MOTION_FACTOR = 10.0
WHEEL_NOTCH = 100.0  # rendercanvas (and the browser) report one wheel notch as dy = ±100
WHEEL_FACTOR = 0.2  # VTK's MouseWheelMotionFactor... × MotionFactor = 2 per notch
MIN_DISTANCE_FRACTION = 1e-6  # dolly never puts the eye on the target (a degenerate camera)
MAX_DOLLY_EXPONENT = 100.0  # one event zooms at most 1.1^100 ≈ 1.4e4 times (no 0 or inf factor)


def orbit(camera: Camera, dx: float, dy: float, size: tuple[int, int]) -> Camera:
    """The camera after a left drag of (dx, dy) pixels (y down) in a `size` window."""
    width, height = size
    azimuth = -dx * ORBIT_DEGREES_PER_WINDOW / width
    elevation = dy * ORBIT_DEGREES_PER_WINDOW / height
    return _orthogonal_up(camera.orbited(azimuth, 0.0).orbited(0.0, elevation))


def drag_zoom_factor(dy: float, size: tuple[int, int]) -> float:
    """The Dolly factor of a right drag of dy pixels (y down): dragging up zooms in."""
    return _factor(DOLLY_MOTION_FACTOR * -dy / (size[1] / 2.0))


def wheel_zoom_factor(dy: float) -> float:
    """The Dolly factor of a wheel event (rendercanvas: dy < 0 when the wheel turns forward,
    which zooms in, as in f3d)."""
    return _factor(DOLLY_MOTION_FACTOR * WHEEL_FACTOR * -dy / WHEEL_NOTCH)


def _factor(exponent: float) -> float:
    return DOLLY_BASE ** min(max(exponent, -MAX_DOLLY_EXPONENT), MAX_DOLLY_EXPONENT)


def dolly(camera: Camera, factor: float) -> Camera:
    """Move the eye towards the target by `factor` (> 1: closer), or, orthographic, shrink
    the view height by it."""
    if camera.orthographic:
        return replace(camera, ortho_height=camera.view_height() / factor)
    eye, target = glm.dvec3(*camera.eye), glm.dvec3(*camera.target)
    offset = eye - target
    distance = glm.length(offset)
    new_distance = max(distance / factor, distance * MIN_DISTANCE_FRACTION)
    return replace(camera, eye=_floats(target + offset * (new_distance / distance)))


def pan(camera: Camera, dx: float, dy: float, size: tuple[int, int]) -> Camera:
    """The camera after a middle drag of (dx, dy) pixels (y down): the point under the
    pointer at the target's depth stays under it."""
    per_pixel = camera.view_height() / size[1]
    right, up, _ = _axes(camera)
    shift = (-dx * per_pixel) * right + (dy * per_pixel) * up
    return replace(
        camera, eye=_floats(glm.dvec3(*camera.eye) + shift), target=_floats(glm.dvec3(*camera.target) + shift)
    )


def _axes(camera: Camera) -> tuple[glm.dvec3, glm.dvec3, glm.dvec3]:
    backward = glm.normalize(glm.dvec3(*camera.eye) - glm.dvec3(*camera.target))
    right = glm.normalize(glm.cross(glm.dvec3(*camera.up), backward))
    return right, glm.cross(backward, right), backward


def _orthogonal_up(camera: Camera) -> Camera:
    """VTK's OrthogonalizeViewUp: the up vector made perpendicular to the view direction
    (unit length), so that the --camera-view-up printed by `P` is the one drawn."""
    _, up, _ = _axes(camera)
    return replace(camera, up=_floats(up))


def _floats(vector) -> tuple[float, float, float]:
    values = tuple(float(v) for v in vector)
    if not all(math.isfinite(v) for v in values):  # pragma: no cover - guarded by Camera too
        raise ValueError(f"camera moved to a non-finite position {values}")
    return values  # type: ignore[return-value]
