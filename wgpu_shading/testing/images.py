"""The pixels of a golden-image test: any image to (H, W, 4) uint8, reference PNGs read
and written, and the difference image (log scale) a person looks at when a test fails.

Pure numpy (imageio for the files, imported when a file is read or written).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .tolerance import GoldenError

# None: the logarithmic scale below (the default); a number K: linear, |difference| × K.
DEFAULT_AMPLIFICATION: float | None = None
# Log scale: a difference of d/255 is drawn as 255·log2(1 + d)/8, so 1/255 → 32, 2 → 51,
# 8 → 101, 64 → 192, 255 → 255. A ×10 linear scale saturated at 26/255, so a one-pixel
# edge shift and a missing highlight looked alike; here every step stays visible and
# nothing saturates before the largest possible difference.
LOG_SCALE_TEXT = "log scale: drawn = 255·log2(1 + d)/8 for a difference of d/255 (1 → 32, 8 → 101, 64 → 192, 255 → 255)"


def diff_scale_text(amplification: float | None = DEFAULT_AMPLIFICATION) -> str:
    """How the diff image maps a difference to brightness, for reports and the PNG itself."""
    if amplification is None:
        return LOG_SCALE_TEXT
    return f"linear scale: drawn = d × {amplification:g} for a difference of d/255, clipped at 255"


def as_rgba8(image, what: str = "image") -> np.ndarray:
    """An (H, W, 4) uint8 copy of a uint8 image with 1, 3 or 4 channels, or of a float image
    in [0, 1] (rounded like the renderer's 8-bit target)."""
    array = np.asarray(image)
    if array.ndim == 2:
        array = array[:, :, None]
    if array.ndim != 3 or array.shape[2] not in (1, 3, 4) or array.shape[0] == 0 or array.shape[1] == 0:
        raise GoldenError(f"{what}: expected an (height, width, 1|3|4) image, got shape {array.shape}")
    if array.dtype == np.uint8:
        pass
    elif np.issubdtype(array.dtype, np.floating):
        if not np.isfinite(array).all():
            raise GoldenError(f"{what}: float image holds NaN or infinity")
        array = np.round(np.clip(array, 0.0, 1.0) * 255.0).astype(np.uint8)
    else:
        raise GoldenError(f"{what}: expected uint8 or float pixels, got {array.dtype}")
    if array.shape[2] == 1:
        array = np.repeat(array, 3, axis=2)
    if array.shape[2] == 3:
        array = np.concatenate([array, np.full(array.shape[:2] + (1,), 255, np.uint8)], axis=2)
    return np.ascontiguousarray(array)


def size_text(image: np.ndarray) -> str:
    """An image array's size as WIDTH×HEIGHT, for messages."""
    return f"{image.shape[1]}×{image.shape[0]}"


PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
MAX_REFERENCE_PIXELS = 16384 * 16384  # the largest image the renderer makes


def read_reference(path: str | os.PathLike[str]) -> tuple[np.ndarray, bool]:
    """A reference image: an 8-bit PNG, as (H, W, 4) uint8, and whether the file has an
    alpha channel. Anything else (another format under any name, 16-bit, palette-less
    oddities Pillow reads as something else, a damaged file) is a GoldenError that says so."""
    import imageio.v3 as iio

    from ..assets.files import check_regular_file
    from ..assets.textures import decoding_limits

    path = Path(path)
    where = f"reference {str(path)!r}"
    check_regular_file(path, where, GoldenError)  # a FIFO would block the read
    if not path.is_file():
        raise GoldenError(f"{where} does not exist")
    with open(path, "rb") as file:
        data = file.read()
    if not data.startswith(PNG_SIGNATURE):
        kind = "JPEG data" if data.startswith(b"\xff\xd8") else "data that is not PNG"
        raise GoldenError(f"{where}: references are 8-bit PNGs; this file holds {kind} (rewrite it with --update)")
    if data[12:16] == b"IHDR" and len(data) >= 26:
        # Pillow reads a 16-bit RGB(A) PNG as 8-bit without a word: the header decides.
        width, height = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
        if data[24] == 16:
            raise GoldenError(f"{where}: references are 8-bit PNGs; this one has uint16 pixels (16 bits per channel; rewrite it with --update)")
        if width * height > MAX_REFERENCE_PIXELS:
            raise GoldenError(f"{where}: {width}×{height} pixels; references of at most {MAX_REFERENCE_PIXELS} pixels are read")
    try:
        with decoding_limits():
            image = iio.imread(data, plugin="pillow")
    except Exception as error:  # Pillow raises many kinds for damaged files
        raise GoldenError(f"{where}: a damaged PNG ({type(error).__name__}: {error}); rewrite it with --update") from None
    if image.dtype != np.uint8:
        raise GoldenError(f"{where}: references are 8-bit PNGs; this one has {image.dtype} pixels (rewrite it with --update)")
    has_alpha = image.ndim == 3 and image.shape[2] in (2, 4)
    if image.ndim == 3 and image.shape[2] == 2:  # gray + alpha
        image = np.concatenate([np.repeat(image[:, :, :1], 3, axis=2), image[:, :, 1:]], axis=2)
    return as_rgba8(image, where), has_alpha


def read_image(path: str | os.PathLike[str]) -> np.ndarray:
    """An 8-bit PNG as (H, W, 4) uint8 (see read_reference)."""
    return read_reference(path)[0]


def write_image(path: str | os.PathLike[str], image, note: str | None = None) -> Path:
    """Write an image as an 8-bit RGBA PNG, creating the folder; `note` goes into the PNG's
    text chunk "Comment" (a diff image states its scale there). Written atomically
    (assets/atomic.py): a test reading the reference meanwhile (`pytest -n`) sees the old
    file or the new one, and a failure or an interrupt leaves the old one."""
    from PIL import Image
    from PIL.PngImagePlugin import PngInfo

    from ..assets.atomic import atomic_path

    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise GoldenError(f"{str(path)!r}: folder {str(path.parent)!r} cannot be made: {error.strerror or error}") from None
    info = PngInfo()
    if note:
        info.add_text("Comment", note)
    picture = Image.fromarray(as_rgba8(image))
    with atomic_path(path, "image", GoldenError) as temporary:
        picture.save(temporary, format="PNG", pnginfo=info)
    return path


def diff_image(actual, expected, amplification: float | None = DEFAULT_AMPLIFICATION) -> np.ndarray:
    """The difference as an opaque RGB(A) image: each color channel is |actual − expected|
    on the log scale (amplification None, the default: `LOG_SCALE_TEXT`) or × amplification
    (clipped to 255), so black means identical and the hue says which channel differs; an
    alpha difference shows in all three (gray/white)."""
    a = as_rgba8(actual, "actual").astype(np.int16)
    e = as_rgba8(expected, "expected").astype(np.int16)
    if a.shape != e.shape:
        raise GoldenError(f"diff image: sizes differ ({size_text(a)} vs {size_text(e)})")
    delta = np.abs(a - e)
    rgb = np.maximum(delta[:, :, :3], delta[:, :, 3:4])
    if amplification is None:
        scaled = 255.0 * np.log2(1.0 + rgb) / 8.0
    else:
        scaled = rgb * float(amplification)
    amplified = np.clip(np.round(scaled), 0, 255).astype(np.uint8)
    return np.concatenate([amplified, np.full(amplified.shape[:2] + (1,), 255, np.uint8)], axis=2)


LEGEND_HEIGHT = 34  # pixels added below a written diff image for its scale
_LEGEND_TICKS = (1, 8, 64, 255)


def with_scale_legend(diff: np.ndarray, amplification: float | None = DEFAULT_AMPLIFICATION) -> np.ndarray:
    """The diff image with its scale drawn below it (the file a person opens says how to read
    it): a ramp of how the diff draws differences, ticks at 1, 8, 64 and 255 (in 1/255) and a
    caption. The diff's own pixels keep their rows and columns. Images narrower than 160
    pixels are returned as they are (no room for labels); the PNG's text says the scale."""
    height, width = diff.shape[:2]
    if width < 160:
        return diff
    from PIL import Image, ImageDraw

    def drawn(d):  # the brightness the diff gives a difference of d/255
        return 255.0 * np.log2(1.0 + d) / 8.0 if amplification is None else d * float(amplification)

    def column(d):  # where the legend puts d: evenly on the log scale, or linearly
        fraction = np.log2(1.0 + d) / 8.0 if amplification is None else d / 255.0
        return int(round(fraction * (width - 1)))

    positions = np.linspace(0.0, 1.0, width)
    differences = 2.0 ** (positions * 8.0) - 1.0 if amplification is None else positions * 255.0
    ramp = np.clip(np.round(drawn(differences)), 0, 255).astype(np.uint8)
    legend = np.zeros((LEGEND_HEIGHT, width, 4), np.uint8)
    legend[..., 3] = 255
    legend[:8, :, :3] = ramp[None, :, None]
    canvas = Image.fromarray(legend)
    draw = ImageDraw.Draw(canvas)
    white = (255, 255, 255, 255)
    for tick in _LEGEND_TICKS:
        x = column(tick)
        draw.line([(x, 8), (x, 10)], fill=white)
        text = str(tick)
        text_width = draw.textlength(text)
        draw.text((min(max(x - text_width / 2, 0), width - text_width - 1), 11), text, fill=white)
    caption = "difference in 1/255, " + ("log scale" if amplification is None else f"linear ×{amplification:g}")
    draw.text((2, 22), caption, fill=white)
    return np.concatenate([as_rgba8(diff), np.asarray(canvas)], axis=0)
