"""Big dataset files written around the page cache (dataset/direct_writes.py): the bytes are
those np.save and the PNG encoder give, whatever the size and alignment; a file system that
refuses O_DIRECT gets the same bytes the usual way; the written pages are not cached."""

from __future__ import annotations

import ctypes
import io
import mmap
import os
import subprocess
import uuid
from pathlib import Path

import numpy as np
import pytest

from wgpu_shading.assets.atomic import atomic_write
from wgpu_shading.dataset import direct_writes

needs_direct = pytest.mark.skipif(not direct_writes.DIRECT_FLAG, reason="no O_DIRECT on this platform")


def npy_bytes(array: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    np.save(buffer, array.astype(np.float32))
    return buffer.getvalue()


@pytest.mark.parametrize("shape", [(512, 512), (257, 333), (5, 7), (181, 181, 3), (1024, 1)])
def test_an_array_file_is_what_np_save_writes(tmp_path, shape):
    array = np.random.default_rng(1).normal(size=shape) * 1e3
    array.flat[::7] = np.inf  # the background's depth
    path = tmp_path / "a.npy"
    atomic_write(path, lambda file: direct_writes.write_npy(file, array, np.float32))
    assert path.read_bytes() == npy_bytes(array)
    np.testing.assert_array_equal(np.load(path), array.astype(np.float32))


@pytest.mark.parametrize("size", [1, direct_writes.SMALLEST_DIRECT_FILE - 1, direct_writes.SMALLEST_DIRECT_FILE, direct_writes.SMALLEST_DIRECT_FILE + 1,
                                  3 * direct_writes.ALIGNMENT * 100, 1_000_003])
def test_encoded_bytes_are_written_whole_at_every_length(tmp_path, size):
    data = np.random.default_rng(size).integers(0, 256, size, dtype=np.uint8).tobytes()
    path = tmp_path / "a.png"
    atomic_write(path, lambda file: direct_writes.write_bytes(file, data))
    assert path.read_bytes() == data


def test_an_in_memory_file_gets_the_same_bytes():
    array = np.random.default_rng(4).normal(size=(400, 400))
    buffer = io.BytesIO()
    direct_writes.write_npy(buffer, array, np.float32)
    assert buffer.getvalue() == npy_bytes(array)


def test_a_file_system_that_refuses_o_direct_gets_the_same_bytes(tmp_path, monkeypatch):
    """tmpfs refused O_DIRECT before Linux 6.6; here every fcntl that asks for it fails as it would."""
    real = direct_writes.fcntl.fcntl

    def refuse(descriptor, command, argument=0):
        if command == direct_writes.fcntl.F_SETFL and argument & direct_writes.DIRECT_FLAG:
            raise OSError(22, "Invalid argument")
        return real(descriptor, command, argument)

    monkeypatch.setattr(direct_writes.fcntl, "fcntl", refuse)
    array = np.random.default_rng(2).normal(size=(600, 601))
    for name in ("a.npy", "b.npy"):
        atomic_write(tmp_path / name, lambda file: direct_writes.write_npy(file, array, np.float32))
        assert (tmp_path / name).read_bytes() == npy_bytes(array)


def test_a_refused_first_write_falls_back(tmp_path, monkeypatch):
    """A file system that takes the flag but refuses the aligned write (EINVAL) still gets the file."""
    real_write = os.write
    calls = []

    def write(descriptor, data):
        flags = direct_writes.fcntl.fcntl(descriptor, direct_writes.fcntl.F_GETFL)
        calls.append(bool(flags & direct_writes.DIRECT_FLAG))
        if flags & direct_writes.DIRECT_FLAG:
            raise OSError(22, "Invalid argument")
        return real_write(descriptor, data)

    monkeypatch.setattr(direct_writes.os, "write", write)
    data = bytes(range(256)) * 4001
    if not direct_writes.DIRECT_FLAG:
        pytest.skip("no O_DIRECT on this platform")
    atomic_write(tmp_path / "a.bin", lambda file: direct_writes.write_bytes(file, data))
    assert (tmp_path / "a.bin").read_bytes() == data
    assert calls[0] is True and not any(calls[1:])  # refused once, then the usual way


def test_a_full_disk_is_an_error_naming_the_file(tmp_path):
    folder = Path(f"/tmp/wgpu-shading-direct-full-{uuid.uuid4().hex[:8]}")
    folder.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(folder)], capture_output=True, text=True)
    if mounted.returncode != 0:
        folder.rmdir()
        pytest.skip(f"cannot mount a small tmpfs to fill ({mounted.stderr.strip() or 'mount failed'}; needs root)")
    try:
        array = np.zeros((512, 512))
        with pytest.raises(Exception, match="a.npy"):
            atomic_write(folder / "a.npy", lambda file: direct_writes.write_npy(file, array, np.float32))
        assert os.listdir(folder) == []  # complete or absent
    finally:
        subprocess.run(["umount", str(folder)], capture_output=True)
        folder.rmdir()


def resident_pages(path: Path) -> int:
    """Pages of the file in the page cache: mincore(2) on a read-only mapping of it (mapping
    reads nothing in)."""
    libc = ctypes.CDLL(None, use_errno=True)
    libc.mmap.restype = ctypes.c_void_p
    libc.mmap.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_long]
    libc.munmap.argtypes = [ctypes.c_void_p, ctypes.c_size_t]
    libc.mincore.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_void_p]
    size = path.stat().st_size
    with open(path, "rb") as file:
        address = libc.mmap(None, size, mmap.PROT_READ, mmap.MAP_SHARED, file.fileno(), 0)
    assert address not in (None, ctypes.c_void_p(-1).value)
    try:
        vector = (ctypes.c_ubyte * -(-size // mmap.PAGESIZE))()
        assert libc.mincore(address, size, vector) == 0
        return sum(v & 1 for v in vector)
    finally:
        libc.munmap(address, size)


@needs_direct
def test_a_big_file_leaves_no_pages_in_the_page_cache(tmp_path):
    try:
        os.close(os.open(tmp_path / "probe", os.O_WRONLY | os.O_CREAT | direct_writes.DIRECT_FLAG, 0o600))
    except OSError:
        pytest.skip("this file system refuses O_DIRECT")
    array = np.random.default_rng(3).normal(size=(512, 512))
    direct, cached = tmp_path / "direct.npy", tmp_path / "cached.npy"
    atomic_write(direct, lambda file: direct_writes.write_npy(file, array, np.float32))
    atomic_write(cached, lambda file: np.save(file, array.astype(np.float32)))
    with open(cached, "rb") as file:
        os.fsync(file.fileno())  # dirty pages stay until written back
        os.posix_fadvise(file.fileno(), 0, 0, os.POSIX_FADV_DONTNEED)
    if resident_pages(cached):
        pytest.skip("this file system keeps files in memory (tmpfs): nothing to compare")
    atomic_write(cached, lambda file: np.save(file, array.astype(np.float32)))
    assert resident_pages(cached) > 200  # the usual way: the whole megabyte is cached
    assert resident_pages(direct) <= 1  # the last part block only
