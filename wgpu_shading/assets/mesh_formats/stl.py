"""Binary STL read with numpy, bounded by the file's size.

trimesh trusted the header's triangle count (a 1 KB file claiming 40M triangles reached
7 GB before "not enough memory", read again as ASCII text) and kept every corner as its own
float64 vertex (a valid 10M-triangle file peaked at 6.4 GB). Here the count is checked
against the file's size before anything is allocated, the corners are read in blocks into
one float32 array, and corners with equal coordinates are joined into one vertex at once
(STL repeats each vertex for every triangle around it; the crease normals weld by exact
position anyway, docs/conventions.md), so everything after works on ~1/6 of the vertices.
ASCII STL stays with trimesh.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.mesh import MAX_TRIANGLES

HEADER_BYTES = 84  # 80 bytes of free text, then the little-endian uint32 triangle count
RECORD = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])  # 50 bytes
# ASCII STL is read by trimesh, whose text parsing peaked at ~6x the file (a 16 MB file:
# 100k triangles, +80 MB resident); 512 MiB of text is ~3M triangles and ~3 GB.
MAX_ASCII_BYTES = 512 << 20
BLOCK = 1 << 16  # triangles read at a time: 3.3 MB of records besides the corners


def binary_stl_count(path: Path, where: str, file_size: int) -> int | None:
    """The triangle count of a binary STL (checked against the file's size), or None for an
    ASCII one (trimesh reads those)."""
    with open(path, "rb") as file:
        head = file.read(1024)
    count = int.from_bytes(head[80:84], "little") if len(head) >= HEADER_BYTES else -1
    if count >= 0 and HEADER_BYTES + RECORD.itemsize * count == file_size:
        if count > MAX_TRIANGLES:
            raise MeshError(f"{where}: {count} triangles; at most {MAX_TRIANGLES} are supported")
        return count  # binary, even when its free text starts with "solid" (many exporters do that)
    text = head.lstrip()
    if text[:5].lower() == b"solid" and _mostly_text(head):
        if file_size > MAX_ASCII_BYTES:
            raise MeshError(
                f"{where}: an ASCII STL of {file_size / 2**20:.0f} MiB; ASCII STL files up to {MAX_ASCII_BYTES >> 20} MiB "
                "are read (trimesh holds ~6 bytes per byte of text); save it as binary STL"
            )
        return None
    if count < 0:
        raise MeshError(f"{where}: not a valid STL file (shorter than a binary STL's 84-byte header, and not ASCII STL)")
    needed = HEADER_BYTES + RECORD.itemsize * count
    if count > MAX_TRIANGLES:
        raise MeshError(
            f"{where}: not a valid STL file: its header declares {count} triangles (at most {MAX_TRIANGLES} are supported) "
            f"in {file_size} bytes"
        )
    if needed > file_size:
        raise MeshError(
            f"{where}: not a valid STL file: its header declares {count} triangles, which need {needed} bytes, "
            f"but the file has {file_size} (truncated?)"
        )
    return count  # trailing bytes after the last triangle: read what the header declares


def read_binary_stl(path: Path, count: int) -> tuple[np.ndarray, np.ndarray]:
    """(positions (V, 3) float32, faces (F, 3) int64) with equal corners joined."""
    corners = np.empty((count * 3, 3), np.float32)
    with open(path, "rb") as file:
        file.seek(HEADER_BYTES)
        for start in range(0, count, BLOCK):
            records = np.fromfile(file, dtype=RECORD, count=min(BLOCK, count - start))
            corners[start * 3 : start * 3 + len(records) * 3] = records["corners"].reshape(-1, 3)
    corners += np.float32(0.0)  # -0.0 becomes 0.0: equal coordinates, equal bits
    return _join_equal(corners)


def _join_equal(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Equal rows of `corners` as one vertex: (positions, faces), sorted by their bits.
    np.unique(return_inverse=True) on 12-byte rows held five arrays of the corners' size at
    once; this holds the corners, one sort order and one sorted copy."""
    bits = corners.view(np.uint32)
    high = (bits[:, 0].astype(np.uint64) << np.uint64(32)) | bits[:, 1]
    order = np.lexsort((bits[:, 2], high))
    del high
    new = np.zeros(len(order), bool)
    new[:1] = True
    for column in range(3):  # one sorted column at a time, not a sorted copy of every corner
        ordered = bits[order, column]
        new[1:] |= ordered[1:] != ordered[:-1]
    del ordered
    positions = corners[order[new]]
    vertex = np.cumsum(new, dtype=np.int32)  # < 2^31: at most 3 · 2^25 corners
    vertex -= 1
    del new
    inverse = np.empty(len(order), np.int32)
    inverse[order] = vertex
    return positions, inverse.reshape(-1, 3)


def _mostly_text(head: bytes) -> bool:
    printable = sum(1 for byte in head if byte in b"\t\n\r" or 32 <= byte < 127)
    return printable >= 0.95 * len(head)
