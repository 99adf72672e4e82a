"""The lights a bare mesh gets: a key light plus a headlight fill, as model viewers do.

A single light leaves the side away from it black (ambient alone is 0.2 × the material's
ambient: 12/255 for gold), which hides the shape. Viewers add light from the camera: f3d
(VTK's light kit) uses a key light 50° above the view plus a fill, back lights and a
headlight of a third of the key. Two directional lights give most of that here:

- key: white, from 45° above and 30° to the right of the view direction; diffuse 0.8,
  specular 1 (the one highlight);
- headlight fill: along the view direction, diffuse 0.35, no specular (a second highlight
  in the middle of every sphere looks wrong), so every surface the camera sees is lit.

Both are placed relative to the camera, so they must be made for the final camera
(after the command line moved it). Measured in tests/test_viewer_lighting.py: on the
built-in and sample meshes, under 5 % of the covered pixels are darker than 32/255.
"""

from __future__ import annotations

import math

from pyglm import glm

from ..camera import Camera
from ..lights import DirectionalLight

KEY_ELEVATION = 45.0  # degrees above the view direction
KEY_AZIMUTH = 30.0  # degrees to the right
KEY_DIFFUSE = (0.7, 0.7, 0.7, 1.0)
KEY_SPECULAR = (1.0, 1.0, 1.0, 1.0)
HEADLIGHT_DIFFUSE = (0.5, 0.5, 0.5, 1.0)


def camera_axes(camera: Camera) -> tuple[glm.dvec3, glm.dvec3, glm.dvec3]:
    """World-space right, up and backward (towards the viewer) unit vectors of the camera."""
    backward = glm.normalize(glm.dvec3(*camera.eye) - glm.dvec3(*camera.target))
    right = glm.normalize(glm.cross(glm.dvec3(*camera.up), backward))
    return right, glm.cross(backward, right), backward


def headlight(camera: Camera, diffuse=HEADLIGHT_DIFFUSE, specular=(0.0, 0.0, 0.0, 1.0)) -> DirectionalLight:
    """A directional light travelling along the view direction (from the eye)."""
    _, _, backward = camera_axes(camera)
    return DirectionalLight(direction=tuple(-backward), diffuse=diffuse, specular=specular)


def key_light(camera: Camera) -> DirectionalLight:
    right, up, backward = camera_axes(camera)
    elevation, azimuth = math.radians(KEY_ELEVATION), math.radians(KEY_AZIMUTH)
    to_light = math.cos(elevation) * (math.sin(azimuth) * right + math.cos(azimuth) * backward) + math.sin(elevation) * up
    return DirectionalLight(direction=tuple(-to_light), diffuse=KEY_DIFFUSE, specular=KEY_SPECULAR)


def viewer_lights(camera: Camera) -> tuple[DirectionalLight, DirectionalLight]:
    """The default lights of a bare mesh seen by `camera`: key light and headlight fill."""
    return key_light(camera), headlight(camera)
