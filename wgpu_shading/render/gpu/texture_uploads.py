"""Texture uploads: an image with its mip chain (mips.py) in an rgba8unorm or
rgba8unorm-srgb texture."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import wgpu

from ...errors import SceneError
from ...scene import Texture
from .caches import BIND_GROUP_CACHE_ENTRIES, LruCache
from .mips import mip_chain, srgb_mip_chain


@dataclass
class GpuTexture:
    """A texture's upload (with its mip chain) and its view, and the bind groups that bind it."""

    texture: object
    view: object
    nbytes: int = 0
    # object bind groups that bind this view (one per object uniform buffer and layout)
    object_groups: LruCache = field(default_factory=lambda: LruCache(BIND_GROUP_CACHE_ENTRIES))

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
