"""Animation files: frames encoded to a looping GIF (Pillow) or an MP4 (imageio-ffmpeg)."""

from __future__ import annotations

import io
import math
import os
import queue
import struct
import threading
from pathlib import Path
from typing import Callable, Iterable

import numpy as np

from ..errors import SceneError, UsageError
from .atomic import atomic_path
from .image_writers import output_path

ANIMATION_SUFFIXES = (".gif", ".mp4")
# GIF stores a frame's delay in hundredths of a second, 1..65535.
MIN_FPS, MAX_FPS = 0.01, 1000.0



def check_animation_path(path: Path) -> None:
    """One-line errors for what write_animation cannot do, before any rendering starts."""
    output_path(path, ANIMATION_SUFFIXES)
    if path.suffix.lower() == ".mp4":
        try:
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            from ..errors import install_hint

            raise UsageError(
                f"output {str(path)!r}: writing MP4 needs imageio-ffmpeg ({install_hint('video')}), or write a .gif"
            ) from None


def write_animation(
    path: str | os.PathLike[str],
    frames: Iterable[np.ndarray],
    *,
    fps: float = 30.0,
    progress: Callable[[int], None] | None = None,
) -> int:
    """Write RGBA or RGB uint8 frames to an animated GIF (looping) or an MP4 (H.264).

    Frames are encoded on a worker thread while the next ones are rendered: the H.264
    encoder is a separate ffmpeg process; Pillow's GIF palette work holds the GIL while it
    runs, so it overlaps the renderer's native work (lavapipe's threads) only. A GIF frame's
    palette is its own (`quantize_frame`). Returns the number of frames written.

    The frames stream into a temporary file beside `path` (atomic.py), renamed over `path`
    once the last frame is written: a failure or an interrupt leaves the previous file (or
    none) and removes the temporary.
    """
    path = Path(path)
    check_animation_path(path)
    if not (isinstance(fps, (int, float)) and MIN_FPS <= fps <= MAX_FPS):
        raise UsageError(f"fps must be between {MIN_FPS:g} and {MAX_FPS:g} frames per second, got {fps!r}")
    with atomic_path(path) as temporary:
        encoder = _GifEncoder(temporary, fps, path) if path.suffix.lower() == ".gif" else _Mp4Encoder(temporary, fps, path)
        return _stream(encoder, frames, progress)


def _stream(encoder, frames: Iterable[np.ndarray], progress: Callable[[int], None] | None) -> int:
    work: queue.Queue = queue.Queue(maxsize=4)  # bounded: rendering may run ahead only a little
    failure: list[BaseException] = []

    def worker() -> None:
        while (frame := work.get()) is not None:
            if not failure:
                try:
                    encoder.add(frame)
                except BaseException as error:  # reported on the main thread
                    failure.append(error)

    thread = threading.Thread(target=worker, name="wgpu-shading-encoder", daemon=True)
    thread.start()
    count = 0
    try:
        try:
            for frame in frames:  # consumed one at a time: a lazy source is never held whole
                if failure:
                    break
                work.put(np.asarray(frame)[:, :, :3])  # no alpha: GIF and H.264 are opaque
                count += 1
                if progress is not None:
                    progress(count)
        finally:
            work.put(None)
            thread.join()
        if failure:
            raise failure[0]
        encoder.close()
    except BaseException:
        encoder.abort()  # the temporary is removed by atomic_path
        raise
    return count


# The GIF palette of a frame (benchmarks/gif_palette.py measured the choices; the table is in
# docs/reliability.md#animations). Frames of up to FEW_COLOURS colours (smooth shading of one
# material: hundreds) are first mapped without dithering, kept when no channel of any pixel
# moves by more than UNDITHERED_TOLERANCE/255 (steps that small draw no visible ring). The
# palette of the others is chosen from an even grid of about PALETTE_SAMPLE_PIXELS pixels
# (every 4th pixel of every 4th row at 512²): a third of the work at 512², the same error.
FEW_COLOURS = 4096
UNDITHERED_TOLERANCE = 2
PALETTE_SAMPLE_PIXELS = 16384


def quantize_frame(rgb: np.ndarray):
    """An (H, W, 3) uint8 frame as the 256-colour Pillow "P" image a GIF frame holds.

    A palette of the frame's own, chosen by maximum coverage. Where it holds the frame within
    2/255 (always, for 256 colours or fewer: exactly) the frame is mapped onto it as it is;
    otherwise with Floyd–Steinberg error diffusion, which trades contour rings for fine noise.
    (The fast octree palette without dithering used before drew contour rings on smooth
    shading.) A palette per frame keeps the GIF streaming: one frame in memory, whatever the
    animation's length."""
    from PIL import Image

    frame = np.ascontiguousarray(rgb[:, :, :3], dtype=np.uint8)
    image = Image.fromarray(frame)
    if image.getcolors(FEW_COLOURS) is not None:  # None: more colours than that
        mapped = image.quantize(256, method=Image.Quantize.MAXCOVERAGE)
        error = np.abs(np.asarray(mapped.convert("RGB"), dtype=np.int16) - frame).max()
        if error <= UNDITHERED_TOLERANCE:
            return mapped
    step = max(1, math.ceil(math.sqrt(frame.shape[0] * frame.shape[1] / PALETTE_SAMPLE_PIXELS)))
    sample = np.ascontiguousarray(frame[::step, ::step])
    palette = Image.fromarray(sample).quantize(256, method=Image.Quantize.MAXCOVERAGE)
    return image.quantize(palette=palette, dither=Image.Dither.FLOYDSTEINBERG)


class _GifEncoder:
    """A looping animated GIF written frame by frame: memory stays at one frame however
    long the animation (Pillow's own multi-frame writer keeps every frame until the end).

    Each frame is quantized (`quantize_frame`) and LZW-encoded by Pillow as a one-frame GIF;
    its palette becomes the frame's local color table and its image block is appended to the
    file."""

    def __init__(self, path: Path, fps: float, shown: Path):
        self.path, self.shown = path, shown  # the temporary written, the name the user gave
        self.delay = min(65535, max(1, round(100.0 / fps)))  # GIF counts in hundredths of a second
        self.file = None
        self.size: tuple[int, int] | None = None
        self.count = 0

    def add(self, rgb: np.ndarray) -> None:
        height, width = rgb.shape[:2]
        image = quantize_frame(rgb)
        encoded = io.BytesIO()
        image.save(encoded, format="GIF", interlace=False)
        color_table, image_block = _split_single_frame_gif(encoded.getvalue())
        if self.file is None:
            self.size = (width, height)
            self.file = open(self.path, "wb")
            self.file.write(b"GIF89a" + struct.pack("<HHBBB", width, height, 0x70, 0, 0))  # no global table
            self.file.write(b"\x21\xff\x0bNETSCAPE2.0\x03\x01\x00\x00\x00")  # loop forever
        elif (width, height) != self.size:
            raise SceneError(f"{self.shown}: frame {self.count + 1} is {width}×{height}, the first was {self.size[0]}×{self.size[1]}")
        # Graphic control extension: no disposal, the frame's delay, no transparency.
        self.file.write(b"\x21\xf9\x04\x04" + struct.pack("<H", self.delay) + b"\x00\x00")
        self.file.write(image_block[:9])  # image separator, position and size
        table_bits = max(0, (len(color_table) // 3).bit_length() - 2)  # 2^(bits+1) entries
        self.file.write(bytes([0x80 | (image_block[9] & 0x40) | table_bits]))  # a local color table; interlace as encoded
        self.file.write(color_table)
        self.file.write(image_block[10:])  # LZW data
        self.file.flush()  # on disk as it comes (and a long run's progress is visible)
        self.count += 1

    def close(self) -> None:
        if self.file is None:
            raise SceneError(f"{self.shown}: no frames to write")
        self.file.write(b"\x3b")
        self.file.close()

    def abort(self) -> None:
        if self.file is not None:
            self.file.close()


def _split_single_frame_gif(data: bytes) -> tuple[bytes, bytes]:
    """(color table, image block) of a one-frame GIF as Pillow writes it: the table is the
    global one (Pillow writes its palette there), the block runs from the image separator
    through the LZW data's terminator."""
    flags = data[10]
    position = 13
    if not flags & 0x80:
        raise ValueError("a one-frame GIF without a global color table")
    table_size = 3 * (1 << ((flags & 0x07) + 1))
    color_table = data[position : position + table_size]
    position += table_size
    while data[position] == 0x21:  # skip extensions: label, then sub-blocks up to a 0
        position += 2
        while data[position]:
            position += data[position] + 1
        position += 1
    if data[position] != 0x2C:
        raise ValueError("no image descriptor in the encoded frame")
    start = position
    image_flags = data[position + 9]
    if image_flags & 0x80:  # a local table after all: use it instead
        local_size = 3 * (1 << ((image_flags & 0x07) + 1))
        color_table = data[position + 10 : position + 10 + local_size]
        block = data[start : start + 10] + data[start + 10 + local_size :]
    else:
        block = data[start:]
    end = block.rfind(b"\x3b")
    return color_table, block[:end]


class _Mp4Encoder:
    """H.264 in an MP4 by the ffmpeg that imageio-ffmpeg ships, fed raw RGB frames on its
    standard input. ffmpeg is run here rather than through imageio's writer so that its
    diagnostics go to a file, not the terminal: a failure (a full disk) is one line naming
    the output, with ffmpeg's last line as the reason."""

    def __init__(self, path: Path, fps: float, shown: Path):
        self.path, self.shown, self.fps = path, shown, fps
        self.process = None
        self.log = None
        self.size: tuple[int, int] | None = None

    def _start(self, width: int, height: int) -> None:
        import subprocess
        import tempfile
        from fractions import Fraction

        import imageio_ffmpeg

        rate = str(Fraction(self.fps).limit_denominator())
        command = [
            imageio_ffmpeg.get_ffmpeg_exe(), "-nostdin", "-y", "-v", "error",
            "-f", "rawvideo", "-vcodec", "rawvideo", "-s", f"{width}x{height}", "-pix_fmt", "rgb24", "-r", rate, "-i", "-",
            "-an", "-vcodec", "libx264", "-pix_fmt", "yuv420p", "-crf", "10",
            # yuv420p needs even sides: odd ones are padded by a row or column (not scaled).
            "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",
            "-f", "mp4", str(self.path),
        ]  # fmt: skip
        self.log = tempfile.TemporaryFile()
        self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=self.log)
        self.size = (width, height)

    def add(self, rgb: np.ndarray) -> None:
        height, width = rgb.shape[:2]
        if self.process is None:
            self._start(width, height)
        elif (width, height) != self.size:
            raise SceneError(f"{self.shown}: frame {width}×{height} differs from the first, {self.size[0]}×{self.size[1]}")
        try:
            self.process.stdin.write(np.ascontiguousarray(rgb, dtype=np.uint8).tobytes())
        except (BrokenPipeError, OSError):
            self.process.wait()
            raise UsageError(f"output {str(self.shown)!r} could not be written: {self._reason()}") from None

    def close(self) -> None:
        if self.process is None:
            raise SceneError(f"{self.shown}: no frames to write")
        try:
            self.process.stdin.close()
        except OSError:
            pass
        if self.process.wait() != 0:
            raise UsageError(f"output {str(self.shown)!r} could not be written: {self._reason()}")
        self.log.close()

    def abort(self) -> None:
        if self.process is not None:
            self.process.kill()
            self.process.wait()
        if self.log is not None:
            self.log.close()

    def _reason(self) -> str:
        """ffmpeg's last line of diagnostics (its earlier lines repeat it), e.g. "No space left on device"."""
        self.log.seek(0)
        lines = [line.strip() for line in self.log.read()[-4096:].decode("utf-8", "replace").splitlines() if line.strip()]
        return f"ffmpeg failed: {lines[-1]}" if lines else f"ffmpeg exited with status {self.process.returncode}"
