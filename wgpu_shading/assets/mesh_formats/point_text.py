"""Point clouds as text, one point a line: `.xyz` (CloudCompare, MeshLab, Agisoft, Open3D)
and `.pts` (Leica, Open3D), drawn as points (docs/primitives.md#point-clouds-as-text).

A line is x y z and what the columns after them say, separated by spaces, tabs, commas or
semicolons; `#` and `//` lines are comments, and CloudCompare's header comment naming the
columns (`//X Y Z R G B Nx Ny Nz`) says which is which, as does a first line of names alone
(PDAL's `"X","Y","Z","Red","Green","Blue"`). Without one, the count decides
(every data line must have the same): 3 x y z; 4 x y z and a scalar (ignored); 6 x y z and
a normal when every row's last three numbers are a unit vector (MeshLab, Open3D `.xyzn`),
else a colour; 7 x y z, a scalar and a colour (Leica PTS; a `.pts` line holding one
whole number is a scan's point count, skipped); 9 x y z with a normal and a colour, in the
order the unit vectors say. Colours are 0..255, or 0..1 when every value is at most 1 and
one is not whole (Open3D `.xyzrgb`).

Read a block of lines at a time into float64 arrays (coordinates far from the origin keep
their precision: scans in UTM metres); a bad line is one error naming the file and line,
and the file size and the vertex limit bound what is allocated.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.freed_memory import return_freed_memory
from ...scene.geometry.mesh import MAX_VERTICES
from ..mesh_pieces import MeshFile, point_piece
from .number_text import parse_floats

_BLOCK_BYTES = 1 << 20  # text read at a time: parse_floats' temporaries are ~20 bytes a character
RETURNED_BYTES = 64 << 20  # blocks of numbers let go between two calls of return_freed_memory
_SEPARATORS = bytes.maketrans(b",;\t\r", b"    ")
_COLOR_NAMES = {"r": 0, "red": 0, "g": 1, "green": 1, "b": 2, "blue": 2}
_NORMAL_NAMES = {"nx": 0, "ny": 1, "nz": 2}
_AXIS_NAMES = {"x": 0, "y": 1, "z": 2}


def read_xyz(path: Path, file_size: int) -> MeshFile:
    """A `.xyz` file (assets/meshes.py's reader) as points."""
    return _read(path, counts=False)


def read_pts(path: Path, file_size: int) -> MeshFile:
    """A `.pts` file: as `.xyz`, with lines of a single whole number (point counts) skipped."""
    return _read(path, counts=True)


class _Lines:
    """The data lines of a file, a block at a time: (line numbers, rows of numbers)."""

    def __init__(self, path: Path, counts: bool):
        self.path, self.counts = path, counts  # errors name the file and line as compilers do: path:line:
        self.names: list[str] | None = None  # a header comment's column names
        self.width = 0  # numbers per data line, from the first

    def blocks(self):
        line = 1
        carry = b""
        with open(self.path, "rb") as file:
            while True:
                chunk = file.read(_BLOCK_BYTES)
                data = carry + chunk
                if chunk:
                    cut = data.rfind(b"\n") + 1
                    data, carry = data[:cut], data[cut:]
                    if not data:
                        if len(carry) > 1 << 20:
                            raise MeshError(f"{self.path}:{line}: a line longer than 1 MiB; not a point per line")
                        continue
                rows = self._rows(data, line)
                if len(rows):
                    yield rows
                line += data.count(b"\n")
                if not chunk:
                    return

    def _rows(self, data: bytes, first_line: int) -> np.ndarray:
        data = data.translate(_SEPARATORS)
        if b"\x00" in data:
            number = first_line + data[: data.index(b"\x00")].count(b"\n")
            raise MeshError(f"{self.path}:{number}: a NUL byte; not a text file")
        if self.width and b"#" not in data and b"/" not in data:
            # read in C (number_text.py: what float() gives each), when every line holds
            # `width` numbers: a blank line, a count or a line of another width is read below
            values = parse_floats(data, self.width)
            if values is not None and np.isfinite(values).all():
                return values.reshape(-1, self.width)
        return self._rows_one_by_one(data, first_line)

    def _rows_one_by_one(self, data: bytes, first_line: int) -> np.ndarray:
        """The slow way, which knows each line's number: comments, blank lines, counts, errors."""
        rows = []
        for number, text in enumerate(data.split(b"\n"), first_line):
            words = text.split()
            if not words:
                continue
            if words[0].startswith((b"#", b"//")):
                if self.names is None and not self.width:
                    self.names = [w.lower() for w in text.lstrip(b"#/ ").decode("latin-1").split()]
                continue
            if self.counts and len(words) == 1 and words[0].isdigit():
                continue
            if not self.width and self.names is None and _is_header(words):  # PDAL's `"X","Y","Z"`: no `//`
                self.names = [word.strip(b"\"'").decode("latin-1").lower() for word in words]
                continue
            if not self.width:
                self.width = len(words)
                if self.width < 3:
                    raise MeshError(f"{self.path}:{number}: {_shown(text)}: a point needs x y z")
            if len(words) != self.width:
                raise MeshError(f"{self.path}:{number}: {_shown(text)}: {len(words)} numbers where the first point has {self.width}")
            try:
                row = [float(word) for word in words]
            except ValueError:
                raise MeshError(f"{self.path}:{number}: {_shown(text)}: not {self.width} numbers") from None
            if not all(np.isfinite(row)):
                raise MeshError(f"{self.path}:{number}: {_shown(text)}: a NaN or infinite number")
            rows.append(row)
        return np.array(rows, dtype=np.float64).reshape(-1, self.width or 1)


def _is_header(words: list[bytes]) -> bool:
    """Whether a first line names its columns (x, y and z among them, no number), as PDAL's
    text writer and spreadsheets write one without CloudCompare's `//`."""
    names = [word.strip(b"\"'").lower() for word in words]
    return {b"x", b"y", b"z"} <= set(names) and not any(_is_number(name) for name in names)


def _is_number(word: bytes) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def _shown(text: bytes) -> str:
    return repr(text.strip()[:60].decode("latin-1"))


def _read(path: Path, counts: bool) -> MeshFile:
    where = f"mesh file {str(path)!r}"
    lines = _Lines(path, counts)
    blocks, total = [], 0
    try:
        for rows in lines.blocks():
            total += len(rows)
            if total > MAX_VERTICES:
                raise MeshError(f"{where}: more than {MAX_VERTICES} points; at most that many are supported")
            blocks.append(rows)
    except OSError as error:
        raise MeshError(f"{where}: cannot be read ({error.strerror or error})") from None
    if not total:
        raise MeshError(f"{where}: holds no points (no line of x y z numbers)")
    axes, normals_at, colors_at = _columns(lines, blocks, where)
    positions = np.empty((total, 3))
    normals = None if normals_at is None else np.empty((total, 3), np.float32)
    colors = None if colors_at is None else np.empty((total, 3))
    start = freed = 0
    while blocks:  # each block copied once, then let go: the file's numbers are never held twice
        rows = blocks.pop(0)
        freed += rows.nbytes
        if freed >= RETURNED_BYTES:  # the blocks are small: glibc keeps them on its heap unless asked
            return_freed_memory()
            freed = 0
        end = start + len(rows)
        positions[start:end] = rows[:, axes]
        if normals is not None:
            normals[start:end] = rows[:, normals_at]
        if colors is not None:
            colors[start:end] = rows[:, colors_at]
        start = end
    if colors is not None:
        colors = _unit_colors(colors, where)
    return MeshFile([point_piece(positions, normals, colors, name=path.name)], self_contained=True)


def _columns(lines: _Lines, blocks: list[np.ndarray], where: str) -> tuple[list[int], list[int] | None, list[int] | None]:
    """Which columns are the axes, the normal and the colour (the module's docstring)."""
    width = lines.width
    names = lines.names if lines.names is not None and len(lines.names) == width else None
    if names is not None and {"x", "y", "z"} <= set(names):
        axes = [names.index(axis) for axis in _AXIS_NAMES]
        normal = [names.index(n) for n in _NORMAL_NAMES] if set(_NORMAL_NAMES) <= set(names) else None
        color = None
        for red, green, blue in (("r", "g", "b"), ("red", "green", "blue")):
            if {red, green, blue} <= set(names):
                color = [names.index(red), names.index(green), names.index(blue)]
        return axes, normal, color
    xyz = [0, 1, 2]
    if width in (3, 4):
        return xyz, None, None
    if width == 6:
        return (xyz, [3, 4, 5], None) if _unit_vectors(blocks, [3, 4, 5]) else (xyz, None, [3, 4, 5])
    if width == 7:
        return xyz, None, [4, 5, 6]
    if width == 9:
        return (xyz, [3, 4, 5], [6, 7, 8]) if _unit_vectors(blocks, [3, 4, 5]) else (xyz, [6, 7, 8], [3, 4, 5])
    raise MeshError(f"{where}: {width} numbers a line; read are 3 (x y z), 4 (and a scalar), 6 (and a normal or a colour), "
                    f"7 (a scalar and a colour) or 9 (a normal and a colour), or columns named by a '//X Y Z ...' header line")


def _unit_vectors(blocks: list[np.ndarray], columns: list[int]) -> bool:
    return all(np.allclose(np.linalg.norm(rows[:, columns], axis=1), 1.0, atol=1e-3) for rows in blocks)


def _unit_colors(colors: np.ndarray, where: str) -> np.ndarray:
    """Colours in [0, 1] with alpha 1: 0..255, or 0..1 when all are at most 1 and one is not whole."""
    low, high = float(colors.min()), float(colors.max())
    if low < 0 or high > 255:
        raise MeshError(f"{where}: colour values from {low:g} to {high:g}; expected 0..255 (or 0..1)")
    fractions = high <= 1.0 and not np.array_equal(colors, np.round(colors))
    unit = colors if fractions else colors / 255.0
    return np.concatenate([unit, np.ones((len(unit), 1))], axis=1)
