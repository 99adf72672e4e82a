"""Texture samplers: how a texture is filtered and what happens outside [0, 1]."""

from __future__ import annotations

import wgpu

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
