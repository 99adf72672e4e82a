"""The shadow maps of a frame (docs/shadows.md#shadow-maps): one depth32float 2D array
texture, a layer per view of a casting light (passes/shadow_views.py), drawn by the shadow
pass and read by the colour pass. The device cache keeps the last few (by size and layer
count); frames in flight may share one, since a queue runs its submissions in order, and a
frame whose maps would be the same as the last ones drawn into it reuses them."""

from __future__ import annotations

from dataclasses import dataclass

import wgpu

from ...errors import SceneError

SHADOW_FORMAT = wgpu.TextureFormat.depth32float
# A frame's shadow maps together (4 bytes a texel): 8 maps of 8192² texels, 128 of 2048². Eight
# positional lights casting at 8192² asked for 48 cube faces, 12 GiB, which lavapipe
# tried to allocate in host memory (and a GPU failed with an internal error).
MAX_SHADOW_MAP_BYTES = 2 << 30


@dataclass(eq=False)
class ShadowMaps:
    texture: object  # wgpu.GPUTexture, (size, size, layers)
    array_view: object  # the whole array, as the colour pass binds it
    layer_views: tuple  # one render attachment per layer
    size: int
    # What the layers hold (passes/shadow.py: each caster's mesh and matrix, view by view):
    # a frame whose casters and views are the same draws nothing.
    contents: tuple | None = None

    @property
    def nbytes(self) -> int:
        return 4 * self.size * self.size * len(self.layer_views)


def new_shadow_maps(device, size: int, layers: int) -> ShadowMaps:
    """`layers` maps of size × size texels (at least one, so there is always a texture to bind)."""
    layers = max(layers, 1)
    if 4 * size * size * layers > MAX_SHADOW_MAP_BYTES:
        raise SceneError(
            f"shadows.map_size: the casting lights need {layers} shadow maps (one per directional or spot light, up to "
            f"six per positional light) of {size}×{size} texels, {4 * size * size * layers / 2**30:.2f} GiB; at most "
            f"{MAX_SHADOW_MAP_BYTES >> 30} GiB are made (a smaller map_size, or fewer casting lights)"
        )
    limits = device.limits
    if size > limits["max-texture-dimension-2d"]:
        raise SceneError(f"shadows.map_size: {size} texels; this adapter allows at most {limits['max-texture-dimension-2d']}")
    if layers > limits["max-texture-array-layers"]:
        raise SceneError(
            f"lights: the casting lights need {layers} shadow maps (one per directional or spot light, up to six per "
            f"positional light); this adapter allows {limits['max-texture-array-layers']} (let fewer lights cast shadows)"
        )
    texture = device.create_texture(
        label="shadow maps", size=(size, size, layers), format=SHADOW_FORMAT,
        usage=wgpu.TextureUsage.RENDER_ATTACHMENT | wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_SRC,
    )
    layer_views = tuple(
        texture.create_view(dimension=wgpu.TextureViewDimension.d2, base_array_layer=layer, array_layer_count=1)
        for layer in range(layers)
    )
    return ShadowMaps(texture, texture.create_view(dimension=wgpu.TextureViewDimension.d2_array), layer_views, size)


def create_comparison_sampler(device) -> object:
    """The shadow maps' comparison sampler for the bilinear and PCF filters: 2×2 texels
    compared and weighted bilinearly, clamped at the map's edges."""
    return device.create_sampler(
        label="shadow comparison",
        address_mode_u=wgpu.AddressMode.clamp_to_edge,
        address_mode_v=wgpu.AddressMode.clamp_to_edge,
        mag_filter=wgpu.FilterMode.linear,
        min_filter=wgpu.FilterMode.linear,
        compare=wgpu.CompareFunction.greater_equal,
    )
