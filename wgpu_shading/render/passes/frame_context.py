"""What a pass is to a frame: the interface every pass of a frame has (`FramePass`) and what
the passes of one frame share while they are encoded (`FrameContext`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
from pyglm import glm

from ...scene import Scene
from ..gpu.device_cache import DeviceCache
from ..gpu.targets import Target


@dataclass
class FrameContext:
    """The scene of one frame and what its passes hand on to each other."""

    scene: Scene
    eye_from_world: glm.dmat4  # the camera's view matrix in double precision, once per frame
    # Resources a pass made for later passes of the frame, by the binding name under which
    # later pipelines' plans bind them (a shadow map and its comparison sampler, say).
    bound: dict[str, object] = field(default_factory=dict)

    @classmethod
    def of(cls, scene: Scene) -> "FrameContext":
        return cls(scene, glm.dmat4(scene.camera.eye_from_world()))


class FramePass(Protocol):
    """One pass of a frame. The Renderer takes each pass's target (None: the pass keeps its
    own, e.g. a shadow map in the device cache), encodes the passes in order into one
    command buffer, and once the GPU is done reads each pass's outputs into the Frame."""

    def take_target(self, cache: DeviceCache, scene: Scene) -> Target | None:
        """A target lent for this frame (given back once it is read)."""

    def encode(self, cache: DeviceCache, encoder, frame: FrameContext, target: Target | None) -> None:
        """Record the pass (and the copies into its readback buffers)."""

    def read(self, target: Target | None, scene: Scene) -> dict[str, np.ndarray | None]:
        """The pass's outputs, by Frame field ("color", "depth", "normals", "ids"); {} for none."""
