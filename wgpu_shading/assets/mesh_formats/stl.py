"""Binary STL read with numpy, bounded by the file's size.

trimesh trusted the header's triangle count (a 1 KB file claiming 40M triangles reached
7 GB before "not enough memory", read again as ASCII text) and kept every corner as its own
float64 vertex (a valid 10M-triangle file peaked at 6.4 GB). Here the count is checked
against the file's size before anything is allocated, the corners are read in blocks into
one float32 array, and corners with equal coordinates are joined into one vertex at once
(STL repeats each vertex for every triangle around it; the crease normals weld by exact
position anyway, docs/conventions.md), so everything after works on ~1/6 of the vertices.
ASCII STL in the layout exporters write is read a block of lines at a time (stl_ascii.py),
any other through trimesh (trimesh_reader.py).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.geometry.mesh import MAX_TRIANGLES
from ..mesh_pieces import MeshFile, MeshPiece
from .corner_join import CornerJoin
from .stl_ascii import read_plain_ascii_stl
from .trimesh_reader import read_with_trimesh

HEADER_BYTES = 84  # 80 bytes of free text, then the little-endian uint32 triangle count
RECORD = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])  # 50 bytes
# An ASCII STL not in the plain layout (stl_ascii.py) is read by trimesh, whose text parsing
# peaked at ~6x the file (a 16 MB file: 100k triangles, +80 MB resident); 512 MiB of text is
# ~3M triangles and ~3 GB.
MAX_ASCII_BYTES = 512 << 20
BLOCK = 1 << 18  # triangles read at a time: 13 MB of records, and the block's corners


def read_stl(path: Path, file_size: int) -> MeshFile:
    """An STL file: binary with numpy; ASCII in blocks of lines when it is in the plain
    layout (stl_ascii.py), else through trimesh."""
    where = f"mesh file {str(path)!r}"
    try:
        count, notes = binary_stl_count(path, where, file_size)
        if count is None:
            piece = read_plain_ascii_stl(path, where, notes)
            if piece is not None:
                return MeshFile([piece], notes, self_contained=True)
            if file_size > MAX_ASCII_BYTES:
                raise MeshError(
                    f"{where}: an ASCII STL of {file_size / 2**20:.0f} MiB, not in the plain layout (a `solid`, facets "
                    f"of seven lines, one `endsolid`) that is read in blocks; others are read whole, up to "
                    f"{MAX_ASCII_BYTES >> 20} MiB (trimesh holds ~6 bytes per byte of text); save it as binary STL"
                )
            return read_with_trimesh(path, file_size)
        positions, faces = read_binary_stl(path, count)
    except OSError as error:
        raise MeshError(f"{where}: cannot be read ({error.strerror or error})") from None
    except MemoryError:
        raise MeshError(f"{where}: not enough memory to read {file_size} bytes of STL") from None
    return MeshFile([MeshPiece(positions, faces, parts=[(0, len(faces), None, path.name)])], notes, self_contained=True)


def binary_stl_count(path: Path, where: str, file_size: int) -> tuple[int | None, list[str]]:
    """The triangle count of a binary STL (checked against the file's size), or None for an
    ASCII one; and what to tell the user about it."""
    with open(path, "rb") as file:
        head = file.read(1024)
    count = int.from_bytes(head[80:84], "little") if len(head) >= HEADER_BYTES else -1
    if count >= 0 and HEADER_BYTES + RECORD.itemsize * count == file_size:
        if count > MAX_TRIANGLES:
            raise MeshError(f"{where}: {count} triangles; at most {MAX_TRIANGLES} are supported")
        return count, []  # binary, even when its free text starts with "solid" (many exporters do that)
    records, rest = divmod(file_size - HEADER_BYTES, RECORD.itemsize)
    if count == 0 and records > 0 and not rest:
        # A writer that streams its triangles may leave the count 0 (it cannot seek back):
        # the file's size says how many there are, as VTK's reader (f3d's) reads such files.
        # (Four zero bytes at 80..83: never ASCII text.)
        if records > MAX_TRIANGLES:
            raise MeshError(f"{where}: {records} triangles; at most {MAX_TRIANGLES} are supported")
        return records, [f"{where}: its header declares 0 triangles; read the {records} its {file_size} bytes hold"]
    if count == 0 and rest:
        raise MeshError(f"{where}: not a valid STL file: its header declares 0 triangles, and the {file_size - HEADER_BYTES} "
                        f"bytes after it are not whole {RECORD.itemsize}-byte triangles")
    text = head.lstrip()
    if text[:5].lower() == b"solid" and _mostly_text(head):
        return None, []
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
    return count, []  # trailing bytes after the last triangle: read what the header declares


def read_binary_stl(path: Path, count: int) -> tuple[np.ndarray, np.ndarray]:
    """(positions (V, 3) float32, faces (F, 3) uint32) with equal corners joined, the
    vertices sorted by their coordinates' bits (x, then y, then z, as unsigned integers):
    a block of triangles at a time (corner_join.py), then one pass over the corners'
    ids at the end to renumber them in sorted order."""
    corner_ids = np.empty(count * 3, np.uint32)
    join = CornerJoin(np.float32)
    with open(path, "rb") as file:
        file.seek(HEADER_BYTES)
        for start in range(0, count, BLOCK):
            records = np.fromfile(file, dtype=RECORD, count=min(BLOCK, count - start))
            ids = join.add(records["corners"].reshape(-1, 3))
            corner_ids[start * 3 : start * 3 + len(ids)] = ids
    positions = join.finish(corner_ids)
    return positions, corner_ids.reshape(-1, 3)


def _mostly_text(head: bytes) -> bool:
    printable = sum(1 for byte in head if byte in b"\t\n\r" or 32 <= byte < 127)
    return printable >= 0.95 * len(head)
