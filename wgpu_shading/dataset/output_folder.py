"""A dataset's output folder, made so that its mesh folders start in fresh parts of the disk.

Why: on ext4 a new file takes an inode in its folder's block group (fs/ext4/ialloc.c,
find_group_other), and a folder takes one in its parent's group (find_group_orlov for a
folder below the top). On a file system without a journal the kernel avoids an inode freed
in the last minute or so, checking each free inode it passes one by one
(ialloc.c: recently_deleted). So right after many files were removed nearby — the previous
run's output (`rm -r out` before rendering it again), a test suite's temporary files — each
new file of the run costs 0.1–0.8 ms of kernel time instead of ~15 µs, three times a view
(docs/performance.md, "Where a dataset frame goes", the thirteenth pass).

What is done: the output folder, when this run makes it or finds it empty, gets ext4's
"top of directory hierarchy" attribute (`chattr +T`, FS_TOPDIR_FL: ext4's Orlov allocator
then spreads its subfolders over block groups with room and few folders, as it does for the
folders at the root of the disk: Documentation/filesystems/ext4 and chattr(1)). Each mesh
folder starts in such a group, away from the removed files. The attribute is a placement
hint only: it is not inherited, changes nothing else about the folder, and `chattr -T`
removes it. A folder with something in it already is the user's: left as it is.

Best effort: file systems without the attribute (xfs, btrfs, tmpfs, NFS) refuse the ioctl and
the folder is made as usual; elsewhere than Linux nothing is tried.
"""

from __future__ import annotations

import array
import os
import platform
import struct
import sys
from pathlib import Path

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None

TOPDIR_FLAG = 0x00020000  # FS_TOPDIR_FL, include/uapi/linux/fs.h

# FS_IOC_GETFLAGS / FS_IOC_SETFLAGS are _IOR('f', 1, long) / _IOW('f', 2, long). Their numbers
# follow include/uapi/asm-generic/ioctl.h on these machines only; powerpc, mips, sparc and
# alpha encode the direction otherwise (there the first number would mean "set"), so nothing is
# tried there.
_GENERIC_IOCTL_MACHINES = ("x86_64", "amd64", "i386", "i686", "aarch64", "arm64", "armv7l", "armv6l",
                           "riscv64", "s390x", "loongarch64")


def _ioctl_number(direction: int, number: int) -> int:
    size = struct.calcsize("l")  # the `long` of the macros' type argument
    return (direction << 30) | (size << 16) | (ord("f") << 8) | number


GET_FLAGS = _ioctl_number(2, 1)  # _IOC_READ
SET_FLAGS = _ioctl_number(1, 2)  # _IOC_WRITE


def can_spread() -> bool:
    """Whether spread_subfolders() may try at all on this system."""
    return fcntl is not None and sys.platform.startswith("linux") and platform.machine().lower() in _GENERIC_IOCTL_MACHINES


def spread_subfolders(folder: str | os.PathLike[str]) -> bool:
    """Mark `folder` as the top of a directory hierarchy (module docstring). True when it
    carries the mark now, False where the system or its file system has none."""
    return _folder_flags(folder, add=TOPDIR_FLAG) is not None


def has_spread_mark(folder: str | os.PathLike[str]) -> bool | None:
    """Whether `folder` carries the mark; None where its attributes cannot be read."""
    flags = _folder_flags(folder)
    return None if flags is None else bool(flags & TOPDIR_FLAG)


def _folder_flags(folder: str | os.PathLike[str], add: int = 0) -> int | None:
    """The folder's attribute flags, with `add` set first where missing; None where they
    cannot be read or set (ENOTTY, EOPNOTSUPP, EINVAL, EPERM: no such attributes here)."""
    if not can_spread():
        return None
    try:
        descriptor = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return None
    try:
        flags = array.array("i", [0])  # the kernel reads and writes an int, whatever the macros say
        fcntl.ioctl(descriptor, GET_FLAGS, flags, True)
        if flags[0] & add != add:
            flags[0] |= add
            fcntl.ioctl(descriptor, SET_FLAGS, flags, True)
        return flags[0]
    except OSError:
        return None
    finally:
        os.close(descriptor)


def make_output_folder(folder: Path) -> None:
    """Make `folder` and its parents where missing; a folder made now or found empty gets
    spread_subfolders(). OSError as mkdir raises it (a file in the way, no permission)."""
    fresh = not folder.is_dir()
    if not fresh:
        with os.scandir(folder) as entries:
            fresh = next(entries, None) is None
    folder.mkdir(parents=True, exist_ok=True)
    if fresh:
        spread_subfolders(folder)
