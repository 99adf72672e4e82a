"""Keeping the driver's per-frame scratch memory mapped from one frame to the next.

lavapipe bins every frame's triangles on its queue thread into scratch blocks it takes
from malloc and frees when the frame is done (64 KiB blocks, ~2.4 MB for the 10K torus at
512²). glibc gives a thread's freed memory back to the kernel once the free space at the
top of its heap exceeds the trim threshold, and every page given back is faulted in and
zeroed again by the next frame: ~600 page faults a frame, which doubled the CPU time of
that thread (1.0 → 2.4 ms of a ~5 ms frame; docs/performance.md, "The small torus frame").

glibc's thresholds are dynamic (mallopt(3), M_MMAP_THRESHOLD: "when blocks larger than
the current threshold [...] are freed, the threshold is adjusted upward to the size of the
freed block", and the trim threshold to twice that). A process that never freed a block
larger than a small frame's image (1 MiB at 512²) trims at 2 MiB, below what one frame
bins. Freeing one untouched block of PRIMED_BYTES once moves the process to the thresholds
it would reach by itself after handling any array of that size (it costs an mmap and a
munmap, no page is touched), and glibc keeps adjusting them upward as before: unlike
mallopt(M_TRIM_THRESHOLD), which would freeze them. Only glibc is concerned; elsewhere
this does nothing. WGPU_SHADING_FRAME_MEMORY=0 leaves the allocator alone.
"""

from __future__ import annotations

import ctypes
import os
import sys

# Allocations up to 4 MiB then come from the heaps and up to 8 MiB free at a heap's top
# stays mapped: above a small frame's scratch (2.4 MB at 512²), and small enough that the
# memory a process keeps is bounded by a few MiB per thread heap. Bigger frames raise the
# thresholds by themselves (their images are bigger blocks); 16 MiB made freed mesh-sized
# arrays stay in the heaps, so that a new upload reused them (tests/test_memory.py).
PRIMED_BYTES = 4 << 20
SWITCH_ENVIRONMENT_VARIABLE = "WGPU_SHADING_FRAME_MEMORY"


def keep_frame_memory_mapped() -> bool:
    """Raise glibc's dynamic mmap and trim thresholds as freeing a PRIMED_BYTES block does
    (module docstring). True when it did; False on another C library or when switched off.
    Idempotent and thread-safe (malloc and free are)."""
    if os.environ.get(SWITCH_ENVIRONMENT_VARIABLE, "1").strip() == "0" or not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None)
        libc.gnu_get_libc_version  # glibc only: musl's thresholds are not dynamic
    except (OSError, AttributeError):
        return False
    libc.malloc.restype = ctypes.c_void_p
    libc.malloc.argtypes = [ctypes.c_size_t]
    libc.free.argtypes = [ctypes.c_void_p]
    block = libc.malloc(PRIMED_BYTES)
    if not block:
        return False
    libc.free(block)
    return True
