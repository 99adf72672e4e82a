"""Mesh files read once: the Mesh a file gave, kept in the cache folder (disk_cache.py), so
that the file read again (the next dataset run, the next `render` of it, a test suite's
next session) is not parsed again. The bunny's OBJ: ~45 ms to parse and give normals, ~2.5
ms to hash and read back.

An entry's key is everything its Mesh follows from:
- the file's bytes (SHA-256; its size, modification time and inode are compared again once
  it is read, and a file that changed meanwhile is not kept),
- its name (parts are named after it) and the crease angle,
- the code that reads it: a hash of the sources of `assets/` and `scene/` and numpy's version.
Only files whose Mesh follows from their own bytes are kept (`MeshFile.self_contained`: no
material library, image or other file read beside it, and everything the user is told in
its notes, which a hit says again); glTF files, and files trimesh reads, never. Files
under MIN_FILE_BYTES parse in about the time a lookup takes and are not kept.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..scene.geometry.mesh import Mesh, MeshPart
from .disk_cache import DamagedEntry, DiskCache, code_hash, disk_cache

MIN_FILE_BYTES = 16 << 10
_ARRAYS = ("positions", "normals", "indices", "uvs", "colors", "tangents", "line_indices", "extra_uvs")  # the Mesh's


@lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """A hash of what turns a file's bytes into a Mesh: the sources of assets/ and scene/
    and numpy's version, once a process (~3 ms), when it first uses the cache (sources
    edited under a running process are not what it runs)."""
    package = Path(__file__).resolve().parent.parent
    sources = [source for tree in ("assets", "scene") for source in sorted((package / tree).rglob("*.py"))]
    return code_hash(f"mesh 1 numpy {np.__version__}", sources, package)


def file_identity(path: Path) -> tuple[int, int, int, int]:
    """(size, modification time in ns, inode, device): what says a file was not changed
    between its hash and its parse."""
    status = os.stat(path)
    return status.st_size, status.st_mtime_ns, status.st_ino, status.st_dev


@dataclass(frozen=True)
class MeshEntry:
    """One mesh file's entry, found or to be written."""

    cache: DiskCache
    key: str
    file: Path  # the mesh file
    identity: tuple[int, int, int, int]  # its size, modification time, inode, device when hashed

    def load(self, name: str) -> tuple[Mesh, list[str]] | None:
        """The Mesh kept for this file (named `name`) and its notes, or None."""
        found = self.cache.read(self.key)
        if found is None:
            return None
        try:
            return _mesh(*found, name)
        except Exception:  # an entry no Mesh can be made of: removed, and the file parsed (disk_cache.py)
            self.cache.discard(self.key)
            return None

    def keep(self, mesh: Mesh, notes: list[str]) -> None:
        """Keep `mesh` and `notes` as this file's entry, unless the file changed since it was hashed."""
        try:
            if file_identity(self.file) != self.identity:
                return
        except OSError:
            return
        arrays = {key: getattr(mesh, key) for key in _ARRAYS if getattr(mesh, key) is not None}
        fields = {
            "origin": list(mesh.origin),
            "parts": [[part.first, part.count, part.name, part.primitive] for part in mesh.parts],
            "notes": list(notes),
        }
        self.cache.write(self.key, arrays, fields)


def mesh_entry(path: Path, file_size: int, crease_angle: float) -> MeshEntry | None:
    """The entry a mesh file's load would use, or None (the cache off, a small file, a file
    that cannot be read now: the reader then says why)."""
    if file_size < MIN_FILE_BYTES:
        return None
    cache = disk_cache()
    if cache is None:
        return None
    import hashlib  # (~3 ms of OpenSSL: only once a file big enough to keep is read)

    try:
        identity = file_identity(path)
        content = _file_hash(path, identity[0])
        fingerprint = code_fingerprint()
    except OSError:
        return None
    if content is None:  # (the file grew while hashed: not kept, and parsed as it is)
        return None
    key = hashlib.sha256(f"mesh\0{content}\0{path.name}\0{float(crease_angle)!r}\0{fingerprint}".encode()).hexdigest()[:40]
    return MeshEntry(cache, key, path, identity)


def _file_hash(path: Path, size: int) -> str | None:
    """SHA-256 of the file's first `size` bytes, or None if it holds more by then: a file
    someone keeps writing is never read past the size its load was allowed."""
    import hashlib

    digest = hashlib.sha256()
    block = bytearray(1 << 20)
    left = size
    with open(path, "rb") as file:
        while left > 0:
            count = file.readinto(block)
            if not count:
                break
            digest.update(memoryview(block)[: min(count, left)])
            left -= count
        if left < 0 or file.read(1):
            return None
    return digest.hexdigest()


def _mesh(arrays: dict[str, np.ndarray], fields: dict, name: str) -> tuple[Mesh, list[str]]:
    if not set(arrays) <= set(_ARRAYS):
        raise DamagedEntry(f"arrays {sorted(arrays)}")
    vertices = len(arrays["positions"])
    for key in ("indices", "line_indices"):  # (the CRC says the bytes are as written; this, that they index the vertices)
        if key in arrays and arrays[key].size and int(arrays[key].max()) >= vertices:
            raise DamagedEntry("an index past the vertices")
    parts = tuple(MeshPart(int(first), int(count), None, str(part), str(primitive)) for first, count, part, primitive in fields["parts"])
    origin = tuple(float(value) for value in fields["origin"])
    if len(origin) != 3:
        raise DamagedEntry("origin")
    return Mesh(**arrays, origin=origin, name=name, parts=parts), [str(note) for note in fields["notes"]]
