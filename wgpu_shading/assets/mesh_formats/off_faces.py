"""The face lines of a plain OFF read a block at a time (off.py, `_plain_in_blocks`): every
line `n i1 .. in`, the same polygon size n in every line, and optionally the same number of
colour values after the indices on every line (`r g b` or `r g b a`, 0..255 integers as
MeshLab writes them or 0..1 floats as Geomview's examples do), read in C; or polygons of
several sizes (triangles and quads), each line's numbers counted, each with its own colour
or none.

Face colours sent a file to the reader of tokens (off.py, `_Tokens`), a Python call or more
a word: a 2M-triangle OFF with a colour a face took 34 s and 12.9x its arrays to load
(docs/performance.md, "Loading a large mesh"), and so did faces of several sizes (22x), and
faces of several sizes with colours (10x and 42 s, until the twenty-first pass). A face's
colour is what follows its indices on its line, as the reader of tokens takes it: 3 or 4
values (RGB, RGBA), anything else none (a colour-map index: white). Anything else (a
comment, a face over several lines, a bad number) gives False, and the reader of tokens
reads the file and names what is wrong.
"""

from __future__ import annotations

import numpy as np

from ...errors import MeshError
from ..mesh_pieces import polygon_fans
from .line_sections import joined
from .number_text import LEADING_COUNT, blank_bytes, counted_lines, parse_floats, parse_numbers, word_starts

COLOUR_WIDTHS = (0, 3, 4)  # values after a face's indices: none, RGB, RGBA


class PlainFaces:
    """The fans of a plain OFF's faces and their colours, read a block of face lines at a time."""

    def __init__(self, vertex_count: int, where: str):
        self.vertex_count, self.where = vertex_count, where
        self.corners: int | None = None  # the polygon size, from the first face
        self.colour_width: int | None = None  # values after the indices, from the first face
        self.mixed = False  # whether faces of several sizes were met: every block is then _mixed's
        self.triangles: list[np.ndarray] = []  # (t, 3) int32 a block
        self.colours: list[np.ndarray] = []  # (faces, colour width) float64 a block, faces of one size
        # Once mixed, each block's faces: (their colours (faces, 4) float64, NaN where a face
        # has none or only RGB, and each face's count of triangles), or the block's count of
        # triangles when none of its faces has a colour.
        self.mixed_colours: list[tuple[np.ndarray, np.ndarray] | int] = []

    def read(self, face_lines: list[str]) -> bool:
        """One block's face lines; False when they are not of this layout."""
        if self.corners is None and face_lines:  # the first face's size, before any number is read
            first = LEADING_COUNT.match(face_lines[0])
            if first is not None and int(first.group(1)) > self.vertex_count:  # as the reader of tokens says it
                raise MeshError(f"{self.where}: face 0 has {int(first.group(1))} vertices (the file has {self.vertex_count})")
        text = "\n".join(face_lines)
        if "#" in text or not face_lines:
            return False
        numbers = parse_numbers(text, np.int64)
        if numbers is None:  # colours as floats (or not numbers at all)
            numbers = None if self.mixed else self._indices_and_floats(text, len(face_lines))
            if numbers is None:
                return self._mixed(face_lines, text, None)
        if not numbers.size:
            return False
        if self.mixed or not self._uniform(numbers, len(face_lines)):
            return self._mixed(face_lines, text, numbers)
        corners, width = self.corners, numbers.size // len(face_lines)
        rows = numbers.reshape(len(face_lines), width)
        polygons = rows[:, : corners + 1]
        if (polygons[:, 0] != corners).any():  # (as many numbers a line, by chance)
            return self._mixed(face_lines, text, numbers)
        if polygons[:, 1:].min() < 0 or polygons[:, 1:].max() >= self.vertex_count:
            return False
        if self.colour_width:
            colours = rows[:, corners + 1 :].astype(np.float64)
            if not np.isfinite(colours).all():
                return False
            self.colours.append(colours)
        self.triangles.append(polygon_fans(polygons[:, 1:]).astype(np.int32))
        return True

    def _uniform(self, numbers: np.ndarray, lines: int) -> bool:
        """Whether the block's lines are each a face of the first face's size with as many
        colour values as it (taking those from this block when it is the first)."""
        if numbers.size % lines:
            return False
        width = numbers.size // lines
        if self.corners is None:
            self.corners = int(numbers[0])
            self.colour_width = width - self.corners - 1
        corners = self.corners
        return 3 <= corners <= self.vertex_count and self.colour_width in COLOUR_WIDTHS and width == corners + 1 + self.colour_width

    def _mixed(self, face_lines: list[str], text: str, numbers: np.ndarray | None) -> bool:
        """A block of faces of several sizes, each fanned from its first corner, one after the
        other, as the reader of tokens fans them (faces of fewer than 3 corners give none),
        with the colour after its indices (`numbers` None: some are floats, read here);
        False for anything else (a bad index or number: the reader of tokens reads or names it)."""
        values = numbers if numbers is not None else parse_floats(text)
        if values is None or not values.size or (numbers is None and not np.isfinite(values).all()):
            return False  # (a NaN or infinite colour: the reader of tokens names it)
        records = counted_lines(face_lines, values)
        if records is None:
            return False
        counts, first, per_line = records
        if counts.max() > self.vertex_count:
            return False
        if numbers is None and not _integers_only(text, _index_tokens(counts, per_line)):
            return False  # `3.0` or `1e0` as a count or an index: the reader of tokens refuses it, naming the line
        fan_rows = np.maximum(counts - 2, 0)
        first_row = np.cumsum(fan_rows) - fan_rows
        triangles = np.empty((int(fan_rows.sum()), 3), np.int32)
        for size in np.unique(counts[counts >= 3]):
            chosen = counts == size
            polygons = values[first[chosen][:, None] + 1 + np.arange(size)]
            if polygons.min() < 0 or polygons.max() >= self.vertex_count:
                return False
            triangles[(first_row[chosen][:, None] + np.arange(size - 2)).reshape(-1)] = polygon_fans(polygons.astype(np.int64))
        colours = _trailing_colours(values, counts, first, per_line - counts - 1)
        if not self.mixed:  # the blocks of one size before: their colours as this one keeps them
            if self.colours:  # (one a block, each of its faces self.corners - 2 triangles)
                self.mixed_colours = [(_padded(rows), np.full(len(rows), self.corners - 2)) for rows in self.colours]
            else:
                self.mixed_colours = [len(block) for block in self.triangles]
            self.colours.clear()
            self.mixed = True
        self.triangles.append(triangles)
        self.mixed_colours.append(len(triangles) if colours is None else (colours, fan_rows))
        return True

    def _indices_and_floats(self, text: str, lines: int) -> np.ndarray | None:
        """The numbers of lines whose colours are floats (float64), when every index (and
        each line's count) is a plain integer: the reader of tokens reads them with int(),
        which refuses `3.0` or `1e0`, so they are refused here too (None)."""
        values = parse_floats(text)
        if values is None or not values.size or values.size % lines:
            return None
        width = values.size // lines
        corners = int(values[0]) if float(values[0]).is_integer() else -1
        if not 0 <= corners < width:
            return None
        return values if _integers_only(text, np.arange(values.size) % width <= corners) else None

    def finish(self) -> tuple[np.ndarray, np.ndarray | None]:
        """The triangles (T, 3) int32 and each triangle's RGBA in [0, 1] (its face's), or None
        without colours, as the reader of tokens reads them (off.py, `_face_colors`)."""
        triangles = joined(self.triangles, np.int32) if self.triangles else np.empty((0, 3), np.int32)
        if self.mixed:
            colours = _mixed_face_colours(self.mixed_colours)
            self.mixed_colours.clear()
            return triangles, colours
        if not self.colours:
            return triangles, None
        colours = np.concatenate(self.colours)
        self.colours.clear()
        return triangles, np.repeat(unit_colors_by_largest(colours), self.corners - 2, axis=0)


def _trailing_colours(values: np.ndarray, counts: np.ndarray, first: np.ndarray, rest: np.ndarray) -> np.ndarray | None:
    """Each face's RGBA from the values after its indices (`rest` of them), NaN where absent:
    3 or 4 values are a colour, any other number none (the reader of tokens' rule). None
    when no face of the block has one."""
    if not ((rest == 3) | (rest == 4)).any():
        return None
    rows = np.full((len(counts), 4), np.nan)
    for width in (3, 4):
        chosen = rest == width
        if chosen.any():
            rows[chosen, :width] = values[(first[chosen] + 1 + counts[chosen])[:, None] + np.arange(width)]
    return rows


def _padded(rows: np.ndarray) -> np.ndarray:
    """(faces, 3 or 4) colours as (faces, 4), NaN where there is no alpha."""
    padded = np.full((len(rows), 4), np.nan)
    padded[:, : rows.shape[1]] = rows
    return padded


def _mixed_face_colours(blocks: list[tuple[np.ndarray, np.ndarray] | int]) -> np.ndarray | None:
    """Each triangle's RGBA in [0, 1] from PlainFaces._mixed's blocks, as the reader of
    tokens makes them (off.py, `_face_colors`): its face's colour; the alpha of an RGB one,
    and the whole of a face without one, `full` (white, opaque): 255 where some triangle's
    value is above 1 (0..255 integers), else 1; then every value divided by 255 where the
    largest is above 1 (unit_colors_by_largest). None when no triangle has a colour."""
    coloured = [rows[fans > 0] for rows, fans in (block for block in blocks if not isinstance(block, int))]
    present = [rows[~np.isnan(rows)] for rows in coloured]
    if not any(values.size for values in present):
        return None
    # (unit_colors_by_largest divides by 255 exactly where `full` is 255: the padding is among its values)
    full = 255.0 if max(float(values.max(initial=0.0)) for values in present) > 1.0 else 1.0
    parts = []
    for block in blocks:
        if isinstance(block, int):
            parts.append(np.full((block, 4), 1.0))
        else:
            rows, fans = block
            parts.append(np.repeat(np.clip(np.where(np.isnan(rows), full, rows) / full, 0.0, 1.0), fans, axis=0))
    return np.concatenate(parts)


def _index_tokens(counts: np.ndarray, per_line: np.ndarray) -> np.ndarray:
    """Per number of the lines: whether it is a line's count or one of its indices."""
    line_start = np.cumsum(per_line) - per_line
    position = np.arange(int(per_line.sum())) - np.repeat(line_start, per_line)
    return position <= np.repeat(counts, per_line)


def _integers_only(text: str, is_index: np.ndarray) -> bool:
    """Whether every number `is_index` marks (one flag a number of `text`, in order) is
    written as a plain integer: the reader of tokens reads counts and indices with int(),
    which refuses `3.0` or `1e0`."""
    encoded = text.encode("latin-1")
    data = np.frombuffer(encoded, np.uint8)
    blank = blank_bytes(encoded)
    filled = ~blank
    starts = word_starts(encoded, blank)
    token = np.maximum(np.cumsum(starts, dtype=np.int64) - 1, 0)  # each byte's number (blanks: the one before)
    in_index = filled & is_index[np.minimum(token, len(is_index) - 1)]
    digit = (data >= ord("0")) & (data <= ord("9"))
    sign = starts & ((data == ord("-")) | (data == ord("+")))
    return not (in_index & ~digit & ~sign).any()


def unit_colors_by_largest(colors: np.ndarray) -> np.ndarray:
    """RGB or RGBA rows, 0..255 integers or 0..1 floats (told apart by the largest value),
    as RGBA in [0, 1]."""
    if colors.shape[1] == 3:
        colors = np.concatenate([colors, np.full((len(colors), 1), 255.0 if colors.max(initial=0.0) > 1.0 else 1.0)], axis=1)
    if colors.max(initial=0.0) > 1.0:  # integer colours 0..255
        colors = colors / 255.0
    return np.clip(colors, 0.0, 1.0)
