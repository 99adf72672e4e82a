"""Texture images read from files (PNG, JPEG, BMP, TIFF, ... decoded by Pillow through imageio) into Texture objects."""

from __future__ import annotations

import io
import os
import threading
import warnings
from contextlib import contextmanager
from typing import Iterator

import numpy as np

from ..errors import SceneError
from ..scene.material import MAX_TEXTURE_SIDE, Texture
from .files import check_regular_file

# An image file bigger than this is refused before it is read (a 16384² RGBA PNG of noise
# is ~1 GiB; nothing sensible is bigger).
MAX_TEXTURE_FILE_BYTES = 1 << 30


_limit_lock = threading.Lock()
_limit_users = 0
_limit_saved: int | None = None


@contextmanager
def decoding_limits(pixels: int = MAX_TEXTURE_SIDE * MAX_TEXTURE_SIDE) -> Iterator[None]:
    """Pillow's decompression-bomb limit raised to `pixels` while we decode.

    Pillow warns above `Image.MAX_IMAGE_PIXELS` (89 M pixels) and refuses above twice that,
    which contradicted our documented 16384-pixel sides (16384×6000 warned, 16384×10923 was
    refused). Our own limit is checked from the header before decoding, so Pillow's need
    only not be lower. The global is raised, never lowered, and restored when the last
    decode of ours ends (a count under a lock, so concurrent decodes do not restore it
    under each other); an application's own higher limit or None is left alone."""
    from PIL import Image

    global _limit_users, _limit_saved
    with _limit_lock:
        if _limit_users == 0:
            _limit_saved = Image.MAX_IMAGE_PIXELS
            if Image.MAX_IMAGE_PIXELS is not None and Image.MAX_IMAGE_PIXELS < pixels:
                Image.MAX_IMAGE_PIXELS = pixels
        _limit_users += 1
    try:
        yield
    finally:
        with _limit_lock:
            _limit_users -= 1
            if _limit_users == 0:
                Image.MAX_IMAGE_PIXELS = _limit_saved


def load_texture(path: str | os.PathLike[str]) -> Texture:
    """An image file as an RGBA8 Texture (the first frame of an animated one).

    The file is read and closed here, then decoded from memory: a file that fails to
    decode leaves no open file descriptor behind. Its size is read from the header and
    checked before the pixels are decoded."""
    where = f"texture {str(path)!r}"
    check_regular_file(path, where, SceneError)  # a FIFO would block open() forever
    try:
        with open(path, "rb") as file:
            data = file.read(MAX_TEXTURE_FILE_BYTES + 1)
    except FileNotFoundError:
        raise SceneError(f"{where}: file not found") from None
    except (OSError, ValueError) as error:  # ValueError: a NUL in the path
        raise SceneError(f"{where}: cannot be read ({getattr(error, 'strerror', None) or error})") from None
    if len(data) > MAX_TEXTURE_FILE_BYTES:
        raise SceneError(f"{where}: the file is larger than {MAX_TEXTURE_FILE_BYTES >> 20} MiB")
    with decoder_warnings(where):
        pixels = _decode(data, where)
    if pixels.ndim == 4:  # animated formats: first frame
        pixels = pixels[0]
    return Texture(np.asarray(pixels), name=str(path))


def _decode(data: bytes, where: str) -> np.ndarray:
    import imageio.v3 as iio  # lazy: imageio costs ~0.1 s to import
    from PIL import Image

    try:
        with decoding_limits(), Image.open(io.BytesIO(data)) as header:  # reads the header only
            width, height = header.size
    except Image.DecompressionBombError:  # far beyond MAX_TEXTURE_SIDE² pixels (Pillow's text says "DOS attack")
        raise SceneError(f"{where}: too large (over {2 * MAX_TEXTURE_SIDE * MAX_TEXTURE_SIDE} pixels); at most {MAX_TEXTURE_SIDE} pixels per side are supported") from None
    except Image.UnidentifiedImageError:  # its text names the BytesIO object and its address
        raise SceneError(f"{where}: not an image Pillow can read (no known image format; {len(data)} bytes)") from None
    except Exception as error:  # not an image format Pillow reads (PNG, JPEG, BMP, TIFF, GIF, WebP, ...)
        raise SceneError(f"{where}: not an image Pillow can read ({type(error).__name__}: {error})") from None
    if width > MAX_TEXTURE_SIDE or height > MAX_TEXTURE_SIDE:
        raise SceneError(f"{where}: {width}×{height} pixels; at most {MAX_TEXTURE_SIDE} per side are supported")
    try:
        # Decoded by Pillow alone: imageio would otherwise try every other plugin on a
        # damaged file (legacy DICOM, tifffile, ...), with deprecation warnings on the way.
        with decoding_limits():
            pixels = iio.imread(data, plugin="pillow")
    except Exception as error:  # imageio raises many kinds for unreadable files
        raise SceneError(f"{where}: cannot read image ({type(error).__name__}: {error})") from None
    return pixels


@contextmanager
def decoder_warnings(where: str) -> Iterator[None]:
    """Pillow's warnings about a file it still decodes ("Corrupt EXIF data", "Tag data larger
    than file", each twice) become one warning that names the file. In the main thread only:
    `warnings.catch_warnings` swaps process-wide state (Python < 3.14), so in other threads
    the warnings pass as Pillow raised them."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield
    messages = list(dict.fromkeys(" ".join(str(item.message).split()) for item in caught))
    if messages:
        more = f" (and {len(messages) - 1} more)" if len(messages) > 1 else ""
        warnings.warn(f"{where}: {messages[0]}{more}; the pixels were read anyway", UserWarning, stacklevel=4)
