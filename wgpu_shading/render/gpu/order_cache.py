"""Vertex-cache orders kept in the cache folder (assets/disk_cache.py): a mesh uploaded again
in a later process (the next dataset run, the next `render` of the same file) is not
reordered again. meshoptimizer takes 0.2–0.35 µs a triangle (the bunny's 70K: 15 ms, a
1.3M-triangle sphere: 0.45 s); its order is read back in about the time its key takes.

The key is what the order follows from: the triangles' indices (SHA-256 of their bytes),
the vertex count, the parts' ranges and which keep their order, and the code that orders
them (vertex_order.py's source and meshoptimizer's version). Only the order of a first
upload is kept, not one with clusters (a cluster build is made on a worker thread after
the first frames: cluster_builds.py). Meshes under MIN_TRIANGLES are reordered in a few ms
(the default torus of `render builtin:torus`, whose cold start would pay more for the
imports of a lookup).
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ...assets.disk_cache import DiskCache

MIN_TRIANGLES = 16384


@lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """vertex_order.py's source and meshoptimizer's version (once a process)."""
    from importlib import metadata  # (~5 ms of imports with hashlib: only once a big mesh is uploaded)

    from ...assets.disk_cache import code_hash

    try:
        version = metadata.version("meshoptimizer")
    except metadata.PackageNotFoundError:
        version = "?"
    here = Path(__file__).resolve().parent
    return code_hash(f"order 1 meshoptimizer {version}", [here / "vertex_order.py"], here)


def order_key(flat: np.ndarray, vertex_count: int, parts, in_order: frozenset[int]) -> tuple[DiskCache, str] | None:
    """Where the order of these triangles would be kept, or None (the cache off, a small mesh)."""
    if flat.size < 3 * MIN_TRIANGLES:
        return None
    import hashlib

    from ...assets.disk_cache import disk_cache

    cache = disk_cache()
    if cache is None:
        return None
    try:
        fingerprint = code_fingerprint()
    except OSError:
        return None
    ranges = [(part.first, part.count, part.primitive) for part in parts]
    digest = hashlib.sha256(f"order\0{fingerprint}\0{vertex_count}\0{ranges}\0{sorted(in_order)}\0".encode())
    digest.update(memoryview(np.ascontiguousarray(flat, np.uint32)).cast("B"))
    return cache, digest.hexdigest()[:40]


def read_order(cache: DiskCache, key: str, ordered_into, index_count: int, vertex_count: int) -> np.ndarray | None:
    """The kept order's vertex gather, its reordered indices read into `ordered_into()` (a
    flat uint32 array of index_count, called once the entry is found), or None."""
    def allocate(name: str, dtype: np.dtype, shape: tuple) -> np.ndarray:
        if name == "ordered" and dtype == np.uint32 and shape == (index_count,):
            return ordered_into()
        if name == "gather" and dtype == np.uint32 and len(shape) == 1 and shape[0] <= vertex_count:
            return np.empty(shape, dtype)
        raise ValueError(f"kept order: {name} {dtype} {shape}")

    found = cache.read(key, allocate)
    if found is None:
        return None
    arrays, _ = found
    ordered, gather = arrays.get("ordered"), arrays.get("gather")
    # (the CRC says the bytes are as written; this, that they index what they should)
    if ordered is None or gather is None or (len(ordered) and int(ordered.max()) >= len(gather)) or (len(gather) and int(gather.max()) >= vertex_count):
        cache.discard(key)
        return None
    return gather


def keep_order(cache: DiskCache, key: str, ordered: np.ndarray, gather: np.ndarray) -> None:
    cache.write(key, {"ordered": ordered, "gather": gather}, {})
