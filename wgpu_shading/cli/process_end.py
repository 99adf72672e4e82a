"""The end of a `wgpu-shading` process, once its command has returned.

Python's own exit tears the interpreter down: every module, the wgpu device and lavapipe's
threads and JIT-compiled shaders, OpenBLAS's threads. That takes 30–50 ms, as long as a
whole small render (docs/performance.md, "Cold start"), and nothing of it reaches a user:
every file the command wrote is complete and closed (assets/atomic.py), and the operating
system frees the rest. So the process ends at once, after flushing what Python would have
flushed (standard streams, logging handlers), unless something may still need an orderly
exit: a thread that is not a daemon, or child processes and their clean-ups (Dask
workers, multiprocessing); then it exits the usual way.
"""

from __future__ import annotations

import logging
import os
import sys
import threading
from typing import NoReturn

EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE, what a shell reports for a text tool whose reader went away


def end_process(code: int) -> NoReturn:
    code = _flushed(code)
    logging.shutdown()
    if _needs_orderly_exit():
        sys.exit(code)
    os._exit(code)


def _flushed(code: int) -> int:
    for stream in (sys.stdout, sys.stderr):
        try:
            if stream is not None and not stream.closed:
                stream.flush()
        except BrokenPipeError:
            # The reader went away after the command's last write (`... | head`): quiet, as
            # main.py is during the command.
            code = code or EXIT_BROKEN_PIPE
        except (OSError, ValueError):
            code = code or 1
    return code


def _needs_orderly_exit() -> bool:
    others = [thread for thread in threading.enumerate() if thread is not threading.main_thread()]
    if any(not thread.daemon for thread in others):
        return True  # Python would wait for it
    # Child processes and their atexit clean-ups (a Dask cluster, a process pool).
    return any(name in sys.modules for name in ("multiprocessing", "distributed", "concurrent.futures.process"))
