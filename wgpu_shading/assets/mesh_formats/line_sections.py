"""The bookkeeping of the text readers that take a file a block of lines at a time
(files.text_line_blocks) and keep only arrays: a plain OFF and an ASCII PLY mesh, whose data
is a vertex a line then a face a line, and the OBJ reader's blocks of arrays joined at the
end. One place for it, so that the readers differ only in how they read a line's numbers.
"""

from __future__ import annotations

from typing import Iterable, Iterator

import numpy as np


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


def joined(blocks: list[np.ndarray], dtype, fill=0) -> np.ndarray:
    """The blocks' rows in one array, their last axis as wide as the widest block's (`fill`
    in the columns a block lacks), each block let go once copied: the rows are never all
    in memory twice. The list is emptied. (np.empty: its pages are taken as the rows are
    copied in, while the blocks' are given back.)"""
    width = max(block.shape[-1] for block in blocks)
    out = np.empty((sum(len(block) for block in blocks), *blocks[0].shape[1:-1], width), dtype)
    start = 0
    blocks.reverse()
    while blocks:
        block = blocks.pop()
        rows = slice(start, start + len(block))
        out[rows, ..., : block.shape[-1]] = block
        out[rows, ..., block.shape[-1] :] = fill
        start += len(block)
        del block
    return out
