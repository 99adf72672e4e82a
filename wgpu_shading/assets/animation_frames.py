"""A glTF file's animation as a sequence of scenes, one per frame (`wgpu-shading animate`;
docs/animation.md): the view `render FILE --animation-time T` draws, at T = start,
start + 1/fps, ... up to the end (included when it falls on a frame), as f3d steps through
an animation at a frame rate (VTK's glTF importer: from 0 to the animation's last keyframe).

Every frame keeps one camera: the bare mesh is framed once, around every pose it takes
(the union of the frames' bounding boxes), so that the model moves in a still picture
instead of the picture following the model. Frames are made when asked for, one at a time,
as `scene/view/turntable.py` makes its views. The file is parsed once (its accessors and
textures decoded once) and posed for each frame; what it says to the user is said once. A
moment at which every object is hidden (scaled to zero, as exporters make objects appear)
is a frame of background, as viewers play it.
"""

from __future__ import annotations

import math
import threading
from dataclasses import replace
from pathlib import Path
from typing import Iterator, Sequence

import numpy as np

from ..errors import MeshError, UsageError
from ..scene.geometry.mesh import Mesh
from ..scene.geometry.vertex_arrays import column_bounds
from ..scene.objects import Scene
from ..scene.view.options import ViewOptions
from .examples import resolve_example
from .meshes import DEFAULT_CREASE_ANGLE, LoadedMesh, loaded_mesh

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
    chooses with animation_index). Safe to index from several threads (one pose at a time)."""

    def __init__(self, source: str, options: ViewOptions, fps: float, start: float | None = None, end: float | None = None):
        from .gltf.animations import animation_duration, chosen_animations
        from .gltf.document import GltfData

        path = Path(resolve_example(str(source)))
        if path.suffix.lower() not in (".gltf", ".glb"):
            raise UsageError(f"{source!r}: only glTF files (.gltf, .glb) hold animations to play")
        if options.animation_time is not None:
            raise UsageError("--animation-time draws one moment; `animate` plays them all (use --start and --end)")
        self._crease_angle = DEFAULT_CREASE_ANGLE if options.crease_angle is None else options.crease_angle
        self._data = GltfData(path)  # the file, parsed once for every frame
        self._lock = threading.Lock()  # the document's caches are filled as frames ask
        self._said: set[str] = set()  # the file's notes, said once for the whole animation
        self.animation = 0 if options.animation_index is None else options.animation_index
        if not self._data.items("animations"):
            raise MeshError(f"mesh file {str(path)!r} has no animations to play")
        indices = chosen_animations(self._data, self.animation)
        self.start = 0.0 if start is None else start
        self.end = animation_duration(self._data, indices) if end is None else end
        self.times = frame_times(self.start, self.end, fps)
        self.source, self.options = str(source), options
        self.framing = None if options.camera_index is not None else self._framing()

    def _pose(self, time: float):
        """The file as the animation poses it at `time` (reader.posed_gltf: a MeshFile)."""
        from .gltf.reader import posed_gltf

        with np.errstate(all="ignore"):  # bad values become MeshErrors, not warnings on stderr
            return posed_gltf(self._data, (time, self.animation))

    def _framing(self) -> Mesh:
        """The corners of the box around every frame's pose (the union of their bounding
        boxes), as points: a flat model (a skinned strip) gives a flat box, which two of its
        sides as triangles could not hold."""
        path = self._data.path
        lower, upper = np.full(3, np.inf), np.full(3, -np.inf)
        with self._lock:
            for time in self.times:
                for piece in self._pose(time).pieces:
                    if piece.element_count:
                        used = piece.positions if piece.primitive == "points" else piece.positions[np.unique(piece.faces)]
                        used_lower, used_upper = column_bounds(used)
                        lower, upper = np.minimum(lower, used_lower), np.maximum(upper, used_upper)
                self._data.notes[:] = dict.fromkeys(self._data.notes)  # each pose says them again: kept once
        if not np.isfinite(lower).all():
            raise MeshError(f"mesh file {str(path)!r}: no frame of the animation from {self.start:g} s to {self.times[-1]:g} s "
                            f"shows anything (every object is hidden, or the file has no triangles, lines or points)")
        corners = np.array([[x, y, z] for x in (lower[0], upper[0]) for y in (lower[1], upper[1]) for z in (lower[2], upper[2])])
        return Mesh.from_arrays(corners, name="the animation's reach")

    def frame_mesh(self, time: float) -> LoadedMesh:
        """The file posed at `time`, read as read_mesh reads it (its notes said once for the
        whole animation); where nothing shows then, the framing box stands in for the mesh
        (shows False: the scene is made around it, then drawn empty)."""
        with self._lock:
            found = self._pose(time)
            if not any(piece.element_count for piece in found.pieces):
                self._data.notes[:] = dict.fromkeys(self._data.notes)  # kept, once each, for a frame that shows
                stand_in = self.framing or Mesh.from_arrays(np.eye(3), name="an empty frame")
                return LoadedMesh(stand_in, found.lights, found.camera, shows=False)
            try:
                return loaded_mesh(found, str(self._data.path), self._data.path.name, self._crease_angle, said=self._said)
            finally:
                self._data.notes.clear()  # said: each pose adds its own again

    def __len__(self) -> int:
        return len(self.times)

    def __getitem__(self, index):
        from .view_loader import load_view

        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self)))]
        time = self.times[index]
        options = replace(self.options, animation_time=time, animation_index=self.animation)
        return load_view(self.source, options, framing=self.framing, loaded=self.frame_mesh(time))

    def __iter__(self) -> Iterator[Scene]:
        for index in range(len(self)):
            yield self[index]

