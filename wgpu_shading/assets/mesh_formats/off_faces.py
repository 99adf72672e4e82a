"""The face lines of a plain OFF read a block at a time (off.py, `_plain_in_blocks`): every
line `n i1 .. in`, the same polygon size n in every line, and optionally the same number of
colour values after the indices on every line (`r g b` or `r g b a`, 0..255 integers as
MeshLab writes them or 0..1 floats as Geomview's examples do), read in C; or polygons of
several sizes without colours (triangles and quads), each line's numbers counted.

Face colours sent a file to the reader of tokens (off.py, `_Tokens`), a Python call or more
a word: a 2M-triangle OFF with a colour a face took 34 s and 12.9x its arrays to load
(docs/performance.md, "Loading a large mesh"), and so did faces of several sizes (22x).
Anything else (faces of several sizes with colours, a colour-map index, a comment, a bad
number) gives False, and the reader of tokens reads the
file and names what is wrong.
"""

from __future__ import annotations

import numpy as np

from ...errors import MeshError
from ..mesh_pieces import polygon_fans
from .line_sections import joined
from .number_text import BLANK_BYTES, LEADING_COUNT, leading_counts, parse_floats, parse_numbers

COLOUR_WIDTHS = (0, 3, 4)  # values after a face's indices: none, RGB, RGBA


class PlainFaces:
    """The fans of a plain OFF's faces and their colours, read a block of face lines at a time."""

    def __init__(self, vertex_count: int, where: str):
        self.vertex_count, self.where = vertex_count, where
        self.corners: int | None = None  # the polygon size, from the first face
        self.colour_width: int | None = None  # values after the indices, from the first face
        self.mixed = False  # whether faces of several sizes were met (then no colours)
        self.triangles: list[np.ndarray] = []  # (t, 3) int32 a block
        self.colours: list[np.ndarray] = []  # (faces, colour width) float64 a block

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
            numbers = self._indices_and_floats(text, len(face_lines))
            if numbers is None:
                return False
        if not numbers.size:
            return False
        if not self._uniform(numbers, len(face_lines)):
            return self._mixed(face_lines, numbers)
        corners, width = self.corners, numbers.size // len(face_lines)
        rows = numbers.reshape(len(face_lines), width)
        polygons = rows[:, : corners + 1]
        if (polygons[:, 0] != corners).any():  # (as many numbers a line, by chance)
            return self._mixed(face_lines, numbers)
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
        if self.mixed and self.colour_width:  # (no colours once faces of several sizes were met)
            return False
        return 3 <= corners <= self.vertex_count and self.colour_width in COLOUR_WIDTHS and width == corners + 1 + self.colour_width

    def _mixed(self, face_lines: list[str], numbers: np.ndarray) -> bool:
        """A block of faces of several sizes without colours, each fanned from its first
        corner, one after the other, as the reader of tokens fans them (faces of fewer than
        3 corners give none); False for anything else (colours, a bad index: the reader of
        tokens reads or names it)."""
        if self.colours or numbers.dtype != np.int64:
            return False
        records = leading_counts(face_lines, numbers)
        if records is None:
            return False
        counts, first = records
        if counts.max() > self.vertex_count:
            return False
        fan_rows = np.maximum(counts - 2, 0)
        first_row = np.cumsum(fan_rows) - fan_rows
        triangles = np.empty((int(fan_rows.sum()), 3), np.int32)
        for size in np.unique(counts[counts >= 3]):
            chosen = counts == size
            polygons = numbers[first[chosen][:, None] + 1 + np.arange(size)]
            if polygons.min() < 0 or polygons.max() >= self.vertex_count:
                return False
            triangles[(first_row[chosen][:, None] + np.arange(size - 2)).reshape(-1)] = polygon_fans(polygons)
        self.triangles.append(triangles)
        self.mixed = True
        if self.corners is None:  # (a later block of one size is read as such, without colours)
            self.corners, self.colour_width = int(counts[0]), 0
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
        data = np.frombuffer(text.encode("ascii"), np.uint8)
        filled = ~BLANK_BYTES[data]
        starts = filled.copy()
        starts[1:] &= ~filled[:-1]
        token = np.cumsum(starts, dtype=np.int64) - 1  # each byte's token (blanks: the one before)
        in_index = filled & (token % width <= corners)  # the count and the indices of each line
        digit = (data >= ord("0")) & (data <= ord("9"))
        sign = starts & ((data == ord("-")) | (data == ord("+")))
        return None if (in_index & ~digit & ~sign).any() else values

    def finish(self) -> tuple[np.ndarray, np.ndarray | None]:
        """The triangles (T, 3) int32 and each triangle's RGBA in [0, 1] (its face's), or None
        without colours, as the reader of tokens reads them (off.py, `_face_colors`)."""
        triangles = joined(self.triangles, np.int32) if self.triangles else np.empty((0, 3), np.int32)
        if not self.colours:
            return triangles, None
        colours = np.concatenate(self.colours)
        self.colours.clear()
        return triangles, np.repeat(unit_colors_by_largest(colours), self.corners - 2, axis=0)


def unit_colors_by_largest(colors: np.ndarray) -> np.ndarray:
    """RGB or RGBA rows, 0..255 integers or 0..1 floats (told apart by the largest value),
    as RGBA in [0, 1]."""
    if colors.shape[1] == 3:
        colors = np.concatenate([colors, np.full((len(colors), 1), 255.0 if colors.max(initial=0.0) > 1.0 else 1.0)], axis=1)
    if colors.max(initial=0.0) > 1.0:  # integer colours 0..255
        colors = colors / 255.0
    return np.clip(colors, 0.0, 1.0)
