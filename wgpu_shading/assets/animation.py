"""Animation files: frames encoded to a looping GIF (Pillow) or an MP4 (imageio-ffmpeg)."""

from __future__ import annotations

import os
import queue
import threading
from pathlib import Path
from typing import Callable, Iterable

import numpy as np

from ..errors import SceneError
from .images import output_path

ANIMATION_SUFFIXES = (".gif", ".mp4")



def check_animation_path(path: Path) -> None:
    """One-line errors for what write_animation cannot do, before any rendering starts."""
    output_path(path, ANIMATION_SUFFIXES)
    if path.suffix.lower() == ".mp4":
        try:
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            from ..errors import install_hint

            raise SceneError(
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

    Frames are encoded on a worker thread while the next ones are rendered: GIF palette
    quantization (Pillow) and the H.264 encoder (a separate ffmpeg process) both run
    outside the GIL. Returns the number of frames written.
    """
    path = Path(path)
    check_animation_path(path)
    encoder = _GifEncoder(path, fps) if path.suffix.lower() == ".gif" else _Mp4Encoder(path, fps)
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
        for frame in frames:
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
    return count


class _GifEncoder:
    def __init__(self, path: Path, fps: float):
        self.path = path
        self.duration_ms = 1000.0 / fps
        self.images: list = []

    def add(self, rgb: np.ndarray) -> None:
        from PIL import Image

        # An adaptive palette per frame (fast octree): smooth shading keeps its gradients,
        # unlike a fixed web palette.
        self.images.append(Image.fromarray(np.ascontiguousarray(rgb)).quantize(256, method=Image.Quantize.FASTOCTREE))

    def close(self) -> None:
        if not self.images:
            raise SceneError(f"{self.path}: no frames to write")
        first, *rest = self.images
        first.save(self.path, save_all=True, append_images=rest, duration=self.duration_ms, loop=0, optimize=False)


class _Mp4Encoder:
    def __init__(self, path: Path, fps: float):
        import imageio.v2 as imageio

        # yuv420p needs even sides; ffmpeg pads odd ones (macro_block_size=2) instead of scaling.
        self.writer = imageio.get_writer(
            path, format="FFMPEG", mode="I", fps=fps, codec="libx264", quality=8, macro_block_size=2
        )

    def add(self, rgb: np.ndarray) -> None:
        self.writer.append_data(rgb)

    def close(self) -> None:
        self.writer.close()
