"""Files written completely or not at all.

Every file the package writes (images, depth, float arrays, animations, golden references
and diff images, dataset files, reports) goes through `atomic_path`/`atomic_write`: the
bytes go to a temporary file beside the target, named

    .NAME.wgpu-shading-tmp-TOKEN.SUFFIX      (TOKEN: this process's id and a random word)

and only a complete file is renamed over the target (`os.replace`, atomic on POSIX within
one file system). A reader therefore sees the old file or the new one, never half of one;
a failure (full disk, an encoder error) or an interrupt (Ctrl-C; SIGTERM, which the CLI
turns into an exception) removes the temporary and leaves the previous file as it was.
A process killed outright (SIGKILL, power loss) can leave a temporary behind: its name
says what it is, and `batch` removes its own kind under its folder lock.

Symbolic links are written through: `out.png -> elsewhere/target.png` replaces
`elsewhere/target.png` (atomically, beside it) and the link stays a link, dangling or not.
An existing target that is not a regular file (a FIFO, a device such as /dev/null, a
folder) is refused: renaming over it would replace the device node itself.

The suffix is kept last so encoders that choose the format by name (Pillow, ffmpeg) see it.
Not done: `fsync`. The guarantee is against failures and signals of this process, not a
power cut (ext4 and xfs flush a file renamed over another before the rename, in practice).
"""

from __future__ import annotations

import errno
import itertools
import os
import stat
from contextlib import contextmanager
from pathlib import Path
from typing import BinaryIO, Callable, Iterator

from ..errors import UsageError, WgpuShadingError

TEMPORARY_MARK = ".wgpu-shading-tmp-"
_counter = itertools.count()
_token: tuple[int, str] | None = None
_UMASK = os.umask(0o022)  # read once (setting it is the only way to read it), then restored
os.umask(_UMASK)


def process_token() -> str:
    """This process's id and a random word (regenerated after a fork): two processes, or two
    runs that reuse a pid, never pick the same temporary name."""
    global _token
    if _token is None or _token[0] != os.getpid():
        # os.urandom is what secrets.token_hex uses; importing secrets (hmac, OpenSSL) costs
        # every cold start ~5 ms (docs/performance.md, cold start).
        _token = (os.getpid(), os.urandom(4).hex())
    return f"{_token[0]}-{_token[1]}"


def write_target(path: str | os.PathLike[str]) -> Path:
    """The file that writing `path` replaces: `path` itself, or where its symbolic link(s)
    lead (the link is kept)."""
    return Path(_target_text(path))


def temporary_path(target: Path, tag: str = "") -> Path:
    """A fresh temporary name beside `target` (its suffix kept last)."""
    return Path(_temporary_text(os.fspath(target), tag))


# The two above on plain strings: a dataset writes several files a frame, and pathlib's
# parsing was a third of the Python time of each write (~20 of 77 µs).
def _target_text(path: str | os.PathLike[str]) -> str:
    path = os.fspath(path)
    return os.path.realpath(path) if os.path.islink(path) else path


def _temporary_text(target: str, tag: str) -> str:
    folder, name = os.path.split(target)
    dot = name.rfind(".")
    suffix = name[dot:] if 0 < dot < len(name) - 1 and len(name) - dot <= 16 else ""  # pathlib's suffix, when short
    return os.path.join(folder, f".{name[: 120]}{TEMPORARY_MARK}{tag}{process_token()}-{next(_counter)}{suffix}")


def is_temporary(name: str, tag: str = "") -> bool:
    return name.startswith(".") and f"{TEMPORARY_MARK}{tag}" in name


def check_target(path: str | os.PathLike[str], what: str = "output", error: type[WgpuShadingError] = UsageError) -> Path:
    """Raise a one-line error unless `path` can be written the way `atomic_path` writes it
    (tried, not guessed: permissions, read-only mounts, /proc, ...). Nothing is created at
    the target and nothing is changed: a temporary is made beside it and removed again, an
    existing file is opened for appending and closed. Returns the target (links followed)."""
    path = Path(path)
    target = write_target(path)
    shown = str(path) if target == path else f"{str(path)} (a link to {str(target)})"
    if os.path.lexists(target):
        try:
            mode = os.stat(target).st_mode
        except OSError as exc:
            raise error(f"{what} {shown!r} cannot be written: {exc.strerror or exc}") from None
        if stat.S_ISDIR(mode):
            raise error(f"{what} {shown!r} is a folder, not a file")
        if not stat.S_ISREG(mode):
            raise error(f"{what} {shown!r} exists and is not a regular file (a device or FIFO); it is not replaced")
        try:
            with open(target, "ab"):
                pass
        except OSError as exc:
            raise error(f"{what} {shown!r} cannot be written: {exc.strerror or exc}") from None
    if not target.parent.is_dir():
        raise error(f"{what} {shown!r}: folder {str(target.parent)!r} does not exist")
    probe = temporary_path(target)
    try:
        descriptor = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except OSError as exc:
        raise error(f"{what} {shown!r} cannot be written: {exc.strerror or exc}") from None
    os.close(descriptor)
    _remove(probe)
    return target


@contextmanager
def atomic_path(
    path: str | os.PathLike[str], what: str = "output", error: type[WgpuShadingError] = UsageError, tag: str = ""
) -> Iterator[Path]:
    """Yield a temporary path beside `path` for the caller to write the whole file to; when
    the block ends normally it replaces `path`. On any exception (OSError becomes `error`
    naming the file; others, KeyboardInterrupt included, pass through) the temporary is
    removed and `path` is as it was."""
    target = _target_text(path)
    temporary = _temporary_text(target, tag)
    try:
        yield Path(temporary)
        _match_mode(temporary, target)
        os.replace(temporary, target)
    except OSError as exc:
        _remove(temporary)
        raise error(_failure(path, what, exc)) from None
    except BaseException:
        _remove(temporary)
        raise


@contextmanager
def atomic_open(
    path: str | os.PathLike[str], what: str = "output", error: type[WgpuShadingError] = UsageError, tag: str = ""
) -> Iterator[BinaryIO]:
    """`atomic_path`, opened for binary writing (closed before the rename)."""
    target = _target_text(path)
    temporary = _temporary_text(target, tag)
    try:
        with open(temporary, "xb") as file:  # created with the umask's mode, as `open` gives a new file
            yield file
        _match_mode(temporary, target, created_by_open=True)
        os.replace(temporary, target)
    except OSError as exc:
        _remove(temporary)
        raise error(_failure(path, what, exc)) from None
    except BaseException:
        _remove(temporary)
        raise


def atomic_write(
    path: str | os.PathLike[str],
    write: Callable[[BinaryIO], object] | bytes,
    what: str = "output",
    error: type[WgpuShadingError] = UsageError,
    tag: str = "",
) -> Path:
    """Write `path` from bytes, or through `write(file)`, atomically. Returns `path`."""
    with atomic_open(path, what, error, tag) as file:
        if isinstance(write, (bytes, bytearray, memoryview)):
            file.write(write)
        else:
            write(file)
    return Path(path)


def remove_temporaries(folder: Path, tag: str) -> int:
    """Delete the temporaries marked `tag` in `folder` and its subfolders (only safe while
    nothing else writes files of that tag there: `batch` holds its folder lock)."""
    removed = 0
    name = f".*{TEMPORARY_MARK}{tag}*"
    for path in [*folder.glob(name), *folder.glob(f"*/{name}")]:
        if _remove(path):
            removed += 1
    return removed


def _failure(path: str | os.PathLike[str], what: str, exc: OSError) -> str:
    reason = exc.strerror or str(exc)
    if isinstance(exc, FileNotFoundError) and not Path(path).parent.is_dir():
        reason = "its folder no longer exists"
    elif exc.errno is None and _no_space_left(write_target(path).parent):
        reason = os.strerror(errno.ENOSPC)  # numpy's short write says only "N requested and M written"
    kept = "the file that was there is unchanged" if os.path.lexists(write_target(path)) else "nothing was written"
    return f"{what} {str(path)!r} could not be written: {reason} ({kept})"


def _no_space_left(folder: Path) -> bool:
    try:
        status = os.statvfs(folder)
    except OSError:
        return False
    return status.f_bavail * status.f_frsize < (1 << 20)


def _match_mode(temporary: str, target: str, created_by_open: bool = False) -> None:
    """The new file keeps the permissions of the one it replaces (a temporary is created 0600
    by some encoders; a new file gets the umask's mode, as `open` would give it, and one
    that `open` created has it already)."""
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode)
    except OSError:
        if created_by_open:
            return
        mode = 0o666 & ~_UMASK
    try:
        os.chmod(temporary, mode)
    except OSError:  # pragma: no cover - a file system without permissions
        pass


def _remove(path: Path) -> bool:
    try:
        os.unlink(path)
        return True
    except OSError:
        return False
