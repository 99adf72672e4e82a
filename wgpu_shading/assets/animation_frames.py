"""A glTF file's animation as a sequence of scenes, one per frame (`wgpu-shading animate`;
docs/animation.md): the view `render FILE --animation-time T` draws, at T = start,
start + 1/fps, ... up to the end (included when it falls on a frame), as f3d steps through
an animation at a frame rate (VTK's glTF importer: from 0 to the animation's last keyframe).

Every frame keeps one camera: the bare mesh is framed once, around every pose it takes
(the union of the frames' bounding boxes), so that the model moves in a still picture
instead of the picture following the model. Frames are made when asked for, one at a time,
as `scene/view/turntable.py` makes its views.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import Iterator, Sequence

import numpy as np

from ..errors import MeshError, UsageError
from ..scene.mesh import Mesh
from ..scene.objects import Scene
from ..scene.view.options import ViewOptions
from .examples import resolve_example

MAX_FRAMES = 100_000  # an hour at 30 fps; frames beyond are surely a typo in --fps or --end


def frame_times(start: float, end: float, fps: float) -> list[float]:
    """start, start + 1/fps, ... while <= end (the end itself when it falls on a frame, to
    1e-9 of a frame); one frame when end <= start."""
    count = max(int(math.floor((end - start) * fps + 1e-9)) + 1, 1)
    if count > MAX_FRAMES:
        raise UsageError(f"{count} frames from {start:g} s to {end:g} s at {fps:g} fps; at most {MAX_FRAMES} are made")
    return [start + k / fps for k in range(count)]


class AnimationFrames(Sequence[Scene]):
    """The scenes of a glTF file's animation at `fps` frames per second: from `start`
    (default 0) to `end` (default the last keyframe of the animation(s) `options`
    chooses with animation_index)."""

    def __init__(self, source: str, options: ViewOptions, fps: float, start: float | None = None, end: float | None = None):
        from .gltf.animations import animation_duration, chosen_animations
        from .gltf.document import GltfData

        path = Path(resolve_example(str(source)))
        if path.suffix.lower() not in (".gltf", ".glb"):
            raise UsageError(f"{source!r}: only glTF files (.gltf, .glb) hold animations to play")
        if options.animation_time is not None:
            raise UsageError("--animation-time draws one moment; `animate` plays them all (use --start and --end)")
        data = GltfData(path)
        self.animation = 0 if options.animation_index is None else options.animation_index
        if not data.items("animations"):
            raise MeshError(f"mesh file {str(path)!r} has no animations to play")
        indices = chosen_animations(data, self.animation)
        self.start = 0.0 if start is None else start
        self.end = animation_duration(data, indices) if end is None else end
        self.times = frame_times(self.start, self.end, fps)
        self.source, self.options = str(source), options
        self.framing = None if options.camera_index is not None else self._framing(data)

    def _framing(self, data) -> Mesh:
        """A mesh holding the corners of the box around every frame's pose (the file parsed once)."""
        from .gltf.animations import posed_nodes
        from .gltf.reader import gltf_mesh_pieces

        path = data.path
        lower, upper = np.full(3, np.inf), np.full(3, -np.inf)
        for time in self.times:
            pieces, _ = gltf_mesh_pieces(data, posed_nodes(data, time, self.animation))
            for piece in pieces:
                if len(piece.faces):
                    used = piece.positions[np.unique(piece.faces)]
                    lower, upper = np.minimum(lower, used.min(axis=0)), np.maximum(upper, used.max(axis=0))
        if not np.isfinite(lower).all():
            raise MeshError(f"mesh file {str(path)!r} contains no triangles")
        corners = np.array([[x, y, z] for x in (lower[0], upper[0]) for y in (lower[1], upper[1]) for z in (lower[2], upper[2])])
        return Mesh.from_arrays(corners, np.array([[0, 1, 3], [0, 3, 2]]), name="the animation's reach")

    def __len__(self) -> int:
        return len(self.times)

    def __getitem__(self, index):
        from .view_loader import load_view

        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self)))]
        time = self.times[index]
        options = replace(self.options, animation_time=time, animation_index=self.animation)
        return load_view(self.source, options, framing=self.framing)

    def __iter__(self) -> Iterator[Scene]:
        for index in range(len(self)):
            yield self[index]
