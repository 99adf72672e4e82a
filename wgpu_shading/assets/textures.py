"""Texture images read from files (PNG, JPEG, BMP, TIFF, ... decoded by Pillow through imageio) into Texture objects."""

from __future__ import annotations

import io
import os

import numpy as np

from ..errors import SceneError
from ..scene.material import MAX_TEXTURE_SIDE, Texture

# An image file bigger than this is refused before it is read (a 16384² RGBA PNG of noise
# is ~1 GiB; nothing sensible is bigger).
MAX_TEXTURE_FILE_BYTES = 1 << 30


def load_texture(path: str | os.PathLike[str]) -> Texture:
    """An image file as an RGBA8 Texture (the first frame of an animated one).

    The file is read and closed here, then decoded from memory: a file that fails to
    decode leaves no open file descriptor behind. Its size is read from the header and
    checked before the pixels are decoded."""
    import imageio.v3 as iio  # lazy: imageio costs ~0.1 s to import
    from PIL import Image

    where = f"texture {str(path)!r}"
    try:
        with open(path, "rb") as file:
            data = file.read(MAX_TEXTURE_FILE_BYTES + 1)
    except FileNotFoundError:
        raise SceneError(f"{where}: file not found") from None
    except (OSError, ValueError) as error:  # ValueError: a NUL in the path
        raise SceneError(f"{where}: cannot be read ({getattr(error, 'strerror', None) or error})") from None
    if len(data) > MAX_TEXTURE_FILE_BYTES:
        raise SceneError(f"{where}: the file is larger than {MAX_TEXTURE_FILE_BYTES >> 20} MiB")
    try:
        with Image.open(io.BytesIO(data)) as header:  # reads the header only
            width, height = header.size
    except Image.DecompressionBombError as error:  # far beyond MAX_TEXTURE_SIDE² pixels
        raise SceneError(f"{where}: too large ({error}); at most {MAX_TEXTURE_SIDE} pixels per side are supported") from None
    except Image.UnidentifiedImageError:  # its text names the BytesIO object and its address
        raise SceneError(f"{where}: not an image Pillow can read (no known image format; {len(data)} bytes)") from None
    except Exception as error:  # not an image format Pillow reads (PNG, JPEG, BMP, TIFF, GIF, WebP, ...)
        raise SceneError(f"{where}: not an image Pillow can read ({type(error).__name__}: {error})") from None
    if width > MAX_TEXTURE_SIDE or height > MAX_TEXTURE_SIDE:
        raise SceneError(f"{where}: {width}×{height} pixels; at most {MAX_TEXTURE_SIDE} per side are supported")
    try:
        # Decoded by Pillow alone: imageio would otherwise try every other plugin on a
        # damaged file (legacy DICOM, tifffile, ...), with deprecation warnings on the way.
        pixels = iio.imread(data, plugin="pillow")
    except Exception as error:  # imageio raises many kinds for unreadable files
        raise SceneError(f"{where}: cannot read image ({type(error).__name__}: {error})") from None
    if pixels.ndim == 4:  # animated formats: first frame
        pixels = pixels[0]
    return Texture(np.asarray(pixels), name=str(path))
