"""A frame is the list of passes it calls for, encoded in order into one command buffer.

The shadow maps (when the scene has shadows, before the colour pass that samples them: its
`encode` puts the maps into `FrameContext.bound`), the colour pass (when the colour or
depth image is asked for) and the normals-and-ids pass of datasets (when normals or ids
are). Only what a frame calls for runs: without the feature, no pass and no code.
"""

from __future__ import annotations

from ...scene import Scene, has_shadows
from .color import ColorPass
from .frame_context import FramePass


def frame_passes(
    scene: Scene, *, color_format: str = "rgba8", color: bool = True, depth: bool = False,
    normals: str | None = None, ids: bool = False,
) -> list[FramePass]:
    """The passes of one frame of `scene`, in the order they run."""
    passes: list[FramePass] = []
    if (color or depth) and has_shadows(scene):
        from .shadow import ShadowPass  # imported by the scenes that have shadows (cold start)

        passes.append(ShadowPass())  # the maps the colour pass reads
    if color or depth:
        passes.append(ColorPass(color_format, read_depth=depth))
    if normals is not None or ids:
        from .extra_outputs import ExtraOutputsPass  # imported by the frames that ask for it (cold start)

        passes.append(ExtraOutputsPass(normals or "eye"))
    return passes
