"""Our PNG encoder (assets/png.py) against two independent decoders: Pillow (libpng's rules in
C) and pypng (pure Python). Every sample must come back exactly."""

from __future__ import annotations

import io
import zlib

import numpy as np
import png as pypng
import pytest
from PIL import Image

from wgpu_shading.assets import png
from wgpu_shading.assets.png import encode_png

SHAPES = [((5, 7), np.uint8), ((5, 7, 2), np.uint8), ((5, 7, 3), np.uint8), ((64, 33, 4), np.uint8), ((1, 1), np.uint8),
          ((9, 4), np.uint16), ((9, 4, 4), np.uint16), ((3, 5, 3), np.uint16)]


def pypng_decode(data: bytes, shape, dtype) -> np.ndarray:
    width, height, rows, info = pypng.Reader(bytes=data).asDirect()
    return np.array([list(row) for row in rows], dtype=dtype).reshape(shape)


@pytest.mark.parametrize("shape, dtype", SHAPES)
@pytest.mark.parametrize("block_bytes", [1 << 22, 16])  # one block, and a block per row or two
def test_every_sample_decodes_back_exactly(shape, dtype, block_bytes, monkeypatch):
    monkeypatch.setattr(png, "_BLOCK_BYTES", block_bytes)
    pixels = np.random.default_rng(7).integers(0, np.iinfo(dtype).max + 1, shape, dtype=dtype)
    data = encode_png(pixels, level=1)
    assert np.array_equal(pypng_decode(data, shape, dtype), pixels)
    if dtype == np.uint8 or len(shape) == 2:  # Pillow reads 16-bit colour as 8 bits
        assert np.array_equal(np.asarray(Image.open(io.BytesIO(data))), pixels)


def test_text_chunks_and_every_level_decode(tmp_path):
    pixels = (np.arange(48 * 40 * 4) % 251).astype(np.uint8).reshape(48, 40, 4)
    for level in range(10):
        data = encode_png(pixels, level, {"near": "0.25", "far": "1e+30"})
        image = Image.open(io.BytesIO(data))
        assert image.text == {"near": "0.25", "far": "1e+30"} and np.array_equal(np.asarray(image), pixels)
    # zlib level 0 stores: the image data is then the filtered rows plus zlib's framing
    assert len(encode_png(pixels, 0)) > pixels.nbytes > len(encode_png(pixels, 9))


def test_the_rows_use_the_up_filter():
    pixels = np.array([[10, 20], [13, 27]], np.uint8)
    data = encode_png(pixels, 0)
    start = data.index(b"IDAT") + 4
    raw = zlib.decompressobj().decompress(data[start:])
    assert raw[:6] == bytes([2, 10, 20, 2, 3, 7])  # each row: filter 2, then the bytes minus those above


def test_unsupported_images_are_refused():
    with pytest.raises(TypeError, match="uint8 or uint16"):
        encode_png(np.zeros((2, 2), np.float32))
    with pytest.raises(ValueError, match="shape"):
        encode_png(np.zeros((2, 2, 5), np.uint8))
    with pytest.raises(ValueError, match="shape"):
        encode_png(np.zeros((0, 2), np.uint8))


def _shaded_sphere(size: int = 256) -> np.ndarray:
    """An image like a render: a lit sphere (Lambert, a highlight) on black, alpha 255."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size * 2 - 1
    inside = x * x + y * y < 0.8
    z = np.sqrt(np.clip(0.8 - x * x - y * y, 0, None))
    light = np.clip((x * -0.4 + y * -0.5 + z * 0.77) / np.sqrt(0.8), 0, 1)
    rgb = np.stack([0.8 * light + 0.2 * light**30, 0.6 * light + 0.2 * light**30, 0.2 * light + 0.2 * light**30], -1)
    image = np.zeros((size, size, 4), np.uint8)
    image[..., :3] = np.where(inside[..., None], np.round(np.clip(rgb, 0, 1) * 255), 0)
    image[..., 3] = 255
    return image


def _idat(data: bytes) -> bytes:
    """The concatenated IDAT payloads of a PNG file."""
    position, payload = 8, b""
    while position < len(data):
        length = int.from_bytes(data[position : position + 4], "big")
        if data[position + 4 : position + 8] == b"IDAT":
            payload += data[position + 8 : position + 8 + length]
        position += 12 + length
    return payload


@pytest.mark.parametrize("level", [1, 2])
def test_the_fast_levels_use_isal_and_make_files_no_larger_than_zlib(level):
    pixels = _shaded_sphere()
    data = encode_png(pixels, level)
    assert np.array_equal(np.asarray(Image.open(io.BytesIO(data))), pixels)
    assert np.array_equal(pypng_decode(data, pixels.shape, np.uint8), pixels)
    filtered = zlib.decompress(_idat(data))  # the rows as the encoder filtered them
    compressor = zlib.compressobj(level, zlib.DEFLATED, 15, 9)
    zlib_stream = compressor.compress(filtered) + compressor.flush()
    if png.isal_zlib is None:
        pytest.skip("isal is not installed here: zlib serves every level")
    assert _idat(data) != zlib_stream  # isal's stream, not zlib's
    assert len(_idat(data)) <= len(zlib_stream)


def test_the_smaller_levels_stay_with_zlib():
    pixels = _shaded_sphere(64)
    data = encode_png(pixels, 6)
    filtered = zlib.decompress(_idat(data))
    compressor = zlib.compressobj(6, zlib.DEFLATED, 15, 9)
    assert _idat(data) == compressor.compress(filtered) + compressor.flush()
