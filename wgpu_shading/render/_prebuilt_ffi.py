"""Load wgpu-py's native backend without re-parsing its C header in every process.

wgpu-py 0.32 uses cffi in "in-line ABI mode": importing the backend parses the 100 KB
WebGPU header with pycparser (about 0.4 s), and every *new* type string later handed to
`ffi.new()` is parsed again together with a preamble of all ~450 typedef names (15–30 ms
each, about 70 distinct types for one render). Profiling a cold `wgpu-shading render`
showed more than 90 % of the process's CPU time in that Python parser, not in lavapipe
(see docs/performance.md; upstream discussion: pygfx/wgpu-py#789).

cffi's own remedy is "out-of-line ABI mode": parse the header once, keep the compiled
type table, and build the FFI from that table (C-level type lookups, no pycparser). This
module does that for wgpu-py: the table is generated from wgpu's own header on first use,
cached under the user's cache folder (keyed by a hash of the header and the cffi
version), and handed to wgpu-py's `_ffi` module in place of its in-line FFI. wgpu-py only
calls public FFI methods (new, cast, callback, string, from_buffer, addressof, dlopen),
which the compiled FFI provides identically.

Anything unexpected (another wgpu-py layout, an unreadable cache, a build error) falls
back to wgpu-py's normal import, so this can only make start-up faster, never break it.
Set WGPU_SHADING_PREBUILT_FFI=0 to turn it off.
"""

from __future__ import annotations

import logging
import marshal
import os
import sys
import zlib
from pathlib import Path

SWITCH_ENVIRONMENT_VARIABLE = "WGPU_SHADING_PREBUILT_FFI"
_BACKEND_MODULE = "wgpu.backends.wgpu_native"
_FORMAT_VERSION = "1"  # bump when the cache file's layout changes

logger = logging.getLogger(__name__)
_ABANDONED_MODULES: list = []


def cache_folder() -> Path:
    """Where the type table is kept ($XDG_CACHE_HOME/wgpu-shading, else ~/.cache/wgpu-shading)."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "wgpu-shading"


def load_wgpu_native() -> bool:
    """Import wgpu's native backend with a prebuilt type table. True if the table was used;
    False if the backend was already imported, the switch is off, or anything failed (then
    the backend is, or will be, imported the normal way)."""
    if _BACKEND_MODULE in sys.modules or os.environ.get(SWITCH_ENVIRONMENT_VARIABLE, "1").strip() == "0":
        return False
    try:
        ffi = _prebuilt_ffi()
    except Exception as error:  # never let an optimization stop a render
        logger.debug("prebuilt FFI unavailable, using wgpu-py's own: %s", error)
        return False

    import importlib

    import cffi

    # wgpu-py's _ffi.py runs `ffi = FFI(); ffi.cdef(header); ffi.set_source(...); ffi.dlopen(path)`.
    # For the duration of that import, FFI() hands out the prebuilt FFI, whose cdef and
    # set_source do nothing (it already knows every type).
    original = cffi.FFI
    cffi.FFI = lambda: ffi  # type: ignore[assignment, misc]
    try:
        importlib.import_module(_BACKEND_MODULE)
        adopted = getattr(sys.modules.get(_BACKEND_MODULE + "._ffi"), "ffi", None) is ffi
    except Exception as error:
        logger.debug("wgpu-py did not accept the prebuilt FFI, importing it normally: %s", error)
        for name in [name for name in sys.modules if name == _BACKEND_MODULE or name.startswith(_BACKEND_MODULE + ".")]:
            # Kept alive: the native library may still hold the log callback they created.
            _ABANDONED_MODULES.append(sys.modules.pop(name))
        adopted = False
    finally:
        cffi.FFI = original
    return adopted


def _prebuilt_ffi():
    import _cffi_backend
    import cffi
    from wgpu._coreutils import get_header_filename

    class PrebuiltFFI(_cffi_backend.FFI):
        """A compiled FFI that accepts (and ignores) the in-line mode's set-up calls."""

        def cdef(self, csource, override=False, packed=False, pack=None) -> None:
            pass

        def set_source(self, module_name, source, source_extension=".c", **kwds) -> None:
            pass

    header = Path(get_header_filename("combined_header.h")).read_bytes()
    path = cache_folder() / f"wgpu-ffi-{_table_key(header, cffi.__version__)}.marshal"
    try:
        name, arguments = _read_table(path)
    except (OSError, ValueError, EOFError, TypeError):
        name, arguments = _build_table(header.decode())
        _store(path, marshal.dumps((name, arguments)))
    return PrebuiltFFI(name, **arguments)


def _table_key(header: bytes, cffi_version: str) -> str:
    """Names the table after everything it is derived from. Two zlib checksums and the
    length instead of a cryptographic hash: the key only tells versions of one header
    apart, and importing hashlib (OpenSSL) costs a cold start ~5 ms."""
    return f"{_FORMAT_VERSION}-{cffi_version}-{len(header)}-{zlib.crc32(header):08x}{zlib.adler32(header):08x}"


def _read_table(path: Path) -> tuple[str, dict]:
    """The cached (name, arguments) of the compiled FFI. marshal, like Python's own bytecode
    caches (the same trust: a file in the user's cache folder), and ~0.2 ms where parsing the
    130 KB as a Python literal took ~13 ms of every cold start. Only plain values are
    accepted: anything else is a damaged file (ValueError), rebuilt by the caller."""
    table = marshal.loads(path.read_bytes())
    if not (isinstance(table, tuple) and len(table) == 2 and isinstance(table[0], str) and isinstance(table[1], dict)):
        raise ValueError(f"{path} does not hold an FFI table")
    name, arguments = table
    if not all(isinstance(key, str) and isinstance(value, (bytes, str, tuple, int)) for key, value in arguments.items()):
        raise ValueError(f"{path} does not hold an FFI table")
    return name, arguments


def _build_table(header: str) -> tuple[str, dict]:
    """Parse the header once with cffi and return the arguments of the compiled FFI."""
    import ast  # here, not at the top: a cold start that finds its table needs none of these
    import contextlib
    import io
    import tempfile

    import cffi

    builder = cffi.FFI()
    builder.cdef(header)
    builder.set_source("_wgpu_shading_wgpu_ffi", None)
    with tempfile.TemporaryDirectory() as folder, contextlib.redirect_stdout(io.StringIO()):
        generated = Path(folder) / "ffi.py"
        builder.emit_python_code(str(generated))  # prints "generating ..." otherwise
        tree = ast.parse(generated.read_text())
    # The generated module is `import _cffi_backend` then `ffi = _cffi_backend.FFI(name, **table)`.
    call = next(node.value for node in tree.body if isinstance(node, ast.Assign))
    assert isinstance(call, ast.Call)
    name = ast.literal_eval(call.args[0])
    arguments = {keyword.arg: ast.literal_eval(keyword.value) for keyword in call.keywords}
    return name, arguments


def _store(path: Path, table: bytes) -> None:
    import tempfile

    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        # Write then rename, so a concurrent process never reads a half-written table.
        with tempfile.NamedTemporaryFile("wb", dir=path.parent, delete=False, suffix=".tmp") as file:
            file.write(table)
        os.replace(file.name, path)
    except OSError as error:  # read-only home: the table is rebuilt next time
        logger.debug("could not cache the FFI table in %s: %s", path.parent, error)
