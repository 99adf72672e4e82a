"""A PLY's `edge` element (`vertex1 vertex2` [`red green blue [alpha]`]), as MeshLab, Open3D
(LineSet), Blender (loose edges) and trimesh write it, drawn as lines (docs/primitives.md).

trimesh turns an `edge` element into a path, which needs scipy and drops the file's faces;
so the header's `element edge` is read by trimesh as `element EDGE` (the same bytes
long: every offset in the file stays), an element trimesh keeps unread in its raw PLY
record, and the segments are built here from that record's columns.
"""

from __future__ import annotations

import io
import re
from pathlib import Path

import numpy as np

from ...errors import MeshError
from ..mesh_pieces import MeshPiece

KEPT_NAME = "EDGE"  # what trimesh reads the `edge` element as (as long as "edge")
_EDGE_DECLARATION = re.compile(rb"(?m)^element[ \t]+(edge)[ \t]")


class _RenamedEdgeFile(io.RawIOBase):
    """A PLY file whose header's `element edge` reads `element EDGE`, read from disk as
    trimesh asks (no copy of the file in memory)."""

    def __init__(self, path: Path, offset: int):
        self._file = open(path, "rb")
        self._offset = offset

    def readable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def seek(self, position: int, whence: int = io.SEEK_SET) -> int:
        return self._file.seek(position, whence)

    def tell(self) -> int:
        return self._file.tell()

    def readinto(self, buffer) -> int:
        start = self._file.tell()
        count = self._file.readinto(buffer)
        low, high = max(start, self._offset), min(start + count, self._offset + len(KEPT_NAME))
        if low < high:
            memoryview(buffer).cast("B")[low - start : high - start] = KEPT_NAME.encode()[low - self._offset : high - self._offset]
        return count

    def close(self) -> None:
        self._file.close()
        super().close()


def renamed_edge_file(path: Path, header_bytes: int) -> io.BufferedReader | None:
    """The file with its `edge` element renamed for trimesh, or None when its header
    (the first header_bytes bytes) declares none."""
    with open(path, "rb") as file:
        head = file.read(header_bytes)
    found = _EDGE_DECLARATION.search(head)
    return None if found is None else io.BufferedReader(_RenamedEdgeFile(path, found.start(1)))


def _column(data, name: str) -> np.ndarray | None:
    """One scalar property of a raw PLY element as trimesh keeps it: a structured array
    (binary) or a dict of (n, 1) columns (ASCII)."""
    names = getattr(getattr(data, "dtype", None), "names", None) or (tuple(data) if isinstance(data, dict) else ())
    if name not in names:
        return None
    return np.asarray(data[name]).reshape(-1)


def _colors(data, count: int) -> np.ndarray | None:
    """An element's red green blue [alpha] as (count, 4) in [0, 1] (integers out of 255), or None."""
    channels = [_column(data, name) for name in ("red", "green", "blue", "alpha")]
    if any(channel is None for channel in channels[:3]):
        return None
    present = [channel for channel in channels if channel is not None]
    colors = np.ones((count, 4))
    for column, channel in enumerate(present):
        colors[:, column] = channel / (255.0 if channel.dtype.kind in "iu" else 1.0)
    return colors


def edge_piece(raw: dict, path: Path) -> MeshPiece | None:
    """The file's edges (trimesh's raw PLY record `raw`) as a piece of lines over the
    file's vertices, in their own colours (red green blue [alpha] on the edge: one per
    segment, unblended), else the vertices' colours; None when the element is empty."""
    data = raw.get(KEPT_NAME, {}).get("data")
    where = f"mesh file {str(path)!r}"
    if data is None or not len(data):
        return None
    vertex = raw.get("vertex", {}).get("data")
    axes = [None if vertex is None else _column(vertex, axis) for axis in "xyz"]
    if any(axis is None for axis in axes):
        raise MeshError(f"{where}: the PLY has edges but no vertex x, y, z for them to join")
    positions = np.stack(axes, axis=1).astype(np.float64)
    ends = [_column(data, "vertex1"), _column(data, "vertex2")]
    if any(end is None for end in ends):
        raise MeshError(f"{where}: the PLY element 'edge' has no 'vertex1' and 'vertex2' properties; edges are read from those")
    segments = np.stack(ends, axis=1)
    declared = raw[KEPT_NAME].get("length", 0)
    if len(segments) < declared:  # an ASCII file cut short (trimesh takes the lines there are)
        raise MeshError(f"{where}: truncated: the header declares {declared} edges, the file holds {len(segments)}")
    if segments.dtype.kind not in "iu" and not np.array_equal(segments, np.round(segments)):  # NaN too
        raise MeshError(f"{where}: a PLY edge's vertex1/vertex2 is not a whole number")
    segments = segments.astype(np.int64)
    low, high = int(segments.min()), int(segments.max())
    if low < 0 or high >= len(positions):
        culprit = low if low < 0 else high
        raise MeshError(f"{where}: an edge refers to vertex {culprit}, but the file has {len(positions)} vertices (valid: 0..{len(positions) - 1})")
    parts = [(0, len(segments), None, f"{path.name} edges")]
    edge_colors = _colors(data, len(segments))
    if edge_colors is None:
        return MeshPiece(positions, segments, colors=_colors(vertex, len(positions)), parts=parts, primitive="lines")
    corners = segments.reshape(-1)  # every end its own vertex (as PLY face colours)
    return MeshPiece(positions[corners], np.arange(len(corners)).reshape(-1, 2), colors=np.repeat(edge_colors, 2, axis=0),
                     parts=parts, primitive="lines")
