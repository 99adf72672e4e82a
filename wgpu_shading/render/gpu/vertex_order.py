"""Triangles and vertices reordered for the vertex stage before upload (same pixels).

llvmpipe/lavapipe shade vertices on one thread and keep a small cache of recently
transformed vertices, so the order of the index buffer decides how often a shared vertex
is transformed again; scans and exported meshes are rarely in a cache-friendly order.
meshoptimizer's `optimize_vertex_cache` (after Forsyth, "Linear-Speed Vertex Cache
Optimisation", 2006; https://github.com/zeux/meshoptimizer#vertex-cache-optimization) reorders the
triangles of each part, then `optimize_vertex_fetch_remap` renumbers the vertices in
first-use order so the vertex fetches walk memory forwards. Measured in
docs/performance.md ("Vertex-cache order"), with meshoptimizer's faster FIFO ordering
tried against it: 4-5x cheaper to make (the bunny 3 against 12-15 ms), but the teapot's
frames 2-10 % slower in every run and the bunny's no faster than the noise; not kept.

What stays the same, so images are bit-identical (tests/test_vertex_order.py):
- every triangle keeps its three corners in their order (winding, and the rasterizer's
  edge setup, are unchanged), and every vertex keeps its attribute values;
- each part keeps its triangle range (first, count), so per-part draws and materials
  are untouched; parts listed in `in_order` (alpha-blended ones, whose triangles blend
  in index order) keep their triangle order as well.
Only which triangle of an opaque part is drawn first changes: with the depth test, that
decides nothing unless two triangles of one part cover a pixel at exactly equal depth.
"""

from __future__ import annotations

import mmap
import threading
import weakref
from dataclasses import dataclass

import numpy as np

from ...scene.freed_memory import return_freed_memory
from .clusters import ClusterTable, cluster_triangles

_UNUSED = np.uint32(0xFFFFFFFF)  # meshoptimizer's remap value for a vertex no triangle uses
_CHUNK = 1 << 16  # vertices or indices handled per step when writing into a GPU buffer


@dataclass(frozen=True)
class VertexOrder:
    """How the uploaded vertices are ordered: kept with the upload so that attributes
    uploaded later (texture coordinates, colors) are reordered the same way."""

    gather: np.ndarray  # uint32: new vertex k is old vertex gather[k] (unused vertices are dropped)
    in_order: frozenset[int]  # the part indices whose triangle order was kept
    clusters: ClusterTable | None = None  # the triangles grouped for leaving out those turned away (clusters.py)

    def vertices(self, array: np.ndarray) -> np.ndarray:
        """A per-vertex array (positions, normals, uvs, colors) in the new vertex order."""
        return np.ascontiguousarray(array[self.gather])

    def write_vertices(self, buffer, array: np.ndarray) -> None:
        """Write `array` in the new vertex order into a buffer mapped at creation, a chunk at
        a time, so no reordered copy of the whole array is ever made."""
        row = array.itemsize * int(np.prod(array.shape[1:]))
        for start in range(0, len(self.gather), _CHUNK):
            buffer.write_mapped(np.ascontiguousarray(array[self.gather[start : start + _CHUNK]]), start * row)


class ScratchIndices:
    """The reordered index buffer, in an anonymous memory map: released to the system as
    soon as it is uploaded (close()), so the upload leaves no freed-but-kept heap behind."""

    def __init__(self, count: int):
        self._map = mmap.mmap(-1, max(4 * count, 1))
        self.array = np.frombuffer(self._map, np.uint32, count)

    def close(self) -> None:
        self.array = None
        try:
            self._map.close()
        except BufferError:  # a view is still alive somewhere: the map goes with it
            pass


def cache_order(
    indices: np.ndarray, vertex_count: int, parts, in_order: frozenset[int] = frozenset(), positions: np.ndarray | None = None
) -> tuple[ScratchIndices, VertexOrder]:
    """Reorder the triangles of every part not in `in_order` for the post-transform vertex
    cache, then the vertices for fetch locality. `parts` are (first, count) triangle ranges
    (MeshPart) covering `indices`. With `positions` (a closed surface: clusters.py), the
    triangles of those parts are then grouped in clusters sorted by direction. Returns the
    new index buffer (flat uint32, in scratch memory: close it after the upload) and the
    vertex order."""
    import meshoptimizer  # imported on first upload: a mesh-less process never pays for it

    flat = np.ascontiguousarray(indices, dtype=np.uint32).reshape(-1)
    scratch = ScratchIndices(flat.size)
    # An order made in an earlier process (order_cache.py); not one with clusters. (Imported
    # on the first upload, as meshoptimizer: a mesh-less process never pays for hashlib.)
    from .order_cache import keep_order, order_key, read_order

    kept = order_key(flat, vertex_count, parts, in_order) if positions is None else None
    if kept is not None:
        gather = read_order(*kept, lambda: scratch.array, flat.size, vertex_count)
        if gather is not None:
            return scratch, VertexOrder(gather=gather, in_order=frozenset(in_order))
    ordered = scratch.array
    ordered[:] = flat
    for number, part in enumerate(parts):
        if number in in_order or part.count < 2 or part.primitive != "triangles":
            continue  # (points and lines have uploads of their own: stroke_uploads.py)
        start, stop = 3 * part.first, 3 * (part.first + part.count)
        optimize_for_cache(ordered[start:stop], flat[start:stop], vertex_count)
    clusters = None if positions is None else cluster_triangles(ordered, positions, parts, frozenset(in_order))
    remap = np.empty(vertex_count, np.uint32)
    used = meshoptimizer.optimize_vertex_fetch_remap(remap, ordered, ordered.size, vertex_count)
    for start in range(0, ordered.size, _CHUNK):  # renumber in place, a chunk at a time
        ordered[start : start + _CHUNK] = remap[ordered[start : start + _CHUNK]]
    referenced = remap != _UNUSED
    gather = np.empty(used, np.uint32)
    gather[remap[referenced]] = np.flatnonzero(referenced)
    del remap, referenced
    if kept is not None:
        keep_order(*kept, ordered, gather)
    if flat.nbytes >= _TRIM_BYTES:
        return_freed_memory()
    return scratch, VertexOrder(gather=gather, in_order=frozenset(in_order), clusters=clusters)


def optimize_for_cache(destination: np.ndarray, indices: np.ndarray, vertex_count: int) -> None:
    """The triangles of `indices` (flat uint32) in vertex-cache order, into `destination`
    (one function, so an A/B can swap the ordering: ab_issue29.py vertex-cache)."""
    import meshoptimizer

    meshoptimizer.optimize_vertex_cache(destination, indices, indices.size, vertex_count)


class SharedOrders:
    """Vertex-cache orders one device computed, for the other devices of the same renderer
    (render_many's helpers) to upload the same mesh without running meshoptimizer again:
    the same order, so every device draws the same triangles in the same order. An entry
    holds a copy of the reordered indices until each sibling has taken it; at most
    SHARED_ORDER_BYTES of them are kept (a bigger mesh is reordered on each device instead,
    so a big upload never costs a second copy of its indices)."""

    def __init__(self, devices: int):
        self.devices = devices  # how many devices upload from this (the renderer's and its helpers')
        # (id(mesh), in_order, with clusters) → [mesh ref, indices, order, left]
        self._entries: dict[tuple[int, frozenset[int], bool], list] = {}
        self._lock = threading.Lock()

    def take(self, mesh, in_order: frozenset[int], clusters: bool = False) -> tuple[np.ndarray, VertexOrder] | None:
        key = (id(mesh), in_order, clusters)
        with self._lock:
            entry = self._entries.get(key)
            if entry is None or entry[0]() is not mesh:  # never offered, or another mesh since
                return None
            entry[3] -= 1
            if entry[3] <= 0:
                del self._entries[key]
            return entry[1], entry[2]

    def offer(self, mesh, in_order: frozenset[int], indices: np.ndarray, order: VertexOrder) -> None:
        if self.devices < 2 or indices.nbytes > SHARED_ORDER_BYTES:
            return
        with self._lock:
            self._entries = {key: entry for key, entry in self._entries.items() if entry[0]() is not None}  # dead meshes
            if sum(entry[1].nbytes for entry in self._entries.values()) + indices.nbytes > SHARED_ORDER_BYTES:
                return
            self._entries[(id(mesh), in_order, order.clusters is not None)] = [weakref.ref(mesh), indices.copy(), order, self.devices - 1]


SHARED_ORDER_BYTES = 64 << 20  # reordered indices kept for sibling devices (a 5M-triangle mesh's)


# meshoptimizer's working arrays for a big mesh (several times its index buffer) are freed
# onto glibc's heap, which keeps them: the process would look a mesh copy bigger after the
# upload than before (tests/test_memory.py measures that). malloc_trim hands them back.
_TRIM_BYTES = 4 << 20
