"""Writing one view's files: every file atomically (assets/atomic.py: a temporary name in the
same folder, then os.replace), the job's record (name.json: row digest, files, camera) last,
so a record on disk means every file it lists is complete. A process killed mid-write leaves
only a `.NAME.wgpu-shading-tmp-batch-*` file, which the next run removes
(remove_stale_temporaries) while it holds the folder's lock (dataset/lock.py)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Callable

import numpy as np

from ..assets import atomic
from ..assets.image_writers import depth_png
from ..assets.png import encode_png
from ..render.passes.extra_outputs import ExtraFrame
from ..render.renderer import Frame
from .direct_writes import write_bytes, write_npy
from .jobs import Job

BATCH_TAG = "batch-"  # marks the temporaries of dataset runs (removed by the next run only)


def atomic_write(path: Path, write: Callable[[object], object]) -> None:
    """Write through `write(file)` to a temporary file beside `path`, then rename it into place."""
    atomic.atomic_write(path, write, "batch output", tag=BATCH_TAG)


def json_text(value: object, depth: int = 0) -> bytes | str:
    """JSON with one key per line and every list on one line (a 4×4 matrix a row per line
    would not fit; json.dumps(indent=1) gave each number a line of its own and ran its
    pure-Python encoder, 5× slower than the C one used here for each value). Bytes at the
    top level, ready to write."""
    if isinstance(value, dict) and value:
        inner = " " * (depth + 1)
        text = "{\n" + ",\n".join(f"{inner}{json.dumps(str(key))}: {json_text(item, depth + 1)}" for key, item in value.items()) + "\n" + " " * depth + "}"
    else:
        text = json.dumps(value)
    return text.encode() if depth == 0 else text


def remove_stale_temporaries(folder: Path) -> int:
    """Delete the dataset temporaries left by killed writers in `folder` and its mesh folders
    (only while this run holds the folder's lock: no other run writes there)."""
    return atomic.remove_temporaries(folder, BATCH_TAG)


def _png(image: np.ndarray, level: int) -> Callable[[object], None]:
    # 8-bit RGBA, 16-bit RGBA (png16 colour) and 16-bit grey (ids): assets/png.py, at half
    # Pillow's CPU time; it writes 16-bit colour too, which Pillow cannot. Big files go
    # around the page cache (direct_writes.py), as the arrays below do.
    return lambda file: write_bytes(file, encode_png(image, level))


def _npy(array: np.ndarray) -> Callable[[object], None]:
    """float32 .npy (what np.save writes for array.astype(np.float32))."""
    return lambda file: write_npy(file, array, np.float32)


def color16(color: np.ndarray) -> np.ndarray:
    """A float32 [0, 1] target as 16-bit values (round to nearest)."""
    return np.round(np.clip(color, 0.0, 1.0) * 65535.0).astype(np.uint16)


def _depth_png(depth: np.ndarray, near: float, far: float, level: int) -> Callable[[object], None]:
    # The encoding of `render --depth d.png` (assets/image_writers.py), near and far in its text chunks.
    return lambda file: write_bytes(file, depth_png(depth, near, far, level))


def write_view(
    out_dir: Path, job: Job, frame: Frame | None, extra: ExtraFrame | None, camera: dict
) -> list[str]:
    """Every file of `job` from its rendered frame(s), then its record. Returns the files."""
    outputs, folder = job.outputs, out_dir / job.folder
    folder.mkdir(parents=True, exist_ok=True)
    level = outputs.compress_level
    written = []
    for file_name in outputs.file_names(job.name):
        path = folder / file_name
        if file_name == f"{job.name}.png":
            assert frame is not None
            write = _png(color16(frame.color) if outputs.color == "png16" else frame.color, level)
        elif "_depth." in file_name:
            assert frame is not None and frame.depth is not None
            if outputs.depth == "npy":
                write = _npy(frame.depth)
            else:
                write = _depth_png(frame.depth, camera["near"], camera["far"], level)
        elif "_normals_" in file_name:
            assert extra is not None
            write = _npy(extra.normals)
        else:
            assert extra is not None
            write = _png(np.asarray(extra.ids, dtype=np.uint16), level)
        atomic_write(path, write)
        written.append(f"{job.folder}/{file_name}")
    record = {"id": job.id, "digest": job.digest(), "source": job.source, "files": written, "camera": camera}
    atomic_write(out_dir / job.record_path(), lambda file: file.write(json_text(record)))
    return written


def finished(out_dir: Path, job: Job) -> dict | None:
    """The job's record when its outputs exist and were made from the same manifest row."""
    try:
        record = json.loads((out_dir / job.record_path()).read_text())
    except (OSError, ValueError):
        return None
    if record.get("digest") != job.digest() or record.get("files") != job.files():
        return None
    if not all((out_dir / file).is_file() for file in record["files"]):
        return None
    return record
