"""Writing rendered images: output paths checked before any work, then PNG/JPEG/TIFF/.npy."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Sequence

import numpy as np

from ..errors import SceneError

IMAGE_SUFFIXES = (".png", ".npy", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")


def output_path(path: os.PathLike[str] | str, suffixes: Sequence[str]) -> Path:
    """A file to write: one of `suffixes`, in a folder that exists (checked before any work)."""
    path = Path(path)
    if path.suffix.lower() not in suffixes:
        raise SceneError(f"output {str(path)!r}: unsupported format; use one of {', '.join(suffixes)}")
    if not path.parent.exists():
        raise SceneError(f"output {str(path)!r}: folder {str(path.parent)!r} does not exist")
    return path


def write_image(path: Path, image: np.ndarray) -> None:
    """.npy keeps float32 exactly; image formats get the 8-bit image, written by Pillow
    directly (imageio's plugin discovery would add ~0.1 s to every cold start)."""
    if path.suffix.lower() == ".npy":
        np.save(path, image)
        return
    from PIL import Image

    if path.suffix.lower() in (".jpg", ".jpeg"):
        # JPEG has no alpha. The color is already over the background; alpha only marks
        # translucent materials, which an opaque framebuffer (OpenGL's default) shows as RGB.
        image = image[:, :, :3]
    Image.fromarray(np.ascontiguousarray(image)).save(path)
