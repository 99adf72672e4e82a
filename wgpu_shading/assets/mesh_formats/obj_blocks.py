"""An OBJ file read a block of whole lines at a time (files.text_line_blocks, 4 MiB each):
each block's lines classified by their first two bytes in numpy, its `v`/`vt`/`vn` numbers
and its face runs read, and only the arrays kept. The text, a Python string per line of a
block, is let go block by block: a 2M-triangle OBJ (75 MB) held 250 MB of line strings
and the whole text at once before (docs/performance.md, "Loading a large mesh").

What a block leaves for the file's end (obj.py): the numbers of its vertex lines, its face
runs as resolved corners (obj_faces.py), the `usemtl`/`s` state the next block starts in,
its `mtllib` names, its `l`/`p` records as text, and the first error of each kind, which
obj.py raises in the order the whole-file reading did (vertices, elements, texture
coordinates, normals, faces), whichever line came first.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ...errors import MeshError
from ...scene.geometry.vertex_arrays import finite_rows
from .line_sections import BlockLines, joined
from .number_text import parse_floats, read_in_blocks
from .obj_faces import FaceRun, check_face_sizes, run_corners, triangles_only
from .obj_vertices import CornerTriples, RunCorners

NUMBER_LINES_AT_ONCE = 1 << 16  # v/vt/vn lines read together: bounded temporaries (a few bytes a character)
KINDS = (("v ", 3), ("vt", 2), ("vn", 3))  # the number lines: keyword, numbers kept
# The type each kind's numbers are kept in: texture coordinates only ever become the Mesh's
# float32 uvs, so they are kept as float32 (the same values, half the memory; and one too
# large for float32 is infinite here, refused by the Mesh, not drawn as infinite). Positions
# and normals stay float64: the crease normals and the normals' check work from them.
NUMBER_TYPES = {"v ": np.float64, "vt": np.float32, "vn": np.float64}


@dataclass
class FaceRunCorners:
    """A run of face lines, read: its state, its triangles' corners (obj_vertices.py: each
    corner's v, and its vt and vn only where they are not its v's own) and, when some face
    is a polygon, each triangle's polygon (for ear clipping once the positions are known);
    None when every face is a triangle."""

    material: str | None
    flat: bool
    corners: RunCorners
    polygon: np.ndarray | None


@dataclass
class ObjContent:
    """What the blocks of an OBJ file read so far hold (obj.py turns it into pieces)."""

    name: str
    vertex_limit: int
    triangle_limit: int
    lines: int = 0  # lines read so far
    counts: dict = field(default_factory=lambda: {keyword: 0 for keyword, _ in KINDS})  # v/vt/vn lines so far
    polygons: int = 0  # face lines so far
    triangles: int = 0  # their fans' triangles so far (the blocks read whole)
    triangle_line: int = 0  # the line whose face took the triangles past the limit
    numbers: dict = field(default_factory=lambda: {keyword: [] for keyword, _ in KINDS})  # keyword → (n, w) blocks (NUMBER_TYPES)
    runs: list[FaceRunCorners] = field(default_factory=list)
    triples: CornerTriples = field(default_factory=CornerTriples)  # each v's own (vt, vn), for the runs' corners
    libraries: list[str] = field(default_factory=list)
    material: str | None = None  # the state the next line is in
    flat: bool = False
    # `l` and `p` records: kind → {line index: (text, v declared before it, material)}
    elements: dict = field(default_factory=lambda: {"lines": {}, "points": {}})
    errors: dict = field(default_factory=dict)  # the first error of each kind ("v ", "vt", "vn", "f")
    notes: list[str] = field(default_factory=list)  # what to tell the user once the file is read (MeshFile.notes)

    @property
    def over_limit(self) -> bool:
        """More vertices or faces than supported: the rest is only counted (obj.py says how many)."""
        return self.counts["v "] > self.vertex_limit or self.polygons > self.triangle_limit or self.triangles > self.triangle_limit

    def read_block(self, data: bytes) -> None:
        """One block of whole lines (the file's first: its byte-order mark and line ends
        already seen to, obj.py)."""
        starts, first, second = _line_starts(data)
        if ((first == 32) | (first == 9)).any():
            data = _without_indentation(data)
            starts, first, second = _line_starts(data)
        if b"\\" in data and _LINE_CONTINUATION.search(data):  # (a backslash anywhere first: bytes' own search)
            data = _CONTINUED_LINE.sub(_joined_line, data)
            starts, first, second = _line_starts(data)
        if _has_trailing_comment(data):
            data = _TRAILING_COMMENT.sub(rb"\1", data)
            starts, first, second = _line_starts(data)
        blank = (second == 32) | (second == 9)
        is_f = (first == ord("f")) & blank
        kinds = {"v ": (first == ord("v")) & blank, "vt": (first == ord("v")) & (second == ord("t")),
                 "vn": (first == ord("v")) & (second == ord("n"))}
        before = dict(self.counts)  # the counts at the block's start
        counts = {keyword: np.cumsum(is_kind) for keyword, is_kind in kinds.items()}  # within the block, up to each line
        for keyword in self.counts:
            self.counts[keyword] += int(counts[keyword][-1]) if len(starts) else 0
        self.polygons += int(is_f.sum())
        offset, self.lines = self.lines, self.lines + len(starts)
        if self.over_limit:  # counted, never split into lines (obj.py raises with the totals)
            return
        if "f" not in self.errors:
            try:
                check_face_sizes(data, starts, np.flatnonzero(is_f), self.name, offset + 1)
            except MeshError as error:
                self.errors["f"] = error
        lines = BlockLines(data, starts)  # (each decoded only when asked for: most are read from the bytes)
        changes = self._state(lines, np.flatnonzero((first == ord("u")) | (first == ord("s")) | (first == ord("m"))))
        change_at = np.array([index for index, _, _ in changes], np.int64)

        def state_at(index: int) -> tuple[str | None, bool]:
            state = int(np.searchsorted(change_at, index)) - 1
            return changes[state][1:]

        for keyword, width in KINDS:
            rows = np.flatnonzero(kinds[keyword])
            if len(rows) and keyword not in self.errors:
                try:
                    run = lines.sub(int(rows[0]), int(rows[-1]) + 1) if rows[-1] - rows[0] + 1 == len(rows) else lines.take(rows)
                    self.numbers[keyword].append(_floats(run, keyword, width, self.name, offset + rows + 1))
                except MeshError as error:
                    self.errors[keyword] = error
        for kind, letter in (("lines", "l"), ("points", "p")):
            for index in np.flatnonzero((first == ord(letter)) & blank).tolist():
                self.elements[kind][offset + index] = (lines[index], before["v "] + int(counts["v "][index]), state_at(index)[0])
        face_lines = np.flatnonzero(is_f)
        if not len(face_lines) or "f" in self.errors:
            return
        # Runs: blocks of consecutive face lines (the counts and the state are fixed within one).
        breaks = np.flatnonzero(np.diff(face_lines) != 1) + 1
        for a, b in zip(np.concatenate([[0], breaks]).tolist(), np.concatenate([breaks, [len(face_lines)]]).tolist()):
            index = int(face_lines[a])
            material, flat = state_at(index)
            run = FaceRun(material, flat, *(before[keyword] + int(counts[keyword][index]) for keyword, _ in KINDS),
                          offset + index + 1, lines.sub(index, int(face_lines[b - 1]) + 1))
            try:
                corners, polygon = run_corners(run, self.name, self.notes)
            except MeshError as error:
                self.errors["f"] = error
                return
            split = self.triples.split(corners, self.counts["v "])
            self.runs.append(FaceRunCorners(material, flat, split, None if triangles_only(polygon) else polygon))
            self.triangles += len(corners)
            if self.triangles > self.triangle_limit:  # polygons cut into more triangles than supported: the rest is only counted
                self.triangle_line = offset + index + 1 + int(polygon[self.triangle_limit - (self.triangles - len(corners))])
                return

    def _state(self, lines: BlockLines, state_lines: np.ndarray) -> list[tuple[int, str | None, bool]]:
        """The block's state changes in order, (line index, material, flat) from there on,
        after the state the block starts in (index −1); `mtllib` names are kept."""
        changes = [(-1, self.material, self.flat)]
        for index in state_lines.tolist():
            line = lines[index].strip()
            if line.startswith("usemtl"):
                self.material = line[6:].strip() or None
            elif line.startswith("s ") or line.startswith("s\t"):
                self.flat = line[2:].strip().lower() in ("off", "0")
            elif line.startswith("mtllib"):
                self.libraries.append(line[6:].strip())
                continue
            else:
                continue
            changes.append((index, self.material, self.flat))
        return changes

    def vertex_numbers(self, keyword: str) -> np.ndarray:
        """Every `keyword` line's numbers, (n, width) of NUMBER_TYPES; `v` lines with colours (x y z
        r g b) in some blocks give every vertex a colour (white where a line had none), as
        the line-by-line reading does (_floats)."""
        blocks = self.numbers[keyword]
        if not blocks:
            return np.zeros((0, dict(KINDS)[keyword]), NUMBER_TYPES[keyword])
        return blocks.pop() if len(blocks) == 1 else joined(blocks, NUMBER_TYPES[keyword], fill=1.0)  # (1.0: white)


def _numbers(lines: Sequence[str], prefix: str, width: int) -> np.ndarray | None:
    """Every number of the lines (their `v`/`vt`/`vn` left out) when each holds `width`,
    NUMBER_LINES_AT_ONCE lines at a time: the reading's temporaries stay a few MB however
    big the file, and in cache. Consecutive lines of a block are read from its bytes,
    never decoded."""
    keyword = prefix.strip()
    if isinstance(lines, BlockLines):
        key = keyword.encode()
        return read_in_blocks(range(len(lines)), NUMBER_LINES_AT_ONCE,
                              lambda block: parse_floats(lines.text(block.start, block.stop).replace(key, b" "), width))
    return read_in_blocks(lines, NUMBER_LINES_AT_ONCE, lambda block: parse_floats("\n".join(block).replace(keyword, " "), width))


def _floats(lines: Sequence[str], prefix: str, width: int, path: str, numbers: np.ndarray) -> np.ndarray:
    """The numbers of `v` / `vt` / `vn` lines as an (n, columns) array of the kind's
    NUMBER_TYPES; `numbers` are their 1-based line numbers (for errors)."""
    first = len(lines[0].split()) - 1 if len(lines) else width  # the first line's numbers (x y z, or x y z r g b)
    values = _numbers(lines, prefix, first) if first == width or (prefix == "v " and first == 6) else None
    if values is not None:
        array = values.reshape(-1, first)
    else:  # mixed widths (vt u v w, v x y z w), a line short of numbers or a bad number: line by line
        rows = []
        for ordinal, line in enumerate(lines):
            text = line.strip()[len(prefix.strip()) :]
            try:
                row = [float(token) for token in text.split()]
            except ValueError:
                raise MeshError(f"{path}:{numbers[ordinal]}: cannot read {prefix.strip()!r} line {line.strip()!r} (expected numbers)") from None
            if len(row) < width:
                raise MeshError(f"{path}:{numbers[ordinal]}: {prefix.strip()!r} line has {len(row)} numbers, expected {width}")
            rows.append(row[:6] if prefix == "v " and len(row) >= 6 else row[:width])
        if prefix == "v " and any(len(r) == 6 for r in rows):
            rows = [r if len(r) == 6 else r[:3] + [1.0, 1.0, 1.0] for r in rows]
        array = np.array(rows, dtype=np.float64).reshape(len(rows), -1)
    kept = array.astype(NUMBER_TYPES[prefix], copy=False)
    for checked, what in ((array, "a NaN or infinite coordinate"), (kept, "a number beyond float32's range")):  # (the second: a float32 too large, infinite)
        finite = finite_rows(checked[:, :width])
        if finite is not None:
            ordinal = int(np.flatnonzero(~finite)[0])
            raise MeshError(f"{path}:{numbers[ordinal]}: {prefix.strip()!r} line has {what}: {lines[ordinal].strip()[len(prefix.strip()):].strip()!r}")
    return kept


# A comment after an element's numbers (`v 1 2 3 # top`, `f 1 2 3 # lid`, `s off # flat`):
# trimesh and VTK's reader (f3d's) read past it. Names (`usemtl`, `o`, `g`, `mtllib`) are left
# as they are: a `#` may be part of one.
_TRAILING_COMMENT = re.compile(rb"^((?:v|vt|vn|vp|f|l|p|s)[ \t][^#\n]*)#[^\n]*", re.MULTILINE)


# A line ending in a backslash goes on on the next one (the OBJ specification; Blender's
# importer reads it): `f 1 2 \` then `3 4`. The lines are joined with a blank, and as many
# empty lines follow as were joined, so every later line keeps its number for errors.
_LINE_CONTINUATION = re.compile(rb"\\[ \t]*\r?\n")
# (Tried at line starts only; never from a comment line: `# C:\models\` goes on nowhere.)
_CONTINUED_LINE = re.compile(rb"^(?!#)(?:[^\n]*\\[ \t]*\r?\n)+[^\n]*", re.MULTILINE)


def _joined_line(match: re.Match) -> bytes:
    text = match.group(0)
    return _LINE_CONTINUATION.sub(b" ", text) + b"\n" * text.count(b"\n")


def _has_trailing_comment(data: bytes) -> bool:
    """Whether an element line of `data` has a comment after its numbers: each `#` found
    with bytes.find (C's memchr), a comment line skipped whole (MeshLab's `####` banners),
    so a file with only comment lines costs a few finds, not a pass of the regex."""
    at = data.find(b"#")
    while at >= 0:
        line_start = data.rfind(b"\n", 0, at) + 1
        if data[line_start:at].strip(b" \t") and _TRAILING_COMMENT.match(data, line_start):
            return True
        end = data.find(b"\n", at)
        if end < 0:
            return False
        at = data.find(b"#", end)
    return False


def _without_indentation(data: bytes) -> bytes:
    """Lines with their leading blanks removed: the OBJ spec allows them, and the
    classification looks at a line's first two bytes."""
    return b"\n".join(line.lstrip(b" \t") for line in data.split(b"\n"))


def _line_starts(data: bytes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each line's first byte offset and its first two bytes (0 past the end), in numpy; a
    block ending with a newline has no empty line after it (the next block goes on)."""
    raw = np.frombuffer(data + b"\0\0", np.uint8)
    starts = np.concatenate([[0], np.flatnonzero(raw[: len(data)] == 10) + 1])
    if len(starts) > 1 and starts[-1] == len(data):
        starts = starts[:-1]
    return starts, raw[starts], raw[starts + 1]
