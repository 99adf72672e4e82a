"""Render targets: the colour and depth textures a frame is drawn into (with the
multisampled attachments of MSAA), the readback buffers its images are copied to, and the
check that an output size fits the adapter before anything is made."""

from __future__ import annotations

import math
from dataclasses import dataclass

import wgpu

from ...errors import SceneError

DEPTH_FORMAT = wgpu.TextureFormat.depth32float
COLOR_FORMATS = {"rgba8": wgpu.TextureFormat.rgba8unorm, "float32": wgpu.TextureFormat.rgba32float}
BYTES_PER_PIXEL = {"rgba8": 4, "float32": 16}
_ROW_ALIGNMENT = 256  # WebGPU's required bytes_per_row multiple for texture copies


@dataclass
class Target:
    """What one frame renders into: colour and depth attachments (and their multisampled
    twins with MSAA) and the readback buffers their rows are copied to."""

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
