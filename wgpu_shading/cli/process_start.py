"""The start of a `wgpu-shading` process: what the installed program sets for itself.

The program runs one command and ends (process_end.py), so it may set what a library must
leave to its caller. Each is measured in docs/performance.md, "Cold start" (the shares
below: callgrind's instructions of `render builtin:torus`, the whole process):

- numpy gets one OpenBLAS thread, unless the user set `OPENBLAS_NUM_THREADS`: our matrix
  products are skinny (N×3 by 3×3 or 4×4, up to 10M rows), where one thread was as fast
  as two on a 2-core machine at half the CPU, and 4–9× faster when the other core was
  busy; the second thread's start-up spin also cost every command ~0.1 s of CPU. Dask
  sets the same for its workers (distributed's nanny pre-spawn-environ).
- Python's cyclic garbage collector is off while the program imports its modules, and on,
  with the start-up objects frozen, from the moment the command runs. The imports leave
  ~43,000 objects the collector tracks (modules, classes, functions, their dicts) that
  live as long as the process and hold no garbage; it scanned them over and over (~80
  collections), 1.3 % of a render's instructions. Frozen, they are left out of every
  later collection, so a long command (a turntable, a batch, the live view) also scans
  less (https://docs.python.org/3/library/gc.html#gc.freeze).
- pyglm's typing aliases (`pyglm.glm_typing`, ~1,900 `typing` constructions, 6.6 %) are
  loaded when something first reads one, not when pyglm's package imports them: nothing
  in a command does (they exist for type checkers). pyglm has no switch for it
  (https://github.com/Zuzu-Typ/PyGLM/blob/master/pyglm/__init__.py).
- A command that renders on lavapipe only lets the Vulkan loader load lavapipe's driver:
  the loader otherwise loads every installed driver (Intel's, AMD's, ...) to enumerate
  adapters, 3.0 %. Only where the whole process uses one selector: a
  library process may ask for another adapter later (render/device.py).
"""

from __future__ import annotations

import gc
import os
import sys
import types

DEFERRED_MODULES = {"pyglm.glm_typing": ("pyglm", "glm_typing.py")}  # module -> (its package, file)


def start_process() -> None:
    """First thing in the installed program, before numpy or any of our modules load."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    gc.disable()
    for name, (package, file) in DEFERRED_MODULES.items():
        defer_module(name, package, file)


class _Deferred(types.ModuleType):
    """Stands in sys.modules for a module that is executed on the first read of a name it
    does not have yet. (importlib.util.LazyLoader cannot serve here: the import system
    reads `__spec__` of a module already in sys.modules, which would load it at once.)"""

    def __getattr__(self, name: str):
        if name == "__path__":  # the import system asking whether it is a package: it is not
            raise AttributeError(name)
        import importlib.util

        real = importlib.util.module_from_spec(self.__spec__)
        self.__spec__.loader.exec_module(real)  # (its bytecode cache, as an import would)
        for key, value in real.__dict__.items():
            if key not in ("__spec__", "__loader__"):
                setattr(self, key, value)
        self.__class__ = types.ModuleType  # loaded: an ordinary module from now on
        return getattr(self, name)


def defer_module(name: str, package: str, file: str) -> bool:
    """Put a deferred stand-in for `name` (file `file` of top-level package `package`) in
    sys.modules, unless the package is imported already or the file is not there. True
    when it did."""
    import importlib.util

    if package in sys.modules or name in sys.modules:
        return False
    try:
        spec = importlib.util.find_spec(package)  # a top-level name: found, not imported
    except (ImportError, ValueError):
        return False
    folders = list(spec.submodule_search_locations or []) if spec is not None else []
    origin = next((os.path.join(folder, file) for folder in folders if os.path.isfile(os.path.join(folder, file))), None)
    if origin is None:
        return False
    stand_in = _Deferred(name)
    stand_in.__spec__ = importlib.util.spec_from_file_location(name, origin)
    stand_in.__file__, stand_in.__loader__, stand_in.__package__ = origin, stand_in.__spec__.loader, package
    sys.modules[name] = stand_in
    return True


def command_starts(command: str, adapter: str | None) -> None:
    """When the parsed command is about to run: the imports so far are start-up objects.
    `adapter`: the --adapter given (None: the default, or the command takes no adapter)."""
    gc.freeze()
    gc.enable()
    if command != "info":  # `info` lists every adapter there is
        from ..render.device import load_only_lavapipe_driver

        load_only_lavapipe_driver(adapter)
