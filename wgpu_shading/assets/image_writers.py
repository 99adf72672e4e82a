"""Writing rendered images: output paths checked before any work, then PNG/JPEG/TIFF/.npy."""

from __future__ import annotations

import os
from pathlib import Path
from typing import NamedTuple, Sequence

import numpy as np

from ..errors import UsageError
from .atomic import atomic_open, atomic_path, check_target
from .png import encode_png, write_png

class FileFormat(NamedTuple):
    """One suffix of the table below: Pillow's format (None: numpy's .npy), what the file holds
    (shown by --help) and whether it keeps alpha."""

    pillow: str | None
    holds: str
    alpha: bool = True


# The files `render -o` and `--depth` write. What `-o` accepts, its --help and the writers
# are all read from here (one truth: a suffix not listed is refused, with the list).
_RGB = FileFormat("JPEG", "8-bit RGB, no alpha", alpha=False)
_TIFF = FileFormat("TIFF", "8-bit RGBA")
IMAGE_FORMATS = {
    ".png": FileFormat("PNG", "8-bit RGBA"),
    ".npy": FileFormat(None, "float32 RGBA, exact"),
    ".jpg": _RGB,
    ".jpeg": _RGB,
    ".bmp": FileFormat("BMP", "8-bit RGB, no alpha", alpha=False),
    ".tif": _TIFF,
    ".tiff": _TIFF,
}
_FLOAT_TIFF = FileFormat("TIFF", "float32, inf = background")
DEPTH_FORMATS = {
    ".npy": FileFormat(None, "float32, inf = background"),
    ".tif": _FLOAT_TIFF,
    ".tiff": _FLOAT_TIFF,
    ".png": FileFormat("PNG", "16-bit, 0 = background, 1..65535 = near..far plane linearly, as batch --depth png16"),
}
IMAGE_SUFFIXES = tuple(IMAGE_FORMATS)
DEPTH_SUFFIXES = tuple(DEPTH_FORMATS)
STDOUT = "-"  # `-o -`: the PNG goes to standard output
# zlib level of `render`'s PNGs, as `batch --compression`'s default: ISA-L's level 1 (png.py)
# encodes a 512² render in 0.5 ms where zlib's default 6 takes 11 ms (5 % of a cold
# `render`), for files about a third larger (docs/performance.md, cold start).
PNG_LEVEL = 1


def formats_text(formats: dict[str, FileFormat]) -> str:
    """A format table for --help: ".png (8-bit RGBA), .jpg/.jpeg (8-bit RGB, no alpha), ..."
    (suffixes that write the same format together)."""
    groups: dict[FileFormat, list[str]] = {}
    for suffix, kind in formats.items():
        groups.setdefault(kind, []).append(suffix)
    return ", ".join(f"{'/'.join(suffixes)} ({kind.holds})" for kind, suffixes in groups.items())


def output_path(path: os.PathLike[str] | str, suffixes: Sequence[str], what: str = "output") -> Path:
    """A file to write: one of `suffixes`, in a folder that exists and can be written
    (checked before any work, so a typo does not cost a render and an OS error is a sentence).
    A symbolic link is written through to its target (see atomic.py)."""
    path = Path(path)
    if path.suffix.lower() not in suffixes:
        raise UsageError(f"{what} {str(path)!r}: unsupported format; use one of {', '.join(suffixes)}")
    if not path.is_symlink() and not path.parent.exists():
        raise UsageError(f"{what} {str(path)!r}: folder {str(path.parent)!r} does not exist")
    check_writable(path, what)
    return path


def check_writable(path: Path, what: str = "output") -> None:
    """Raise a one-line UsageError unless `path` can be written (atomic.check_target: tried
    with a temporary beside it; nothing is created at the target, a link stays a link)."""
    check_target(path, what, UsageError)


def check_folder_writable(folder: Path, what: str) -> None:
    """Raise a one-line UsageError unless files can be created in `folder` (tried, not guessed)."""
    import tempfile

    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as error:
        raise UsageError(f"{what} {str(folder)!r}: files cannot be written there: {error.strerror or error}") from None


def png_bytes(image: np.ndarray) -> bytes:
    """An 8-bit RGBA (or RGB) image as PNG file contents (for `-o -` and Jupyter)."""
    if image.dtype != np.uint8:  # a float32 render: [0, 1] to 8 bits, as the 8-bit target rounds
        image = np.round(np.clip(image, 0.0, 1.0) * 255.0).astype(np.uint8)
    return encode_png(image, PNG_LEVEL)


# The one 16-bit depth PNG encoding (`render --depth d.png` and `batch --depth png16`):
# 0 marks the background, so that nothing drawn is never read as a depth.
DEPTH_PNG_CONVENTION = (
    "uint16: 0 = background (nothing drawn); 1..65535 = eye-space depth from near to far, linearly: "
    "depth = near + (value - 1) / 65534 * (far - near)"
)


def depth_png_levels(depth: np.ndarray, near: float, far: float) -> np.ndarray:
    """Eye-space depth (inf where nothing was drawn) as DEPTH_PNG_CONVENTION's uint16 values."""
    covered = np.isfinite(depth)
    clipped = np.clip(np.where(covered, depth, near).astype(np.float64), near, far)
    levels = np.round(1.0 + (clipped - near) / (far - near) * 65534.0)
    return np.where(covered, levels, 0).astype(np.uint16)


def depth_png(depth: np.ndarray, near: float, far: float, compress_level: int = PNG_LEVEL) -> bytes:
    """Depth as a 16-bit grey PNG file's contents, with near, far and the convention in its
    text chunks (tEXt `near`, `far`: repr of the floats; `depth_encoding`)."""
    text = {"near": repr(float(near)), "far": repr(float(far)), "depth_encoding": DEPTH_PNG_CONVENTION}
    return encode_png(depth_png_levels(depth, near, far), compress_level, text)


def save_depth_png(file, depth: np.ndarray, near: float, far: float, compress_level: int = PNG_LEVEL) -> None:
    """depth_png() written to a binary file."""
    file.write(depth_png(depth, near, far, compress_level))


def read_depth_png(path: os.PathLike[str] | str) -> np.ndarray:
    """A depth PNG written by save_depth_png back as float32 eye-space depth (inf = background),
    to within (far - near) / 65534."""
    from PIL import Image

    with Image.open(path) as image:
        near, far = float(image.text["near"]), float(image.text["far"])
        levels = np.asarray(image).astype(np.float64)
    depth = near + (levels - 1.0) / 65534.0 * (far - near)
    return np.where(levels == 0, np.inf, depth).astype(np.float32)


def write_depth(path: Path, depth: np.ndarray, near: float, far: float) -> str:
    """Eye-space depth (distance along the view axis, inf where nothing was drawn) by suffix;
    returns how the values are stored, for the user.

    .npy   float32 distances, inf = background
    .tiff  the same float32 values as a 32-bit float TIFF
    .png   16-bit grey, DEPTH_PNG_CONVENTION (0 = background, 1..65535 = near..far); near and
           far are also written into the PNG's text chunks
    """
    suffix = path.suffix.lower()
    distances = depth.astype(np.float32)
    if suffix == ".npy":
        with atomic_open(path, "--depth") as file:
            np.save(file, distances)
        return "float32 eye-space distance, inf = background"
    from PIL import Image

    if suffix in (".tif", ".tiff"):
        with atomic_path(path, "--depth") as temporary:
            Image.fromarray(np.ascontiguousarray(distances)).save(temporary, format="TIFF")  # float32 → mode F
        return "32-bit float eye-space distance, inf = background"
    with atomic_open(path, "--depth") as file:
        save_depth_png(file, depth, near, far)
    return f"16-bit, linear: 0 = background, 1..65535 = near plane ({near:g}) .. far plane ({far:g})"


def write_image(path: Path, image: np.ndarray, what: str = "output") -> None:
    """.npy keeps float32 exactly; image formats get the 8-bit image, written by Pillow
    directly (imageio's plugin discovery would add ~0.1 s to every cold start). Written
    atomically (atomic.py): a failure or an interrupt leaves the previous file."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".npy":
        with atomic_open(path, what) as file:
            np.save(file, image)
        return
    if suffix == ".png":
        with atomic_open(path, what) as file:
            write_png(file, np.ascontiguousarray(image), PNG_LEVEL)
        return
    from PIL import Image

    if not IMAGE_FORMATS[suffix].alpha:
        # JPEG and BMP (as readers take it) keep no alpha. The color is already over the
        # background; alpha only marks translucent materials, which an opaque framebuffer
        # (OpenGL's default) shows as RGB.
        image = image[:, :, :3]
    picture = Image.fromarray(np.ascontiguousarray(image))
    with atomic_path(path, what) as temporary:
        picture.save(temporary, format=IMAGE_FORMATS[suffix].pillow)
