"""Texture images read from files (PNG, JPEG, ... through imageio) into Texture objects."""

from __future__ import annotations

import os

from ..errors import SceneError
from ..scene.material import Texture


def load_texture(path: str | os.PathLike[str]) -> Texture:
    """An image file as an RGBA8 Texture (the first frame of an animated one)."""
    import imageio.v3 as iio  # lazy: imageio costs ~0.1 s to import

    try:
        pixels = iio.imread(path)
    except FileNotFoundError:
        raise SceneError(f"texture {str(path)!r}: file not found") from None
    except Exception as error:  # imageio raises many kinds for unreadable files
        raise SceneError(f"texture {str(path)!r}: cannot read image ({error})") from None
    if pixels.ndim == 4:  # animated formats: first frame
        pixels = pixels[0]
    return Texture(pixels, name=str(path))
