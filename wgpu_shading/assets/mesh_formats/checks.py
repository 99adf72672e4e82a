"""Checks on mesh files before trimesh reads them: sizes, declared counts, text encoding.

trimesh allocates what a file's header declares and reads text formats through an
optional charset detector, so a hostile or damaged file could exhaust memory (a 2 GB PLY
declaring billions of faces), render a truncated mesh as if it were whole, or fail with
"No module named 'charset_normalizer'". Everything here reads at most the header.
"""

from __future__ import annotations

import io
import re
from pathlib import Path

from ...errors import MeshError
from ...scene.geometry.mesh import MAX_TRIANGLES, MAX_VERTICES
from ..files import read_text_bytes

MAX_MESH_FILE_BYTES = 2 << 30  # 2 GiB: beyond MAX_TRIANGLES of every format but ASCII STL
# ASCII STL spends ~270 bytes a triangle (seven lines of %e numbers, as SolidWorks writes
# them): a 10M-triangle file is ~2.6 GB. The plain layout is read a block of lines at a time
# (stl_ascii.py: memory bound by the triangles read, refused past MAX_TRIANGLES), any other
# layout only up to stl.MAX_ASCII_BYTES: so an STL's limit is MAX_TRIANGLES facets of 288 bytes.
MAX_STL_FILE_BYTES = MAX_TRIANGLES * 288  # 9 GiB
_FILE_LIMITS = {".stl": MAX_STL_FILE_BYTES}  # suffix → its limit, where not MAX_MESH_FILE_BYTES
# The corners of one polygon (an OBJ `f` line, a PLY face): a 48 MB OBJ line of 24M corners
# took 5.2 GB and 17 s to become triangles before its mesh was refused; Blender's n-gons
# and CAD outlines have far fewer (docs/valid-ranges.md).
MAX_FACE_CORNERS = 1 << 20
_TEXT_FORMATS = (".obj",)  # always text: decoded here, handed to trimesh as UTF-8


def check_file_size(path: Path, where: str) -> int:
    size = path.stat().st_size
    limit = _FILE_LIMITS.get(path.suffix.lower(), MAX_MESH_FILE_BYTES)
    if size > limit:
        files = f"{path.suffix.lstrip('.').upper()} files" if limit != MAX_MESH_FILE_BYTES else "mesh files"
        raise MeshError(f"{where}: {size / 2**30:.1f} GiB; {files} up to {limit >> 30} GiB are supported")
    if size == 0:
        raise MeshError(f"{where}: the file is empty")
    return size


def check_declared_counts(where: str, vertices: int, faces: int, needed_bytes: int, available: int) -> None:
    if vertices > MAX_VERTICES or faces > MAX_TRIANGLES:
        raise MeshError(
            f"{where}: declares {vertices} vertices and {faces} faces; at most {MAX_VERTICES} of each are supported"
        )
    if needed_bytes > available:
        raise MeshError(
            f"{where}: declares {vertices} vertices and {faces} faces, which need at least {needed_bytes} bytes, "
            f"but the file has only {available} after its header (truncated or damaged)"
        )


def text_source(path: Path, where: str, file_size: int) -> io.BytesIO | None:
    """For text formats: the file as UTF-8 bytes, decoded here (UTF-8, else Latin-1, which
    decodes any byte) so trimesh never needs its optional charset detector. None for
    binary-capable formats, which trimesh reads from the path."""
    if path.suffix.lower() not in _TEXT_FORMATS:
        return None
    data = read_text_bytes(path, where, MeshError)  # a NUL byte: refused at once, not after reading 2 GB
    try:
        text = data.decode("utf-8")
        utf8 = True
    except UnicodeDecodeError:
        text = data.decode("latin-1")
        utf8 = False
    return io.BytesIO(data if utf8 else text.encode("utf-8"))


def describe_load_error(error: BaseException, path: Path) -> str:
    """trimesh's failure as one line a user can act on."""
    if isinstance(error, ImportError):
        # trimesh re-raises it from its own record, without the `name` attribute: from the text
        named = re.search(r"No module named '([^']+)'", str(error))
        missing = getattr(error, "name", None) or (named.group(1) if named else "")
        if missing and missing.split(".")[0] not in ("charset_normalizer", "chardet"):
            # trimesh reaches for another optional module for what the file holds (scipy for
            # a PLY's edges, which ply_edges.py now reads): not a damaged file, a part we do not read.
            return f"holds something its reader (trimesh) reads only with the optional module {missing!r}, not installed; not drawn"
        # trimesh asks an optional charset detector when a file is neither valid binary
        # nor UTF-8 text: for us that means the file is not what its suffix says.
        return f"not a valid {path.suffix.lstrip('.').upper()} file (neither its binary form nor UTF-8 text)"
    if isinstance(error, MemoryError):
        return "not enough memory to read it"
    text = str(error).strip()
    escape = re.match(r"'(.*)' escapes resolver root '(.*)'", text)
    if escape:  # trimesh's advice names its own API (FilePathResolver(path, allow_anywhere=True))
        return f"it refers to {escape.group(1)!r}, outside its folder {escape.group(2)!r}; only files beside it or below are read"
    if isinstance(error, AssertionError) or not text:  # a parser's internal check: "AssertionError: " says nothing
        return f"not a valid {path.suffix.lstrip('.').upper()} file (its reader found an inconsistency it could not describe)"
    return f"cannot be read ({type(error).__name__}: {error})"


def file_size_or_error(path: Path, where: str) -> int:
    try:
        return check_file_size(path, where)
    except OSError as error:
        raise MeshError(f"{where}: cannot be read ({error.strerror or error})") from None

