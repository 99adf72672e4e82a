"""Input files: what may be opened for reading at all.

A FIFO (named pipe) blocks `open()` until some other process writes to it, a character
device such as /dev/zero or /dev/urandom never ends, and a folder raises an OSError whose
message does not say which input it was. Every file input (meshes, textures, scene files,
manifests, glTF buffers and images) is checked here first, with `os.stat` only: nothing is
opened, so a FIFO cannot block the check itself.
"""

from __future__ import annotations

import importlib.util
import os
import stat
from functools import lru_cache
from pathlib import Path
from typing import Iterator

from ..errors import WgpuShadingError

_KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def special_kind(path: str | os.PathLike[str]) -> str | None:
    """What `path` is when it is not a regular file ("a FIFO (named pipe)", ...); None for a
    regular file (links followed) and for a path that does not exist (the caller says
    "not found" in its own words)."""
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return None
    if stat.S_ISREG(mode):
        return None
    for test, kind in _KINDS:
        if test(mode):
            return kind
    return "not a regular file"


def check_regular_file(path: str | os.PathLike[str], where: str, error: type[WgpuShadingError]) -> Path:
    """Raise `error("<where> is a FIFO (named pipe), not a regular file")` unless `path` is a
    regular file or missing; `where` names the input (e.g. "texture 'a.png' (map_Kd of x.mtl)")."""
    kind = special_kind(path)
    if kind is not None:
        raise error(f"{where} is {kind}, not a regular file; only regular files are read")
    return Path(path)


def is_readable_regular_file(path: str | os.PathLike[str]) -> bool:
    """True for an existing regular file (links followed): for inputs that are skipped with
    a warning rather than refused."""
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except (OSError, ValueError):
        return False


TEXT_CHUNK = 16 << 20


# The blocks of lines the OBJ, plain OFF and ASCII PLY readers take at a time: their lines
# are Python strings (~60 bytes a line) a block at a time, never the whole file's.
TEXT_BLOCK_BYTES = 4 << 20


class LongLine(Exception):
    """A line longer than text_line_blocks was told to expect (longest_line): raised before
    the rest of it is read, for a reader whose format has only short lines to give up."""


def text_line_blocks(path: str | os.PathLike[str], where: str, error: type[WgpuShadingError],
                     block_bytes: int | None = None, longest_line: int | None = None) -> Iterator[bytes]:
    """A text file's bytes in blocks of whole lines, about `block_bytes` each (None:
    TEXT_BLOCK_BYTES; a line longer than that is one block), refused at the first NUL byte
    as read_text_bytes refuses it: a reader that takes a block at a time never holds the
    whole text (a 2M-triangle OBJ is 75 MB). Every block but the last ends with a newline.
    UTF-16 text (a byte-order mark) is read whole, as read_text_bytes reads it, and given as
    one block.

    The file is read TEXT_CHUNK bytes at a time whatever the block size, one read ahead of
    the blocks given, so that a file of one chunk is read to its end (the last, empty read
    takes and frees a TEXT_CHUNK buffer) before its block is parsed, as with read_text_bytes.
    Reading the end only after the parsing, glibc's heap grew and shrank around the parser's
    temporaries at every file: 6,200 instead of 1,400 page faults and 42 instead of 32 ms
    to read the bunny's OBJ, in a new process (docs/performance.md, "Loading a large mesh").
    `longest_line`: LongLine is raised once a line goes on past that many bytes, instead of
    reading the whole line (a file of one line is one block otherwise)."""
    block_bytes = TEXT_BLOCK_BYTES if block_bytes is None else block_bytes
    offset = 0  # bytes of the file read so far
    carry: list[bytes] = []  # the unfinished last line of what was read (joined once it ends)
    with open(path, "rb") as file:
        following = file.read(TEXT_CHUNK)
        while chunk := following:
            if offset == 0 and chunk[:2] in (b"\xff\xfe", b"\xfe\xff"):
                yield chunk + file.read()
                return
            following = file.read(TEXT_CHUNK)
            nul = chunk.find(b"\x00")
            if nul >= 0:
                raise error(f"{where}: not a text file (a NUL byte at offset {offset + nul}); is it binary or damaged?")
            offset += len(chunk)
            if b"\n" not in chunk:  # the line goes on (a file without newlines is one block, read once)
                carry.append(chunk)
                if longest_line is not None and sum(map(len, carry)) > longest_line:
                    raise LongLine(where)
                continue
            text = b"".join(carry + [chunk]) if carry else chunk
            start = 0
            while True:
                end = text.rfind(b"\n", start, start + block_bytes) + 1  # the last line end within a block
                if end <= start:  # none: the next line is longer than a block
                    end = text.find(b"\n", start) + 1
                if end <= start:  # no line ends here: the line goes on in the next chunk
                    break
                yield text[start:end]
                start = end
            carry = [text[start:]] if start < len(text) else []
    if carry:
        yield b"".join(carry)


def read_text_bytes(path: str | os.PathLike[str], where: str, error: type[WgpuShadingError]) -> bytes:
    """A text file's bytes, read in 16 MiB chunks and refused at the first NUL byte: text
    formats (OBJ, OFF, MTL) never hold one, and a file of zeros (a damaged copy, a disk
    image) was read whole and then exhausted memory while being split into lines. UTF-16
    text (it starts with a byte-order mark) is half NULs and is read whole, as before."""
    chunks: list[bytes] = []
    offset = 0
    utf16 = False
    with open(path, "rb") as file:
        while chunk := file.read(TEXT_CHUNK):
            if offset == 0:
                utf16 = chunk[:2] in (b"\xff\xfe", b"\xfe\xff")
            nul = -1 if utf16 else chunk.find(b"\x00")
            if nul >= 0:
                raise error(f"{where}: not a text file (a NUL byte at offset {offset + nul}); is it binary or damaged?")
            chunks.append(chunk)
            offset += len(chunk)
    return b"".join(chunks)


@lru_cache(maxsize=8)
def installed_folder(package: str) -> Path:
    """The folder of one of the package's data folders (`wgpu_shading.wgsl`,
    `wgpu_shading.examples`): a plain folder, as wgpu's native library rules out zipped
    installs. Found once through the import system, which knows where an editable install
    keeps it; importlib.resources, asked for each of a shader's ~30 files, cost a cold start
    ~4 ms, and its import brings tempfile and random (docs/performance.md, "Cold start")."""
    spec = importlib.util.find_spec(package)
    if spec is None or not spec.submodule_search_locations:
        raise WgpuShadingError(f"the {package} folder is not installed; reinstall wgpu-shading")
    return Path(next(iter(spec.submodule_search_locations)))
