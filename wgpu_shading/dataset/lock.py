"""One output folder, one run: `batch` holds an exclusive lock on OUTPUT/.wgpu-shading.lock
while it writes there.

Without it two runs into one folder broke each other: the second run's clean-up deleted the
first run's in-flight temporary files, whose jobs then failed, and both wrote the same
views. The lock is `fcntl.flock` on an open file: the kernel releases it when the process
ends however it ends (SIGKILL included), so a crashed run never leaves the folder locked.
The file itself stays (removing a lock file while another process opens it is a race); it
holds the pid of the run that last took it, for the message.

flock works between processes of one machine and on most network file systems that
emulate it (NFSv4, CIFS); a folder shared between machines without that should be given
one run at a time by hand. Dask workers write into the folder under the run's lock: they
are the run's own processes.
"""

from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from ..errors import UsageError
from .names import LOCK_FILE


@contextmanager
def folder_lock(out_dir: Path) -> Iterator[None]:
    """Hold OUTPUT's lock for the block, or raise a one-line UsageError when another run has it."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows: no flock; one run at a time is up to the user
        yield
        return
    path = out_dir / LOCK_FILE
    try:
        descriptor = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as error:
        raise UsageError(f"output folder {str(out_dir)!r}: its lock file cannot be made: {error.strerror or error}") from None
    try:
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(descriptor, 32, 0).decode("ascii", "replace").strip()
            raise UsageError(
                f"output folder {str(out_dir)!r} is being written by another batch run"
                + (f" (pid {holder})" if holder.isdigit() else "")
                + "; wait for it to finish or choose another folder"
            ) from None
        except OSError as error:
            raise UsageError(f"output folder {str(out_dir)!r}: cannot be locked: {error.strerror or error}") from None
        os.ftruncate(descriptor, 0)
        os.pwrite(descriptor, f"{os.getpid()}\n".encode(), 0)
        yield
    finally:
        os.close(descriptor)  # releases the lock
