"""Mip chains of texture images, box-filtered on the CPU before upload: display values as
they are, sRGB-encoded images in linear light."""

from __future__ import annotations

import numpy as np


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

def srgb_mip_chain(pixels: np.ndarray) -> list[np.ndarray]:
    """Mip levels of an sRGB-encoded image, box-filtered in linear light (alpha as is), so
    a minified texture keeps its brightness; each level is encoded again for the *-srgb format."""
    from ...scene.maps import srgb_decode, srgb_encode

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
