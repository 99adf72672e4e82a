"""Big dataset files written around the page cache (O_DIRECT), where the file system allows.

A dataset is written once and read later, usually by another process or machine; the kernel
still keeps every byte written in its page cache, and taking a fresh page for it is the
single largest cost a frame adds to its rendering on the benchmark's VM: `perf` put 1.1 ms
of CPU a 512² colour + depth frame in copy_folio_from_iter_atomic, the copy into new
page-cache pages (~1 ms per MB, against ~0.14 ms per MB written with O_DIRECT). Writing the
depth and normal arrays (and 16-bit colour PNGs) direct took the batch's CPU from 14.5 to
13.1 ms a frame and its time inside chunks from 9.1 to 8.5 ms (docs/performance.md, "Where
a dataset frame goes"). Small files (8-bit PNGs, records) stay cached: for them the
device's latency would cost more than the copy.

O_DIRECT wants the buffer's address, the length and the file offset aligned to the device's
logical block (512 or 4096 bytes: open(2), "O_DIRECT"). So the whole file is built in an
aligned buffer of this thread (kept from one file to the next: a new one would take fresh
pages too), its whole 4 KiB blocks are written direct and the last part block the usual
way (one page cached; nothing padded to cut off again). A
file system without direct I/O (tmpfs on older kernels, some FUSE mounts) refuses the flag
with EINVAL (one system call a file, not worth remembering): that file is written the usual way.
Elsewhere than Linux there is no O_DIRECT and every file is written the usual way.
"""

from __future__ import annotations

import errno
import io
import os
import threading
from typing import BinaryIO, Callable

import numpy as np

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: no O_DIRECT either
    fcntl = None

ALIGNMENT = 4096  # a multiple of every logical block size Linux supports
# Smaller files are written through the page cache: a direct write costs ~150 µs of CPU
# whatever its size (the block layer, the device's interrupt), a cached one ~0.1 ms per
# 256 KiB here, and more once its pages are new to the VM (docs/performance.md).
SMALLEST_DIRECT_FILE = 512 << 10
DIRECT_FLAG = getattr(os, "O_DIRECT", 0) if fcntl is not None else 0  # 0: every file the usual way

_buffers = threading.local()  # this thread's aligned buffer (encoder threads each have one)


def _aligned(size: int) -> np.ndarray:
    """`size` bytes of this thread's buffer, its address aligned to ALIGNMENT."""
    buffer = getattr(_buffers, "buffer", None)
    if buffer is None or buffer.size < size:
        raw = np.empty(size + ALIGNMENT, np.uint8)
        start = (-raw.ctypes.data) % ALIGNMENT
        buffer = raw[start : start + size]
        _buffers.buffer = buffer
    return buffer[:size]


def write_bytes(file: BinaryIO, data: bytes) -> None:
    """Encoded contents (a PNG) into `file`, a new, empty file opened for binary writing."""
    if len(data) < SMALLEST_DIRECT_FILE or not DIRECT_FLAG:
        file.write(data)
        return

    def fill(view: np.ndarray) -> None:
        view[:] = np.frombuffer(data, np.uint8)

    _write(file, len(data), fill)


def write_npy(file: BinaryIO, array: np.ndarray, dtype=np.float32) -> None:
    """What np.save(file, array.astype(dtype)) writes, converted while it is copied into the
    buffer (no intermediate array)."""
    dtype = np.dtype(dtype)
    header_file = io.BytesIO()
    header = {"descr": np.lib.format.dtype_to_descr(dtype), "fortran_order": False, "shape": array.shape}
    np.lib.format.write_array_header_1_0(header_file, header)  # np.save's format for any header below 64 KiB
    header_bytes = np.frombuffer(header_file.getvalue(), np.uint8)
    size = len(header_bytes) + array.size * dtype.itemsize
    if size < SMALLEST_DIRECT_FILE or not DIRECT_FLAG:
        np.save(file, array.astype(dtype, copy=False))
        return

    def fill(view: np.ndarray) -> None:
        view[: len(header_bytes)] = header_bytes
        np.copyto(view[len(header_bytes) :].view(dtype).reshape(array.shape), array, casting="same_kind")

    _write(file, size, fill)


def _write(file: BinaryIO, size: int, fill: Callable[[np.ndarray], None]) -> None:
    """A file of exactly `size` bytes, which `fill(view)` puts into a uint8 view of that
    length: its whole blocks direct where the file system allows, the last part block the
    usual way (module docstring)."""
    buffer = _aligned(size)
    fill(buffer)
    file.flush()
    try:
        descriptor = file.fileno()
    except (AttributeError, io.UnsupportedOperation):  # an in-memory file: nothing to go around
        file.write(buffer.data)
        return
    view = memoryview(buffer.data)
    blocks = size - size % ALIGNMENT
    done = 0
    if _set_direct(descriptor, True):
        try:
            while done < blocks:
                written = os.write(descriptor, view[done:blocks])
                done += written
                if written % ALIGNMENT:  # a short write off a block boundary: the rest the usual way
                    break
        except OSError as error:
            if error.errno != errno.EINVAL or done:  # EINVAL at the first write: another alignment wanted
                raise
        finally:
            _set_direct(descriptor, False)
    while done < size:
        done += os.write(descriptor, view[done:size])


def _set_direct(descriptor: int, direct: bool) -> bool:
    """Switch O_DIRECT on or off for an open file; False where the file system refuses it."""
    flags = fcntl.fcntl(descriptor, fcntl.F_GETFL)
    try:
        fcntl.fcntl(descriptor, fcntl.F_SETFL, (flags | DIRECT_FLAG) if direct else (flags & ~DIRECT_FLAG))
    except OSError as error:
        if error.errno != errno.EINVAL:
            raise
        return False
    return True
