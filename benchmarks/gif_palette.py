"""How much colour an animated GIF loses, per palette method: the numbers behind the GIF
encoder of `turntable` (assets/animation.py, docs/reliability.md#animations).

    python benchmarks/gif_palette.py            # Markdown table on stdout (~20 s on 2 cores)
    python benchmarks/gif_palette.py --picture docs/images/gif_palette.png   # and the crops
    python benchmarks/gif_palette.py --smoke    # does it still run? seconds, numbers mean nothing

A GIF frame holds at most 256 colours. Each method below turns the same turntable frames
(rendered once, kept as the PNG-exact RGB arrays) into GIF frames with Pillow, and the GIF
is decoded again and compared with the frames:

    error          per channel |GIF − frame| in 1/255: the mean and the 99th percentile
                   over all pixels and frames, and the maximum
    banding        the same after a 5 × 5 box blur of both: what the eye sees from a
                   normal distance (it averages dither noise away; contour rings stay).
                   The 99th percentile of this is the number that says "rings or not".
    size           bytes per frame of the GIF
    CPU            encoder CPU time per frame (process time; the load is printed)

The scenes: builtin:sphere and the Stanford bunny with the default viewer light (a few
hundred colours: smooth shading of one material), and examples/two_lights.toml (two
coloured lights: tens of thousands of colours).
"""

from __future__ import annotations

import argparse
import io
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from PIL import Image

from wgpu_shading import Renderer, load_scene, mesh_scene, turntable
from wgpu_shading.assets.animation import quantize_frame

ROOT = Path(__file__).resolve().parent.parent


def _pillow(method, dither: bool, sample_step: int = 1):
    def quantize(rgb: np.ndarray) -> Image.Image:
        image = Image.fromarray(rgb)
        source = Image.fromarray(np.ascontiguousarray(rgb[::sample_step, ::sample_step])) if sample_step > 1 else image
        palette = source.quantize(256, method=method)
        if not dither:
            return palette if sample_step == 1 else image.quantize(palette=palette, dither=Image.Dither.NONE)
        return image.quantize(palette=palette, dither=Image.Dither.FLOYDSTEINBERG)

    return quantize


Q = Image.Quantize
METHODS = {  # name → frame (H, W, 3) uint8 → "P" image
    "fast octree, no dither (before)": _pillow(Q.FASTOCTREE, False),
    "median cut, no dither (imageio's GIF writer)": _pillow(Q.MEDIANCUT, False),
    "max coverage, no dither": _pillow(Q.MAXCOVERAGE, False),
    "fast octree + Floyd–Steinberg": _pillow(Q.FASTOCTREE, True),
    "median cut + Floyd–Steinberg": _pillow(Q.MEDIANCUT, True),
    "max coverage + Floyd–Steinberg": _pillow(Q.MAXCOVERAGE, True),
    "**chosen: max coverage, Floyd–Steinberg only where needed**": quantize_frame,
}


def box_blur(image: np.ndarray, k: int = 5) -> np.ndarray:
    """A k × k box blur (edges repeated), float64."""
    pad = k // 2
    padded = np.pad(image.astype(np.float64), ((pad, pad), (pad, pad), (0, 0)), mode="edge")
    sums = np.pad(padded.cumsum(0).cumsum(1), ((1, 0), (1, 0), (0, 0)))
    h, w = image.shape[:2]
    return (sums[k : k + h, k : k + w] - sums[:h, k : k + w] - sums[k : k + h, :w] + sums[:h, :w]) / (k * k)


def measure(frames: list[np.ndarray], quantize) -> dict:
    errors, blurred, size, cpu = [], [], 0, 0.0
    for frame in frames:
        start = time.process_time()
        encoded = io.BytesIO()
        quantize(frame).save(encoded, format="GIF")
        cpu += time.process_time() - start
        size += encoded.tell()
        back = _decoded_bytes(encoded.getvalue())
        errors.append(np.abs(back.astype(np.int16) - frame.astype(np.int16)).reshape(-1, 3))
        blurred.append(np.abs(box_blur(back) - box_blur(frame)).reshape(-1, 3))
    e, b = np.concatenate(errors), np.concatenate(blurred)
    return {
        "mean": e.mean(axis=0), "p99": np.percentile(e, 99, axis=0), "max": e.max(axis=0),
        "banding_p99": np.percentile(b, 99, axis=0), "kib": size / len(frames) / 1024, "ms": 1000 * cpu / len(frames),
    }  # fmt: skip


def _shared_models() -> Path | None:
    for folder in ROOT.parents:
        if (folder / "shared" / "models").is_dir():
            return folder / "shared" / "models"
    return None


def scenes(size: int) -> dict:
    found = {"builtin:sphere": mesh_scene("builtin:sphere"), "two_lights.toml": load_scene(ROOT / "examples" / "two_lights.toml")}
    models = _shared_models()
    if models is not None and (models / "stanford-bunny.obj").is_file():
        found["Stanford bunny"] = mesh_scene(str(models / "stanford-bunny.obj"))
    return {name: replace(scene, size=(size, size)) for name, scene in found.items()}


def _channels(values, digits: int = 1) -> str:
    return " / ".join(f"{v:.{digits}f}" if digits else f"{int(v)}" for v in values)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=384)
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("--smoke", action="store_true", help="tiny frames, one scene: does it still run?")
    parser.add_argument("--picture", metavar="PNG", help="also write 4× crops of a frame: PNG | before | chosen")
    args = parser.parse_args(argv)
    size, count = (32, 2) if args.smoke else (args.size, args.frames)
    renderer = Renderer()
    chosen = scenes(size)
    if args.smoke:
        chosen = dict(list(chosen.items())[:1])
    print(f"{count} turntable frames of {size}×{size} per scene; load average {open('/proc/loadavg').read().split()[0]}"
          if os.path.exists("/proc/loadavg") else f"{count} frames of {size}×{size}")
    print()
    print("| scene | method | error mean R/G/B | error p99 | error max | banding p99 (5×5 blur) | KiB/frame | CPU ms/frame |")
    print("|---|---|---|---|---|---|---:|---:|")
    crops = []
    for name, scene in chosen.items():
        frames = [np.ascontiguousarray(f.color[:, :, :3]) for f in renderer.render_many(turntable(scene, count))]
        crops.append([(f"{name}: {label}", _crop(image)) for label, image in _compared(frames[0])])
        for method, quantize in METHODS.items():
            r = measure(frames, quantize)
            print(f"| {name} | {method} | {_channels(r['mean'], 2)} | {_channels(r['p99'], 0)} | {_channels(r['max'], 0)} | "
                  f"{_channels(r['banding_p99'])} | {r['kib']:.1f} | {r['ms']:.0f} |")
    if args.picture:
        from wgpu_shading.assets.images import write_image
        from wgpu_shading.study.accuracy.pictures import contact_sheet

        write_image(args.picture, contact_sheet(crops))
        print(f"\nwrote {args.picture}")
    return 0


def _decoded(image: Image.Image) -> np.ndarray:
    encoded = io.BytesIO()
    image.save(encoded, format="GIF")
    return _decoded_bytes(encoded.getvalue())


def _decoded_bytes(data: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"))


def _compared(frame: np.ndarray):
    before = METHODS["fast octree, no dither (before)"]
    return [("PNG", frame), ("GIF before", _decoded(before(frame))), ("GIF now", _decoded(quantize_frame(frame)))]


def _crop(image: np.ndarray) -> np.ndarray:
    """A quarter of the image's side from its middle, shown 4× (each pixel a 4 × 4 block)."""
    h, w = image.shape[:2]
    part = image[h * 3 // 8 : h * 5 // 8, w * 3 // 8 : w * 5 // 8]
    return part.repeat(4, axis=0).repeat(4, axis=1)


if __name__ == "__main__":
    sys.exit(main())
