"""The cache folder: arrays kept on disk under a key, for work that a later process would
otherwise do again (a mesh file's parse and normals: mesh_cache.py; a mesh's vertex-cache
order: render/gpu/order_cache.py).

A key is a hash of everything an entry follows from (the callers say what), so an entry is
never stale, only unused. Where: the folder `$WGPU_SHADING_MESH_CACHE`, else
`$XDG_CACHE_HOME/wgpu-shading/meshes` (`~/.cache/...`); `WGPU_SHADING_MESH_CACHE=off` turns
it off. At most `$WGPU_SHADING_MESH_CACHE_MB` MiB (default 1024) for all entries: those used
least recently go first (a hit marks its entry used), and an entry over half of that is not
written.

An entry is one file: a magic line, a JSON header (the arrays' types, shapes and offsets,
a CRC-32 of their bytes, the caller's own fields), the arrays 64-byte aligned. It is written
atomically (assets/atomic.py) and read straight into arrays that own their memory (no
copy). A damaged or foreign entry is removed and reads as a miss. Nothing here ever fails
the caller: a folder that cannot be written, a full disk, an unreadable entry only mean
the work is done again.
"""

from __future__ import annotations

import json
import logging
import os
import stat
import struct
import time
import warnings
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from ..errors import WgpuShadingError
from .atomic import atomic_write, is_temporary

CACHE_VARIABLE = "WGPU_SHADING_MESH_CACHE"  # a folder, or "off"
SIZE_VARIABLE = "WGPU_SHADING_MESH_CACHE_MB"
DEFAULT_MEGABYTES = 1024
SUFFIX = ".entry"
TEMPORARY_TAG = "cache-"
_MAGIC = b"wgpu-shading cache entry 1\n"
_LENGTH = struct.Struct("<Q")  # the JSON header's length, after the magic line
_ALIGN = 64  # each array starts at a multiple of this
_TYPES = frozenset({"<f4", "<f8", "<u4", "<u2", "|u1", "<i4", "<i8"})  # what an entry may hold
_STALE_TEMPORARY_SECONDS = 3600  # a temporary this old was left by a process killed outright
logger = logging.getLogger(__name__)

Allocate = Callable[[str, np.dtype, tuple], np.ndarray]  # (name, type, shape) → where to read an array into


class DamagedEntry(ValueError):
    """An entry that is not what this module writes (read as a miss, and removed)."""


@dataclass(frozen=True)
class DiskCache:
    folder: Path
    max_bytes: int

    def path(self, key: str) -> Path:
        return self.folder / f"{key}{SUFFIX}"

    def read(self, key: str, allocate: Allocate | None = None) -> tuple[dict[str, np.ndarray], dict] | None:
        """The arrays (read-only, owning their memory unless `allocate` gave them) and the
        fields kept under `key`, or None."""
        path = self.path(key)
        try:
            # (non-blocking: a FIFO put in an entry's place is refused at once, never waited on)
            with os.fdopen(os.open(path, os.O_RDONLY | os.O_NONBLOCK), "rb") as file:
                status = os.fstat(file.fileno())
                if not stat.S_ISREG(status.st_mode):
                    raise DamagedEntry("not a regular file")
                found = _read_entry(file, status.st_size, allocate)
        except FileNotFoundError:
            return None
        except Exception as error:  # damaged, foreign, unreadable: never a reason to fail the caller
            logger.debug("cache entry %s not used: %s", path, error)
            _remove(path)
            return None
        try:
            os.utime(path)  # used now: the least recently used go first
        except OSError:
            pass
        return found

    def usage(self) -> tuple[int, int]:
        """(entries, bytes) kept now (none where the folder is not there yet)."""
        try:
            sizes = [size for _, size, _ in _entries(self.folder)]
        except OSError:
            sizes = []
        return len(sizes), sum(sizes)

    def discard(self, key: str) -> None:
        """Remove the entry under `key` (one its caller found wrong)."""
        _remove(self.path(key))

    def write(self, key: str, arrays: dict[str, np.ndarray], fields: dict) -> None:
        """Keep `arrays` and `fields` (JSON) under `key`, unless they are over half the cache;
        then trim the cache to its size."""
        if sum(array.nbytes for array in arrays.values()) > self.max_bytes // 2:
            return
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            atomic_write(self.path(key), lambda file: _write_entry(file, arrays, fields), "cache entry", WgpuShadingError, TEMPORARY_TAG)
            trim(self.folder, self.max_bytes)
        except Exception as error:  # a full disk, a folder that cannot be written: the work is done again next time
            logger.debug("cache entry %s not written: %s", self.path(key), error)


def code_hash(versions: str, sources: list[Path], root: Path) -> str:
    """SHA-256 of the code an entry's work follows from: `versions` (this entry format, the
    libraries' versions) and each of `sources` (its path under `root`, and its bytes)."""
    import hashlib  # (~3 ms of OpenSSL: only once the cache is asked for something)

    digest = hashlib.sha256(versions.encode())
    for source in sources:
        digest.update(b"\0" + source.relative_to(root).as_posix().encode() + b"\0" + source.read_bytes())
    return digest.hexdigest()


def disk_cache() -> DiskCache | None:
    """The cache as the environment sets it now (read at each use: a test or a service may
    change it), or None when it is off."""
    chosen = os.environ.get(CACHE_VARIABLE, "").strip()
    if chosen.lower() in ("off", "0", "no", "false"):
        return None
    if chosen:
        folder = Path(chosen)
    else:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        folder = Path(base) / "wgpu-shading" / "meshes"
    text = os.environ.get(SIZE_VARIABLE, "").strip()
    try:
        megabytes = float(text) if text else DEFAULT_MEGABYTES
    except ValueError:
        megabytes = -1.0
    if not megabytes >= 0:  # a bad value (a word, a negative size, NaN) does not stop a render: the default, and said
        warnings.warn(f"{SIZE_VARIABLE}={text!r} is not a number of MiB; the mesh cache keeps its default, {DEFAULT_MEGABYTES} MiB",
                      stacklevel=2)
        megabytes = DEFAULT_MEGABYTES
    if megabytes == 0:  # no room: off
        return None
    return DiskCache(folder, int(min(megabytes, 1 << 40) * (1 << 20)))


def trim(folder: Path, max_bytes: int) -> None:
    """Remove the least recently used entries until the folder's entries fit in max_bytes,
    and temporaries a killed process left (older than an hour)."""
    entries = _entries(folder, remove_stale=True)
    total = sum(size for _, size, _ in entries)
    for _, size, entry in sorted(entries):
        if total <= max_bytes:
            break
        _remove(Path(entry))
        total -= size


def _entries(folder: Path, remove_stale: bool = False) -> list[tuple[float, int, str]]:
    """(modification time, size, path) of each entry in `folder`; with remove_stale, the
    temporaries a killed process left (older than an hour) are removed on the way."""
    entries = []
    now = time.time()
    with os.scandir(folder) as listing:
        for item in listing:
            try:
                status = item.stat(follow_symlinks=False)
            except OSError:  # (removed meanwhile)
                continue
            if is_temporary(item.name):
                if remove_stale and is_temporary(item.name, TEMPORARY_TAG) and now - status.st_mtime > _STALE_TEMPORARY_SECONDS:
                    _remove(Path(item.path))
            elif item.name.endswith(SUFFIX):
                entries.append((status.st_mtime, status.st_size, item.path))
    return entries


def _remove(path: Path) -> None:
    try:
        path.unlink()
    except (OSError, ValueError):
        pass


def _padding(offset: int) -> int:
    return -offset % _ALIGN


def _write_entry(file, arrays: dict[str, np.ndarray], fields: dict) -> None:
    arrays = {name: np.ascontiguousarray(array) for name, array in arrays.items()}
    described, offset, crc = {}, 0, 0
    for name, array in arrays.items():
        offset += _padding(offset)
        described[name] = {"type": array.dtype.str, "shape": list(array.shape), "offset": offset}
        offset += array.nbytes
        crc = zlib.crc32(memoryview(array).cast("B"), crc)
    header = json.dumps({"arrays": described, "bytes": offset, "crc32": crc, "fields": fields}).encode()
    start = len(_MAGIC) + _LENGTH.size + len(header)
    file.write(_MAGIC + _LENGTH.pack(len(header)) + header + bytes(_padding(start)))
    written = 0
    for name, array in arrays.items():
        file.write(bytes(described[name]["offset"] - written))
        file.write(memoryview(array).cast("B"))
        written = described[name]["offset"] + array.nbytes


def _read_entry(file, size: int, allocate: Allocate | None) -> tuple[dict[str, np.ndarray], dict]:
    if file.read(len(_MAGIC)) != _MAGIC:
        raise DamagedEntry("not an entry of this format")
    (length,) = _LENGTH.unpack(file.read(_LENGTH.size))
    if length > size:
        raise DamagedEntry("header past the end")
    header = json.loads(file.read(length))
    start = len(_MAGIC) + _LENGTH.size + length
    start += _padding(start)
    if start + int(header["bytes"]) != size:
        raise DamagedEntry("sizes disagree")
    arrays, crc = {}, 0
    for name, described in header["arrays"].items():
        if described["type"] not in _TYPES:
            raise DamagedEntry(f"array {name!r} of type {described['type']!r}")
        dtype, shape = np.dtype(described["type"]), tuple(int(n) for n in described["shape"])
        if min(shape, default=0) < 0 or int(described["offset"]) + dtype.itemsize * int(np.prod(shape)) > int(header["bytes"]):
            raise DamagedEntry(f"array {name!r} past the end")
        array = np.empty(shape, dtype) if allocate is None else allocate(name, dtype, shape)
        file.seek(start + int(described["offset"]))
        view = memoryview(array).cast("B")
        if file.readinto(view) != array.nbytes:
            raise DamagedEntry("short read")
        crc = zlib.crc32(view, crc)
        if allocate is None:
            array.setflags(write=False)  # read-only and owning its memory: a Mesh keeps it as it is
        arrays[name] = array
    if crc != int(header["crc32"]):
        raise DamagedEntry("damaged (CRC-32)")
    return arrays, header["fields"]
