"""Mesh uploads: positions, normals and indices in GPU buffers (in vertex-cache order,
vertex_order.py), and the optional attributes (uvs, colors, tangents) once a draw needs them."""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import numpy as np
import wgpu

from ...scene import Mesh
from .caches import BIND_GROUP_CACHE_ENTRIES, LruCache
from .cluster_builds import BuiltOrder, ClusterBuild
from .clusters import CLUSTER_MAX_TRIANGLES, CLUSTER_MIN_TRIANGLES, CLUSTERS_AFTER_FRAMES
from .vertex_order import SharedOrders, VertexOrder, cache_order


@dataclass
class GpuMesh:
    """A mesh's GPU buffers (positions, normals, indices; uvs and colours when a plan binds
    them), in its vertex-cache order, with its clusters once they are built."""

    positions: object
    normals: object
    indices: object
    uvs: object | None
    triangle_count: int
    colors: object | None = None
    tangents: object | None = None
    # the mesh's other texture coordinate sets (Mesh.extra_uvs[:, k − 1] as uv_set_k), once a draw reads them
    uv_set_1: object | None = None
    uv_set_2: object | None = None
    uv_set_3: object | None = None
    # flat shading's vertex-pulling bind groups (one per layout: a handful)
    storage_groups: LruCache = field(default_factory=lambda: LruCache(BIND_GROUP_CACHE_ENTRIES))
    # the vertex-cache order the buffers hold (render/gpu/vertex_order.py); None: the mesh's own
    order: VertexOrder | None = None
    # frames since the upload that could have left out clusters it does not have
    # (asks_for_clusters); -1: the mesh does not qualify, not counted again
    cluster_asks: int = 0
    # the build of its clusters, once asked for and until a frame applies it (cluster_builds.py)
    cluster_build: ClusterBuild | None = None

    @property
    def nbytes(self) -> int:
        buffers = (self.positions, self.normals, self.indices, self.uvs, self.colors, self.tangents, self.uv_set_1, self.uv_set_2, self.uv_set_3)
        return sum(b.size for b in buffers if b is not None)

def vertex_order_enabled() -> bool:
    """Meshes are uploaded in vertex-cache order unless WGPU_SHADING_VERTEX_ORDER=0 (for
    A/B measurements and the test that the pixels do not change)."""
    return os.environ.get("WGPU_SHADING_VERTEX_ORDER", "1") != "0"


def clusters_enabled() -> bool:
    """WGPU_SHADING_CLUSTERS=0 draws every triangle of every frame from then on (read per
    frame: the A/B of benchmarks/depth.py and of the test that the pixels do not change)."""
    return os.environ.get("WGPU_SHADING_CLUSTERS", "1") != "0"


def asks_for_clusters(gpu_mesh: GpuMesh, mesh: Mesh) -> bool:
    """A frame that could leave out the triangles turned away (passes/turned_away.py) asks
    the upload for its clusters (clusters.py). True when their build should start (on the
    renderer's worker: cluster_builds.py, which checks that the mesh is a closed surface
    wound counter-clockwise from outside): at the CLUSTERS_AFTER_FRAMES-th such frame after
    the one that uploaded it, for a mesh big enough to pay (WGPU_SHADING_CLUSTERS=0 turns
    them off). The build (the closed-surface check, the clusters, the upload again) costs
    the 1.3M-triangle sphere ~1.7 s CPU, what ~25 of its frames then save
    (docs/performance.md): waiting 16 frames first keeps a mesh drawn a few times (a
    dataset's views) from paying for them."""
    if _never_asked_again(gpu_mesh) or gpu_mesh.cluster_build is not None:
        return False
    gpu_mesh.cluster_asks += 1
    if gpu_mesh.cluster_asks < CLUSTERS_AFTER_FRAMES:
        return False
    wanted = _clusters_pay(mesh)
    gpu_mesh.cluster_asks = gpu_mesh.cluster_asks if wanted else -1
    return wanted


def clusters_settled(gpu_mesh: GpuMesh, mesh: Mesh) -> bool:
    """True when no later frame's ask (asks_for_clusters) can change this upload: its
    clusters are built, or will never be, and no build is running. A frame plan
    (frame_plans.py) is kept only for frames whose uploads are settled, since a frame drawn
    from a plan asks nothing."""
    if gpu_mesh.cluster_build is not None:
        return False
    return _never_asked_again(gpu_mesh) or not _clusters_pay(mesh)


def _never_asked_again(gpu_mesh: GpuMesh) -> bool:
    """The upload has no order to cluster, has its clusters, or was found not to want them."""
    return gpu_mesh.order is None or gpu_mesh.order.clusters is not None or gpu_mesh.cluster_asks < 0


def _clusters_pay(mesh: Mesh) -> bool:
    """A mesh big enough to repay its clusters and small enough to build them, clusters switched on."""
    return CLUSTER_MIN_TRIANGLES <= mesh.triangle_count <= CLUSTER_MAX_TRIANGLES and clusters_enabled()


def upload_mesh(
    device, mesh: Mesh, extra_usage: int, in_order: frozenset[int] = frozenset(), shared: SharedOrders | None = None,
    built: BuiltOrder | None = None,
) -> GpuMesh:
    """Positions, normals and indices of `mesh` in GPU buffers. One upload serves every
    frequency: vertex buffers for Gouraud/Phong, storage buffers for flat shading's vertex
    pulling. `extra_usage` is MAP_WRITE where the device writes such buffers in place.

    The triangles of every part not in `in_order` (the alpha-blended parts) are uploaded in
    vertex-cache order, and the vertices in first-use order (render/gpu/vertex_order.py: same
    pixels, less vertex work). The vertices are written into their buffers in the new order
    a chunk at a time, and the reordered indices live in scratch memory that is handed back
    right after their upload: the upload still leaves one copy of the mesh (the driver's).
    `shared`: the order another device of the same renderer computed for this mesh is used
    as it is, and the one computed here is offered to the others (vertex_order.SharedOrders).
    `built`: the order (with the triangles of those parts grouped in clusters: clusters.py)
    a cluster build made (cluster_builds.py), uploaded as it is; the caller releases it."""
    usage = wgpu.BufferUsage.VERTEX | wgpu.BufferUsage.STORAGE | extra_usage
    index_usage = wgpu.BufferUsage.INDEX | wgpu.BufferUsage.STORAGE | extra_usage
    if not vertex_order_enabled():
        return GpuMesh(
            positions=device.create_buffer_with_data(data=mesh.positions, usage=usage),
            normals=device.create_buffer_with_data(data=mesh.normals, usage=wgpu.BufferUsage.VERTEX | extra_usage),
            indices=device.create_buffer_with_data(data=mesh.indices, usage=index_usage),
            uvs=None,
            triangle_count=mesh.triangle_count,
        )
    taken = (built.indices, built.order) if built is not None else shared.take(mesh, in_order) if shared is not None else None
    if taken is not None:
        reordered, order = taken
        indices = device.create_buffer_with_data(data=reordered, usage=index_usage)
    else:
        scratch, order = cache_order(mesh.indices, mesh.vertex_count, mesh.parts, in_order)
        try:
            indices = device.create_buffer_with_data(data=scratch.array, usage=index_usage)
            if shared is not None:
                shared.offer(mesh, in_order, scratch.array, order)
        finally:
            scratch.close()
    return GpuMesh(
        positions=_reordered_buffer(device, mesh.positions, order, usage),
        normals=_reordered_buffer(device, mesh.normals, order, wgpu.BufferUsage.VERTEX | extra_usage),
        indices=indices,
        uvs=None,
        triangle_count=mesh.triangle_count,
        order=order,
    )

def _reordered_buffer(device, array: np.ndarray, order: VertexOrder | None, usage: int):
    """A buffer holding `array` (per-vertex rows) in the upload's vertex order."""
    if order is None:
        return device.create_buffer_with_data(data=array, usage=usage)
    row_bytes = array.itemsize * int(np.prod(array.shape[1:]))
    buffer = device.create_buffer(size=(len(order.gather) * row_bytes + 3) & ~3, usage=usage, mapped_at_creation=True)
    order.write_vertices(buffer, array)
    buffer.unmap()
    return buffer


# The per-vertex arrays a draw may need besides positions and normals: GpuMesh and Mesh
# attributes of these names (the binding plan's VertexAttribute names).
OPTIONAL_ATTRIBUTES = ("uvs", "colors", "tangents", "uv_set_1", "uv_set_2", "uv_set_3")


def upload_attribute(device, gpu_mesh: GpuMesh, mesh: Mesh, name: str, extra_usage: int) -> None:
    """The mesh's `name` array (uvs, float32 RGBA colors, a file's float32 xyzw tangents),
    uploaded only once a draw needs it: most meshes are drawn untextured, and a big mesh's
    uvs are a seventh of its memory."""
    if name.startswith("uv_set_"):  # set k of the mesh's other texture coordinates
        k = int(name.rpartition("_")[2])
        values = None if mesh.extra_uvs is None or mesh.extra_uvs.shape[1] < k else np.ascontiguousarray(mesh.extra_uvs[:, k - 1])
    else:
        values = getattr(mesh, name)
    if getattr(gpu_mesh, name) is None and values is not None:
        usage = wgpu.BufferUsage.VERTEX | wgpu.BufferUsage.STORAGE | extra_usage
        setattr(gpu_mesh, name, _reordered_buffer(device, values, gpu_mesh.order, usage))
