"""PNG encoding with one fixed row filter: exact, and half the CPU of Pillow's encoder.

Why our own encoder (the format is the W3C PNG specification, https://www.w3.org/TR/png/:
a signature, an IHDR chunk, zlib-compressed filtered rows in IDAT chunks, IEND; every chunk
with a CRC-32): Pillow chooses a filter for every row by trying four of them
(`ImagingZipEncode` in libImaging/ZipEncode.c), and for rendered images that trial costs
more than the compression itself (callgrind: 51 % of a dataset encoder thread, zlib 35 %).
Pillow has no option to fix the filter, nor does pypng to use one (it writes unfiltered
rows from a Python loop). Here every row takes the "Up" filter (the byte above
subtracted), computed in numpy for a block of rows at a time, then compressed by zlib,
which releases the GIL, so encoding overlaps with rendering on other threads. On the
dataset benchmark's renders this takes 0.46× Pillow's CPU time at the same compression
level, and the files come out the same size within 1 % (docs/performance.md). Decoders
see the same pixels (tests/test_png.py decodes with Pillow and pypng).

Levels 1 and 2 (level 1 is the default of `render` and `batch`: image_writers.PNG_LEVEL) are deflated by Intel's ISA-L (python-isal's
`isal_zlib`, the same zlib stream format, the GIL released too) at its own levels 1 and
2: on rendered images it is 8–11× zlib's speed at those levels and its files are no
larger (a 512² torus: 0.4 against 4.6 ms, 50.8 against 55.0 KB). From level 3 on zlib
makes the smaller files, so it keeps them; and it serves every level where isal cannot
be imported.
"""

from __future__ import annotations

import zlib

import numpy as np

try:
    from isal import isal_zlib
except ImportError:  # pragma: no cover - a platform without isal's wheels: zlib at every level
    isal_zlib = None

ISAL_LEVELS = (1, 2)  # zlib levels whose streams isal makes faster and no larger (module docstring)

SIGNATURE = b"\x89PNG\r\n\x1a\n"
UP = 2  # the PNG filter type "Up": each byte minus the byte above it (the first row: minus 0)
_COLOR_TYPES = {1: 0, 2: 4, 3: 2, 4: 6}  # channels → PNG colour type (grey, grey + alpha, RGB, RGBA)
_BLOCK_BYTES = 1 << 22  # rows filtered and compressed at a time: bounded memory for any image


def _chunk(kind: bytes, data: bytes) -> bytes:
    return len(data).to_bytes(4, "big") + kind + data + zlib.crc32(data, zlib.crc32(kind)).to_bytes(4, "big")


def encode_png(pixels: np.ndarray, level: int = 6, text: dict[str, str] | None = None) -> bytes:
    """PNG file contents of `pixels`: (H, W) grey or (H, W, C) with C = 2 (grey + alpha),
    3 (RGB) or 4 (RGBA); uint8 or uint16 (16 bits per sample). `level`: zlib's compression
    level 0..9. `text`: tEXt chunks (Latin-1 keywords and values), before the image data."""
    if pixels.dtype not in (np.uint8, np.uint16):
        raise TypeError(f"PNG samples must be uint8 or uint16, got {pixels.dtype}")
    height, width = pixels.shape[:2]
    channels = 1 if pixels.ndim == 2 else pixels.shape[2]
    if pixels.ndim not in (2, 3) or channels not in _COLOR_TYPES or height < 1 or width < 1:
        raise ValueError(f"cannot write an image of shape {pixels.shape} as PNG")
    bits = 8 * pixels.dtype.itemsize
    # Rows as bytes, big-endian samples (PNG's order).
    rows = np.ascontiguousarray(pixels, dtype=pixels.dtype.newbyteorder(">")).view(np.uint8).reshape(height, -1)
    header = width.to_bytes(4, "big") + height.to_bytes(4, "big") + bytes([bits, _COLOR_TYPES[channels], 0, 0, 0])
    parts = [SIGNATURE, _chunk(b"IHDR", header)]
    for keyword, value in (text or {}).items():
        parts.append(_chunk(b"tEXt", keyword.encode("latin-1") + b"\0" + value.encode("latin-1")))
    compressor = compressor_for(level)
    data = []
    block = max(1, _BLOCK_BYTES // rows.shape[1])
    filtered = np.empty((min(block, height), rows.shape[1] + 1), np.uint8)
    filtered[:, 0] = UP
    for start in range(0, height, block):
        stop = min(start + block, height)
        out = filtered[: stop - start, 1:]
        below = 0 if start else 1  # the first row has zeros above it: kept as it is
        if not start:
            out[0] = rows[0]
        np.subtract(rows[start + below : stop], rows[start + below - 1 : stop - 1], out=out[below:])
        data.append(compressor.compress(filtered[: stop - start]))
    data.append(compressor.flush())
    parts.append(_chunk(b"IDAT", b"".join(data)))
    parts.append(_chunk(b"IEND", b""))
    return b"".join(parts)


def compressor_for(level: int):
    """A zlib-format compressor for zlib's `level` 0..9: isal's at ISAL_LEVELS, else zlib's."""
    if isal_zlib is not None and level in ISAL_LEVELS:
        return isal_zlib.compressobj(level, isal_zlib.DEFLATED, 15, 9)
    return zlib.compressobj(level, zlib.DEFLATED, 15, 9)


def write_png(file, pixels: np.ndarray, level: int = 6, text: dict[str, str] | None = None) -> None:
    """encode_png(pixels, level, text) written to a binary file object."""
    file.write(encode_png(pixels, level, text))
