"""ASCII STL in the layout exporters write, read a block of lines at a time.

    solid NAME
    facet normal nx ny nz
    outer loop
    vertex x y z          (three of these)
    endloop
    endfacet
    ...                   (a facet is always these seven lines)
    endsolid NAME         (a file without it, ending after a whole facet, is read with a warning)

trimesh reads ASCII STL as one lower-cased copy of the whole text, then a string per
`vertex` line, and keeps every corner as its own float64 vertex: ~6 bytes per byte of
text, 19x the mesh's arrays for a 2M-triangle file (docs/performance.md, "Loading a large
mesh"). Here the text comes in blocks of whole lines (files.text_line_blocks), each block's
facets are checked line by line in numpy (every line's keyword, and its count of words: 5,
2, 4, 4, 4, 1, 1), the keywords and the `facet normal` lines are then blanked and the
nine numbers of each facet's vertices read in C (number_text.parse_floats), float64 as
trimesh reads them, joined into vertices as a binary STL's are (corner_join.py): the same triangles,
corner by corner, on a sixth of the vertices; the crease normals weld by exact position
anyway, so every corner gets the normal it got before and the images are the same (the
facet normals are not used, by either). Anything else (several solids, upper-case
keywords, a blank or extra line, a facet of other than three vertices, a word where a
number belongs) gives None, and trimesh reads the file as before (stl.py).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.geometry.mesh import MAX_TRIANGLES
from ..files import LongLine, text_line_blocks
from ..mesh_pieces import MeshPiece
from .corner_join import CornerJoin
from .line_sections import joined
from .number_text import BLANK_BYTES, parse_floats, word_starts

# A facet's seven lines: each one's keyword and its count of words (keywords and numbers).
_LINES = (("facet normal", 5), ("outer loop", 2), ("vertex", 4), ("vertex", 4), ("vertex", 4), ("endloop", 1), ("endfacet", 1))
_KEYWORD_BYTES = 12  # the longest keyword, "facet normal": each line's first 12 bytes are compared
_INDENT = 16  # blanks a line may start with (exporters indent by 0 to 6)
_EXPECTED = np.array([list(word.encode().ljust(_KEYWORD_BYTES, b"\0")) for word, _ in _LINES], np.uint8)
_WORDS = np.array([words for _, words in _LINES])
_LENGTHS = np.array([len(word) for word, _ in _LINES])
_CORNER_NUMBERS = 9  # a facet's three vertices' three (its normal's are not read)
JOIN_CORNERS = 3 << 18  # corners joined at a time: as a binary STL's blocks of triangles (stl.py)
BLOCK_BYTES = 1 << 20  # text read at a time: its parsing takes ~10 bytes a byte (number_text.py)
LONGEST_LINE = 1 << 16  # a facet's lines are short: a longer one is another layout, not read whole here


def read_plain_ascii_stl(path: Path, where: str, notes: list[str] | None = None) -> MeshPiece | None:
    """The file's triangles with equal corners joined (corner_join.py, as a binary STL's:
    float64 vertices sorted by their bits), or None when the file is not in the plain
    layout; what the user should be told goes to `notes` (MeshFile.notes)."""
    try:
        return _read(path, where, [] if notes is None else notes)
    except LongLine:  # (no line of the layout is long: not read further)
        return None


def _read(path: Path, where: str, notes: list[str]) -> MeshPiece | None:
    join = CornerJoin(np.float64)
    ids: list[np.ndarray] = []  # each corner's vertex id (order met), a joined block at a time
    pending: list[np.ndarray] = []  # corners read, not yet joined
    pending_corners = triangles = 0
    rest = b""  # the lines after the last whole facet read, not yet a facet
    for number, block in enumerate(text_line_blocks(path, where, MeshError, BLOCK_BYTES, LONGEST_LINE)):
        text = rest + block
        if number == 0:  # the `solid NAME` line
            head, _, text = text.partition(b"\n")
            if not head.lstrip().lower().startswith(b"solid"):
                return None
        data = np.frombuffer(text, np.uint8)
        ends = np.flatnonzero(data == 10)
        facets = len(ends) // 7
        cut = int(ends[7 * facets - 1]) + 1 if facets else 0
        corners = _facet_corners(data[:cut], ends[: 7 * facets])
        if corners is None:
            return None
        rest = text[cut:]
        triangles += facets
        if triangles > MAX_TRIANGLES:
            raise MeshError(f"{where}: more than {MAX_TRIANGLES} triangles; at most {MAX_TRIANGLES} are supported")
        pending.append(corners)
        pending_corners += len(corners)
        if pending_corners >= JOIN_CORNERS:  # joined in large blocks: each join copies the index once
            ids.append(join.add(np.concatenate(pending)).reshape(-1, 3))
            pending.clear()
            pending_corners = 0
    last = rest.strip()
    if last.lower().startswith(b"facet") and last.count(b"\n") < len(_LINES) - 1 and b"endsolid" not in last.lower():
        # (fewer lines than a facet's, the first a facet's: the file ends inside one)
        raise MeshError(f"{where}: truncated: it ends inside facet {triangles + 1}, after {triangles} whole ones")
    if not triangles or (last and (not last.lower().startswith(b"endsolid") or b"\n" in last)):
        return None  # (no facet, or something after them other than one `endsolid` line)
    if not last:  # whole facets to the end, no `endsolid` (a file cut short between facets): VTK's reader draws them
        notes.append(f"{where}: no 'endsolid' line at its end (cut short?); the {triangles} whole facet(s) before it are drawn")
    if pending:
        ids.append(join.add(np.concatenate(pending)).reshape(-1, 3))
    del pending
    faces = joined(ids, np.uint32)
    positions = join.finish(faces)  # (the faces renumbered to the sorted vertices)
    return MeshPiece(positions, faces, parts=[(0, triangles, None, path.name)])


def _facet_corners(data: np.ndarray, ends: np.ndarray) -> np.ndarray | None:
    """The (3 × facets, 3) float64 corners of whole facets of the plain layout (`data`: the
    text's bytes, `ends`: its newlines, 7 a facet); None for anything else."""
    lines = len(ends)
    if not lines:
        return np.zeros((0, 3))
    if data.max() >= 128:
        return None  # not ASCII
    starts = np.empty(lines, np.int64)
    starts[0], starts[1:] = 0, ends[:-1] + 1
    padded = np.concatenate([data, np.full(_INDENT + _KEYWORD_BYTES + 1, 10, np.uint8)])  # (newlines: blank)
    # Each line's keyword: after at most _INDENT blanks, then followed by a blank. (Column
    # by column: temporaries of one value a line, not of a line's bytes.)
    first = starts
    for _ in range(_INDENT):
        indented = BLANK_BYTES[padded[first]]
        if not indented.any():
            break
        first = first + indented
    if np.any(first >= ends):
        return None  # a blank line, or one indented further
    kind = np.tile(np.arange(7), lines // 7)
    lengths = _LENGTHS[kind]
    for column in range(_KEYWORD_BYTES):
        within = column < lengths
        if not np.array_equal(padded[first[within] + column], _EXPECTED[kind[within], column]):
            return None  # another keyword
    if not BLANK_BYTES[padded[first + lengths]].all():
        return None  # a longer word ("vertexes")
    # Every line has its count of words (keyword and numbers).
    word_start = word_starts(data)
    if not np.array_equal(np.add.reduceat(word_start, starts, dtype=np.int32), _WORDS[kind]):
        return None
    numbers = data.copy()
    for column in range(_KEYWORD_BYTES):  # the keywords blanked
        numbers[first[column < lengths] + column] = 32
    # The `facet normal` lines blanked whole: no reader uses the file's normals (the crease
    # normals are computed), and their numbers were a quarter of the reading.
    normal_lines = np.zeros(len(data) + 1, np.int8)
    normal_lines[starts[::7]] = 1
    normal_lines[ends[::7]] -= 1
    numbers[np.cumsum(normal_lines[:-1], dtype=np.int8).view(bool)] = 32
    values = parse_floats(numbers.tobytes())
    facets = lines // 7
    if values is None or len(values) != _CORNER_NUMBERS * facets:
        return None
    return values.reshape(-1, 3)
