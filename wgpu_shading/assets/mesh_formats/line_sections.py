"""The bookkeeping of the text readers that take a file a block of lines at a time
(files.text_line_blocks) and keep only arrays: a plain OFF and an ASCII PLY mesh, whose data
is a vertex a line then a face a line, and the OBJ reader's blocks of arrays joined at the
end. One place for it, so that the readers differ only in how they read a line's numbers.
"""

from __future__ import annotations

from typing import Iterable, Iterator, Sequence

import numpy as np

from ...scene.freed_memory import return_freed_memory


class BlockLines(Sequence[str]):
    """The lines of a block of bytes (files.text_line_blocks: whole lines), each decoded
    (UTF-8, bad bytes replaced) only when asked for, the same strings as the whole block's
    `decode(...).split("\n")`: a reader takes most lines' numbers from the bytes themselves
    (`text`), and the block split into Python strings was 6.5 of the Stanford bunny OBJ's
    28 ms. `starts`: each line's first byte (as obj_blocks finds them); `stop`: where the
    last line ends (its newline excluded), by default the block's end."""

    def __init__(self, data: bytes, starts: np.ndarray, stop: int | None = None):
        self.data, self.starts = data, starts
        self.stop = (len(data) - 1 if data.endswith(b"\n") else len(data)) if stop is None else stop

    def __len__(self) -> int:
        return len(self.starts)

    def _end(self, index: int) -> int:
        """Where line `index` ends, its newline excluded."""
        return int(self.starts[index + 1]) - 1 if index + 1 < len(self.starts) else self.stop

    def text(self, first: int = 0, stop: int | None = None) -> bytes:
        """Lines first..stop−1 as bytes, joined by their newlines."""
        stop = len(self) if stop is None else stop
        return self.data[int(self.starts[first]) : self._end(stop - 1)] if stop > first else b""

    def sub(self, first: int, stop: int) -> "BlockLines":
        """Lines first..stop−1, as lines of their own."""
        return BlockLines(self.data, self.starts[first:stop], self._end(stop - 1))

    def take(self, indices: np.ndarray) -> "BlockLines":
        """Lines `indices` (increasing), as lines of their own: their bytes gathered in
        numpy (a file's `v` and `vn` lines may alternate), never decoded."""
        ends = np.append(self.starts[1:], min(self.stop + 1, len(self.data)))  # each line's end, its newline included
        lengths = ends - self.starts
        chosen = np.zeros(len(self), bool)
        chosen[indices] = True
        first = int(self.starts[0])
        data = np.frombuffer(self.data, np.uint8, int(ends[-1]) - first, first)[np.repeat(chosen, lengths)].tobytes()
        return BlockLines(data, np.concatenate([[0], np.cumsum(lengths[indices])[:-1]]))

    def __getitem__(self, index):
        if isinstance(index, slice):
            first, stop, step = index.indices(len(self))
            if step != 1:
                return [self[k] for k in range(first, stop, step)]
            return self.text(first, stop).decode("utf-8", errors="replace").split("\n") if stop > first else []
        if index < 0:
            index += len(self)
        if not 0 <= index < len(self):
            raise IndexError(index)
        return self.data[int(self.starts[index]) : self._end(index)].decode("utf-8", errors="replace")

    def __iter__(self) -> Iterator[str]:
        return iter(self[:])


def ascii_texts(blocks: Iterable[bytes], skip: int = 0) -> Iterator[str | None]:
    """The blocks as text, past their first `skip` bytes (a header of whole lines); None for
    a block that is not ASCII, after which nothing more is given (the numbers of these
    formats are ASCII: the whole-text readers take any other file)."""
    for block in blocks:
        if skip:  # (the header is whole lines: a block ends at its end or beyond)
            block, skip = block[skip:], max(skip - len(block), 0)
            if not block:
                continue
        try:
            yield block.decode("ascii")
        except UnicodeDecodeError:
            yield None
            return


def vertex_and_face_lines(texts: Iterable[str | None], vertices: int, faces: int) -> Iterator[tuple[list[str], list[str]] | None]:
    """Per text block: its vertex lines and its face lines, for data that is `vertices`
    lines then `faces` lines (blank lines after the last face dropped). None, and nothing
    after it, where the data is otherwise: a block that is not text, more lines than
    that, or fewer."""
    vertices_read = faces_read = 0
    for text in texts:
        if text is None:
            yield None
            return
        lines = text.split("\n")
        if lines[-1] == "":
            lines.pop()
        wanted = min(len(lines), vertices - vertices_read)
        face_lines = lines[wanted:]
        while face_lines and faces_read + len(face_lines) > faces and not face_lines[-1].strip():
            face_lines.pop()  # blank lines after the last face
        if faces_read + len(face_lines) > faces:
            yield None
            return
        yield lines[:wanted], face_lines
        vertices_read += wanted
        faces_read += len(face_lines)
    if vertices_read != vertices or faces_read != faces:
        yield None


# Blocks freed while joining, then handed back (return_freed_memory): glibc keeps freed blocks
# of a few MB on its heap, so without it the copy and the freed blocks were both resident.
GIVE_BACK_BYTES = 32 << 20


def joined(blocks: list[np.ndarray], dtype, fill=0) -> np.ndarray:
    """The blocks' rows in one array, their last axis as wide as the widest block's (`fill`
    in the columns a block lacks), each block let go once copied: the rows are never all
    in memory twice. The list is emptied. (np.empty: its pages are taken as the rows are
    copied in, while the blocks' are given back.)"""
    width = max(block.shape[-1] for block in blocks)
    out = np.empty((sum(len(block) for block in blocks), *blocks[0].shape[1:-1], width), dtype)
    start, since_given_back = 0, 0
    blocks.reverse()
    while blocks:
        block = blocks.pop()
        rows = slice(start, start + len(block))
        out[rows, ..., : block.shape[-1]] = block
        out[rows, ..., block.shape[-1] :] = fill
        start += len(block)
        since_given_back += block.nbytes
        del block
        if since_given_back >= GIVE_BACK_BYTES:  # blocks of a few MB sit on glibc's heap once freed: hand them back
            return_freed_memory()
            since_given_back = 0
    return out
