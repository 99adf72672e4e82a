"""The start of a `wgpu-shading` process: what the installed program sets for itself.

The program runs one command and ends (process_end.py), so it may set what a library must
leave to its caller. Each is measured in docs/performance.md, "Cold start":

- numpy gets one OpenBLAS thread, unless the user set `OPENBLAS_NUM_THREADS`: our matrix
  products are skinny (N×3 by 3×3 or 4×4, up to 10M rows), where one thread was as fast
  as two on a 2-core machine at half the CPU, and 4–9× faster when the other core was
  busy; the second thread's start-up spin also cost every command ~0.1 s of CPU. Dask
  sets the same for its workers (distributed's nanny pre-spawn-environ).
- Python's cyclic garbage collector is off while the program imports its modules, and on,
  with the start-up objects frozen, from the moment the command runs. Importing creates
  some 200,000 objects (modules, classes, functions) that live as long as the process and
  hold no garbage; the collector scanned them over and over (~80 collections, one of them
  full) for ~10 ms of a 0.28 s render. Frozen, they are left out of every later
  collection, so a long command (a turntable, a batch, the live view) also scans less
  (https://docs.python.org/3/library/gc.html#gc.freeze).
- A command that renders on lavapipe only lets the Vulkan loader load lavapipe's driver:
  the loader otherwise loads every installed driver (Intel's, AMD's, ...) to enumerate
  adapters, ~5 ms of every start. Only where the whole process uses one selector: a
  library process may ask for another adapter later (render/device.py).
"""

from __future__ import annotations

import gc
import os


def start_process() -> None:
    """First thing in the installed program, before numpy or any of our modules load."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    gc.disable()


def command_starts(command: str, adapter: str | None) -> None:
    """When the parsed command is about to run: the imports so far are start-up objects.
    `adapter`: the --adapter given (None: the default, or the command takes no adapter)."""
    gc.freeze()
    gc.enable()
    if command != "info":  # `info` lists every adapter there is
        from ..render.device import load_only_lavapipe_driver

        load_only_lavapipe_driver(adapter)
