"""Uploads of points and line segments: per-instance vertex buffers (shaders/bindings.py
POINT_ATTRIBUTES, SEGMENT_ATTRIBUTES), apart from the triangles' upload (mesh_uploads.py,
which keeps only the vertices triangles use, in its own order).

Points are vertex ranges of the mesh (scene/geometry/mesh_parts.py): the vertices from the first
point part's first to the last one's end are uploaded as they are, and a part draws the
instances from its first vertex on (`base`). Segments (a mesh's lines, or its triangles'
edges for `--edges`) are uploaded as their two ends, one instance each.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wgpu

from ...scene import Mesh


@dataclass
class GpuPoints:
    positions: object
    normals: object | None
    colors: object | None
    base: int  # the mesh vertex that instance 0 is

    @property
    def nbytes(self) -> int:
        return sum(b.size for b in (self.positions, self.normals, self.colors) if b is not None)


@dataclass
class GpuSegments:
    starts: object
    ends: object
    start_colors: object | None
    end_colors: object | None

    @property
    def nbytes(self) -> int:
        return sum(b.size for b in (self.starts, self.ends, self.start_colors, self.end_colors) if b is not None)


def _buffer(device, array: np.ndarray, extra_usage: int):
    return device.create_buffer_with_data(data=np.ascontiguousarray(array), usage=wgpu.BufferUsage.VERTEX | extra_usage)


def upload_points(device, mesh: Mesh, extra_usage: int) -> GpuPoints:
    """The vertices of every point part (with their normals where some point has one, and
    their colours where the mesh has them)."""
    ranges = [(part.first, part.first + part.count) for part in mesh.parts if part.primitive == "points" and part.count]
    start, stop = min(r[0] for r in ranges), max(r[1] for r in ranges)
    normals = mesh.normals[start:stop]
    return GpuPoints(
        positions=_buffer(device, mesh.positions[start:stop], extra_usage),
        normals=_buffer(device, normals, extra_usage) if any(mesh.has_point_normals(p) for p in mesh.parts) else None,
        colors=None if mesh.colors is None else _buffer(device, mesh.colors[start:stop], extra_usage),
        base=start,
    )


def upload_segments(device, mesh: Mesh, segments: np.ndarray, extra_usage: int, colors: bool = True) -> GpuSegments:
    """Segments (L, 2) of vertex indices of `mesh` as their ends (and the ends' colours,
    with `colors` and vertex colours)."""
    with_colors = colors and mesh.colors is not None
    return GpuSegments(
        starts=_buffer(device, mesh.positions[segments[:, 0]], extra_usage),
        ends=_buffer(device, mesh.positions[segments[:, 1]], extra_usage),
        start_colors=_buffer(device, mesh.colors[segments[:, 0]], extra_usage) if with_colors else None,
        end_colors=_buffer(device, mesh.colors[segments[:, 1]], extra_usage) if with_colors else None,
    )
