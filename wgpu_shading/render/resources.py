"""GPU resources that outlive a frame: render targets with their readback buffers, mesh
and texture uploads, and reading a mapped buffer back into numpy."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

import numpy as np
import wgpu

from ..errors import SceneError
from ..scene import Mesh, Texture
from .caches import BIND_GROUP_CACHE_ENTRIES, LruCache
from .pipeline_cache import COLOR_FORMATS, DEPTH_FORMAT
from .vertex_order import VertexOrder, cache_order

BYTES_PER_PIXEL = {"rgba8": 4, "float32": 16}
_ROW_ALIGNMENT = 256  # WebGPU's required bytes_per_row multiple for texture copies


@dataclass
class GpuMesh:
    positions: object
    normals: object
    indices: object
    uvs: object | None
    triangle_count: int
    colors: object | None = None
    tangents: object | None = None
    # flat shading's vertex-pulling bind groups (one per layout: a handful)
    storage_groups: LruCache = field(default_factory=lambda: LruCache(BIND_GROUP_CACHE_ENTRIES))
    # the vertex-cache order the buffers hold (render/vertex_order.py); None: the mesh's own
    order: VertexOrder | None = None

    @property
    def nbytes(self) -> int:
        buffers = (self.positions, self.normals, self.indices, self.uvs, self.colors, self.tangents)
        return sum(b.size for b in buffers if b is not None)


@dataclass
class GpuTexture:
    texture: object
    view: object
    nbytes: int = 0
    # object bind groups that bind this view (one per object uniform buffer and layout)
    object_groups: LruCache = field(default_factory=lambda: LruCache(BIND_GROUP_CACHE_ENTRIES))


@dataclass
class Target:
    width: int
    height: int
    color_format: str
    color: object
    color_view: object
    depth: object
    depth_view: object
    color_readback: object
    depth_readback: object
    color_row_bytes: int
    depth_row_bytes: int
    # MSAA (samples > 1): the multisampled attachments drawn into; `color` is then their
    # resolve target (what is read back) and `depth` the single-sample depth of a second,
    # depth-only-use pass, drawn when depth is read (multisampled depth cannot be copied).
    samples: int = 1
    msaa_color_view: object = None
    msaa_depth_view: object = None


def padded_row_bytes(width: int, bytes_per_pixel: int) -> int:
    return math.ceil(width * bytes_per_pixel / _ROW_ALIGNMENT) * _ROW_ALIGNMENT


def map_for_reading(buffer) -> None:
    """map_sync(READ) without wgpu-py's extra empty submit.

    wgpu-py 0.32 submits an empty command buffer before every read-mapping, a work-around
    for wgpu-native#305, which concerns buffers written through the mapping API. Readback
    buffers are only written by copy commands already submitted, so that submit only adds
    a round trip to the driver (~0.7 ms a frame on lavapipe, measured); wgpu-py's own
    "READ_NOSYNC" mode skips it. Falls back to the public mode if a wgpu-py lacks it.
    """
    try:
        buffer.map_sync("READ_NOSYNC")
    except (ValueError, KeyError, TypeError):
        buffer.map_sync(wgpu.MapMode.READ)


def halved(level: np.ndarray) -> np.ndarray:
    """The next mip level of a (height, width, 4) float level: 2×2 box filter, an odd last
    row or column repeated so that it is averaged with itself."""
    height, width = level.shape[:2]
    if height % 2:
        level = np.concatenate([level, level[-1:]], axis=0)
    if width % 2:
        level = np.concatenate([level, level[:, -1:]], axis=1)
    level = level.reshape(level.shape[0] // 2, 2, level.shape[1] // 2, 2, 4).mean(axis=(1, 3))
    return level[: max(1, height // 2), : max(1, width // 2)]


def mip_chain(pixels: np.ndarray) -> list[np.ndarray]:
    """Box-filtered mip levels down to 1×1 (texture values are used as linear, like the seeds)."""
    levels = [pixels]
    if pixels.shape[0] == 1 and pixels.shape[1] == 1:
        return levels
    current = _first_level(pixels)
    levels.append(np.round(current).astype(np.uint8))
    while current.shape[0] > 1 or current.shape[1] > 1:
        current = halved(current)
        levels.append(np.round(current).astype(np.uint8))
    return levels



def _first_level(pixels: np.ndarray, rows_per_strip: int = 512) -> np.ndarray:
    """The first mip level's exact float32 means, computed a strip of rows at a time: a
    16384² texture in float32 would take 4 GiB at once. (Means of four 8-bit values are
    exact in float32, so this equals the whole-image computation bit for bit.)"""
    height, width = pixels.shape[:2]
    out_height, out_width = max(1, height // 2), max(1, width // 2)
    result = np.empty((out_height, out_width, 4), np.float32)
    for start in range(0, height, rows_per_strip):  # an even strip height keeps 2×2 blocks whole
        first_row = start // 2
        if first_row >= out_height:
            break
        strip = pixels[start : start + rows_per_strip].astype(np.float32)
        if strip.shape[0] % 2:
            strip = np.concatenate([strip, strip[-1:]], axis=0)
        if width % 2:
            strip = np.concatenate([strip, strip[:, -1:]], axis=1)
        means = strip.reshape(strip.shape[0] // 2, 2, strip.shape[1] // 2, 2, 4).mean(axis=(1, 3))
        count = min(len(means), out_height - first_row)
        result[first_row : first_row + count] = means[:count, :out_width]
    return result


def new_target(device, width: int, height: int, color_format: str, samples: int = 1) -> Target:
    """Fresh color and depth textures with their readback buffers (render_many keeps one
    set per frame in flight); with samples > 1 also the multisampled attachments."""
    color = device.create_texture(
        size=(width, height, 1),
        format=COLOR_FORMATS[color_format],
        usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC,
    )
    depth = device.create_texture(
        size=(width, height, 1),
        format=DEPTH_FORMAT,
        usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.COPY_SRC,
    )
    color_row_bytes = padded_row_bytes(width, BYTES_PER_PIXEL[color_format])
    depth_row_bytes = padded_row_bytes(width, 4)
    readback_usage = wgpu.BufferUsage.MAP_READ | wgpu.BufferUsage.COPY_DST
    msaa = {}
    if samples > 1:
        for name, texture_format in (("msaa_color_view", COLOR_FORMATS[color_format]), ("msaa_depth_view", DEPTH_FORMAT)):
            msaa[name] = device.create_texture(
                size=(width, height, 1), format=texture_format, sample_count=samples,
                usage=wgpu.TextureUsage.RENDER_ATTACHMENT,
            ).create_view()
    return Target(
        width=width,
        height=height,
        color_format=color_format,
        color=color,
        color_view=color.create_view(),
        depth=depth,
        depth_view=depth.create_view(),
        color_readback=device.create_buffer(size=color_row_bytes * height, usage=readback_usage),
        depth_readback=device.create_buffer(size=depth_row_bytes * height, usage=readback_usage),
        color_row_bytes=color_row_bytes,
        depth_row_bytes=depth_row_bytes,
        samples=samples,
        **msaa,
    )



def vertex_order_enabled() -> bool:
    """Meshes are uploaded in vertex-cache order unless WGPU_SHADING_VERTEX_ORDER=0 (for
    A/B measurements and the test that the pixels do not change)."""
    return os.environ.get("WGPU_SHADING_VERTEX_ORDER", "1") != "0"


def upload_mesh(device, mesh: Mesh, extra_usage: int, in_order: frozenset[int] = frozenset()) -> GpuMesh:
    """Positions, normals and indices of `mesh` in GPU buffers. One upload serves every
    frequency: vertex buffers for Gouraud/Phong, storage buffers for flat shading's vertex
    pulling. `extra_usage` is MAP_WRITE where the device writes such buffers in place.

    The triangles of every part not in `in_order` (the alpha-blended parts) are uploaded in
    vertex-cache order, and the vertices in first-use order (render/vertex_order.py: same
    pixels, less vertex work). The vertices are written into their buffers in the new order
    a chunk at a time, and the reordered indices live in scratch memory that is handed back
    right after their upload: the upload still leaves one copy of the mesh (the driver's)."""
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
    scratch, order = cache_order(mesh.indices, mesh.vertex_count, mesh.parts, in_order)
    try:
        indices = device.create_buffer_with_data(data=scratch.array, usage=index_usage)
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


def upload_uvs(device, gpu_mesh: GpuMesh, mesh: Mesh, extra_usage: int) -> None:
    """Texture coordinates only once a textured draw needs them: most meshes are drawn
    untextured, and a big mesh's uvs are a seventh of its memory."""
    if gpu_mesh.uvs is None and mesh.uvs is not None:
        usage = wgpu.BufferUsage.VERTEX | wgpu.BufferUsage.STORAGE | extra_usage
        gpu_mesh.uvs = _reordered_buffer(device, mesh.uvs, gpu_mesh.order, usage)


def upload_tangents(device, gpu_mesh: GpuMesh, mesh: Mesh, extra_usage: int) -> None:
    """A file's tangents (float32 xyzw), once a normal-mapped draw needs them."""
    if gpu_mesh.tangents is None and mesh.tangents is not None:
        usage = wgpu.BufferUsage.VERTEX | wgpu.BufferUsage.STORAGE | extra_usage
        gpu_mesh.tangents = _reordered_buffer(device, mesh.tangents, gpu_mesh.order, usage)


def upload_colors(device, gpu_mesh: GpuMesh, mesh: Mesh, extra_usage: int) -> None:
    """Vertex colors (float32 RGBA), once a draw needs them."""
    if gpu_mesh.colors is None and mesh.colors is not None:
        usage = wgpu.BufferUsage.VERTEX | wgpu.BufferUsage.STORAGE | extra_usage
        gpu_mesh.colors = _reordered_buffer(device, mesh.colors, gpu_mesh.order, usage)


def srgb_mip_chain(pixels: np.ndarray) -> list[np.ndarray]:
    """Mip levels of an sRGB-encoded image, box-filtered in linear light (alpha as is), so
    a minified texture keeps its brightness; each level is encoded again for the *-srgb format."""
    from ..scene.maps import srgb_decode, srgb_encode

    table = srgb_decode(np.arange(256) / 255.0).astype(np.float32)
    current = np.empty(pixels.shape, np.float32)
    current[:, :, :3] = table[pixels[:, :, :3]]
    current[:, :, 3] = pixels[:, :, 3] / np.float32(255.0)
    levels = [pixels]
    while current.shape[0] > 1 or current.shape[1] > 1:
        current = halved(current)
        encoded = np.concatenate([srgb_encode(current[:, :, :3]), current[:, :, 3:]], axis=2)
        levels.append(np.round(encoded * 255.0).astype(np.uint8))
    return levels


def upload_texture(device, texture: Texture, srgb: bool = False) -> GpuTexture:
    """The texture with its box-filtered mip chain, rows bottom-up: texture row 0 is the
    image's last row, so v = 0 is the bottom. `srgb`: stored in an rgba8unorm-srgb texture,
    which decodes texels to linear light before filtering (linear colour space)."""
    height, width = texture.pixels.shape[:2]
    limit = device.limits["max-texture-dimension-2d"]
    if width > limit or height > limit:
        raise SceneError(f"texture {texture.name!r}: {width}×{height} pixels exceeds this adapter's limit of {limit} pixels per side")
    rows_up = np.ascontiguousarray(texture.pixels[::-1])
    levels = srgb_mip_chain(rows_up) if srgb else mip_chain(rows_up)
    height, width = levels[0].shape[:2]
    gpu = device.create_texture(
        size=(width, height, 1),
        format=wgpu.TextureFormat.rgba8unorm_srgb if srgb else wgpu.TextureFormat.rgba8unorm,
        usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST,
        mip_level_count=len(levels),
    )
    for level, pixels in enumerate(levels):
        device.queue.write_texture(
            {"texture": gpu, "mip_level": level},
            np.ascontiguousarray(pixels),
            {"bytes_per_row": pixels.shape[1] * 4, "rows_per_image": pixels.shape[0]},
            (pixels.shape[1], pixels.shape[0], 1),
        )
    return GpuTexture(texture=gpu, view=gpu.create_view(), nbytes=sum(level.nbytes for level in levels))


def read_buffer(buffer, row_bytes: int, height: int, width: int, dtype, channels: int) -> np.ndarray:
    map_for_reading(buffer)
    try:
        raw = np.frombuffer(buffer.read_mapped(copy=False), dtype=np.uint8).reshape(height, row_bytes)
        pixel_bytes = width * channels * np.dtype(dtype).itemsize
        image = raw[:, :pixel_bytes].copy().view(dtype).reshape(height, width, channels)
    finally:
        buffer.unmap()
    return image


def read_mapped_rows(buffer, row_bytes: int, height: int, width: int, dtype, convert):
    """`convert` applied to the (height, width) single-channel rows of a readback buffer,
    read straight from the mapping (no copy of the padded rows first); `convert` must
    return a new array, since the mapping goes away afterwards. The depth readback uses it:
    eye depth is computed from the mapped float32 rows in one pass (uniforms.linear_depth)."""
    map_for_reading(buffer)
    try:
        itemsize = np.dtype(dtype).itemsize
        rows = np.frombuffer(buffer.read_mapped(copy=False), dtype=dtype).reshape(height, row_bytes // itemsize)
        return convert(rows[:, :width])
    finally:
        buffer.unmap()


def check_target_size(device, size: tuple[int, int], color_format: str, samples: int = 1) -> None:
    """A clear error for an output the adapter cannot render or read back."""
    if samples > 1 and color_format != "rgba8":
        # WebGPU cannot resolve (average) multisampled rgba32float targets.
        raise SceneError(
            f"output.samples {samples}: antialiasing needs the 8-bit target; the float32 "
            "target (.npy, --float) is single-sample only (use samples = 1)"
        )
    width, height = size
    limit = device.limits["max-texture-dimension-2d"]
    if width > limit or height > limit:
        raise SceneError(f"output.size {width}×{height} exceeds this adapter's limit of {limit} pixels per side")
    readback_bytes = padded_row_bytes(width, BYTES_PER_PIXEL[color_format]) * height
    if readback_bytes > device.limits["max-buffer-size"]:
        raise SceneError(
            f"output.size {width}×{height} with the {color_format} target needs a "
            f"{readback_bytes / 2**30:.1f} GiB readback buffer; this adapter allows "
            f"{device.limits['max-buffer-size'] / 2**30:.1f} GiB (use a smaller size"
            + (" or the 8-bit target)" if color_format != "rgba8" else ")")
        )


def cached_bind_group(device, cache: LruCache, layout, resources: tuple) -> object:
    """A bind group, cached in `cache`: the LRU cache of whoever owns the resources (the
    renderer for uniform buffers, a GpuMesh for its buffers, a GpuTexture for its view).
    The key holds the bound objects themselves (identity-hashed), not their id()s: an
    evicted buffer's id may be reused by a new one, which must not find the old group."""
    key = (layout,) + tuple(resources)
    group = cache.get(key)
    if group is None:
        entries = []
        for binding, resource in enumerate(resources):
            if isinstance(resource, wgpu.GPUBuffer):
                resource = {"buffer": resource, "offset": 0, "size": resource.size}
            entries.append({"binding": binding, "resource": resource})
        group = device.create_bind_group(layout=layout, entries=entries)
        cache.put(key, group)
    return group


def uniform_buffer(device, cache: LruCache, key: tuple, payload: bytes) -> object:
    """The uniform buffer cached under `key` (made on first use), holding `payload`.

    Queue writes are ordered with submissions, so a buffer holds the last bytes written
    to it for every later frame: writing the same bytes again (a re-render, an object a
    camera move did not change) is skipped. The cache keeps [buffer, bytes last written]."""
    cached = cache.get(key)
    if cached is None:
        buffer = device.create_buffer(size=len(payload), usage=wgpu.BufferUsage.UNIFORM | wgpu.BufferUsage.COPY_DST)
        cached = cache.put(key, [buffer, None])
    if payload != cached[1]:
        device.queue.write_buffer(cached[0], 0, payload)
        cached[1] = payload
    return cached[0]


_ADDRESS_MODES = {"repeat": "repeat", "clamp": "clamp-to-edge", "mirror": "mirror-repeat"}


def create_sampler(device, nearest: bool, wrap: tuple[str, str]) -> object:
    """A texture sampler: linear filtering with mipmaps, or nearest (glTF NEAREST filters);
    coordinates outside [0, 1] repeat, clamp to the edge or mirror (Texture.wrap)."""
    filter_mode = wgpu.FilterMode.nearest if nearest else wgpu.FilterMode.linear
    return device.create_sampler(
        address_mode_u=_ADDRESS_MODES[wrap[0]],
        address_mode_v=_ADDRESS_MODES[wrap[1]],
        mag_filter=filter_mode,
        min_filter=filter_mode,
        mipmap_filter=wgpu.MipmapFilterMode.nearest if nearest else wgpu.MipmapFilterMode.linear,
    )
