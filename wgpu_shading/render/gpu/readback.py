"""Reading a frame back: a mapped readback buffer's padded rows into numpy."""

from __future__ import annotations

import numpy as np
import wgpu


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
