"""OFF files (Geomview's Object File Format) read as a stream of tokens; the commonest,
a vertex a line then a face a line, a block of lines at a time (bounded memory).

The format is whitespace-separated: nothing ties a vertex or a face to one line, and
libigl's writer breaks long faces over several lines, which trimesh (one face per line)
read as "contains no triangles". Here a face is its count n followed by n indices,
wherever the line breaks fall; what follows the indices on the face's last line is its
colour. `#` starts a comment. The header keyword may carry the prefixes ST (texture
coordinates), C (vertex colours) and N (normals), in that order of the vertex's numbers:
x y z [nx ny nz] [r g b a] [s t] (Geomview's OFF specification); polygons are fanned from
their first vertex (convex polygons, as trimesh did).

The header is read by lines, as every tool writes it: the counts line holds the vertex
and face counts and, optionally, the edge count (ignored): many writers give only two
counts (`4 1`), so an edge count is read only from the face count's own line. The counts
may share the keyword's line (`OFF 8 6 0`) or be glued to it (`OFF8 6 0`, as the ModelNet
files are written). Beyond Geomview, as Online3DViewer reads them: a plain OFF whose every
vertex line holds 6 or 7 numbers carries vertex colours (docs/real-world-files.md).
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import MeshError
from ...scene.freed_memory import return_freed_memory
from ..files import TEXT_BLOCK_BYTES, read_text_bytes, text_line_blocks
from ..mesh_pieces import MeshFile, MeshPiece, point_piece, polygon_fans, with_face_colors
from .checks import check_declared_counts
from .line_sections import ascii_texts, vertex_and_face_lines
from .number_text import parse_floats, tokens_as_numbers
from .off_faces import PlainFaces, unit_colors_by_largest

_KEYWORD = re.compile(r"(ST)?(C)?(N)?(4)?(n)?OFF(\d*)")


@dataclass
class _OffArrays:
    positions: np.ndarray
    faces: np.ndarray
    normals: np.ndarray | None
    colors: np.ndarray | None
    uvs: np.ndarray | None
    face_colors: np.ndarray | None = None  # (faces, 4) in [0, 1], one row per triangle


@dataclass
class _Header:
    keyword: re.Match
    vertex_count: int
    face_count: int
    rest: list[str]  # words after the counts on their line: a one-line file's data
    line: int  # the number (from 1) of the line that holds the last count
    offset: int  # where the next line starts in the text


def read_off(path: Path, file_size: int) -> MeshFile:
    """An OFF file as one piece, its face colours given each face's own corners."""
    off = _read_arrays(path, file_size)
    if not len(off.faces):  # `N 0 0`: a point cloud (docs/primitives.md)
        return MeshFile([point_piece(off.positions, off.normals, off.colors, name=path.name)], self_contained=True)
    piece = MeshPiece(off.positions, off.faces, off.normals, off.uvs, off.colors, parts=[(0, len(off.faces), None, path.name)])
    return MeshFile([piece if off.face_colors is None else with_face_colors(piece, off.face_colors)], self_contained=True)


def _read_arrays(path: Path, file_size: int) -> _OffArrays:
    where = f"mesh file {str(path)!r}"
    plain = _plain_in_blocks(path, file_size, where)
    if plain is not None:
        return plain
    data = read_text_bytes(path, where, MeshError)  # a NUL byte: refused at once (2 GB of NULs took minutes)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    header = _header(text, where)
    # limits, before anything is allocated: at least "0 0 0\n" a vertex, "3 0 0 0\n" a face
    check_declared_counts(where, header.vertex_count, header.face_count, 6 * header.vertex_count + 8 * header.face_count, file_size)
    fast = _uniform_faces(text, header)
    if fast is not None:
        return fast
    numbered = [(header.line, header.rest)]
    numbered += [(n, line.split("#", 1)[0].split()) for n, line in enumerate(text[header.offset :].splitlines(), header.line + 1)]
    numbered = [(n, words) for n, words in numbered if words]
    tokens = _Tokens([words for _, words in numbered], [n for n, _ in numbered], where)
    width = _vertex_width(header)
    vertices = tokens.numbers(header.vertex_count, width, "vertices", extra_widths=() if width > 3 else PLAIN_COLOUR_WIDTHS)
    faces, face_colors = _faces(tokens, header.face_count, header.vertex_count, where)
    return _OffArrays(*_vertex_columns(vertices[:, :3], vertices[:, 3:], header, faces, face_colors))


PLAIN_COLOUR_WIDTHS = (6, 7)  # a plain OFF's vertex lines of x y z r g b [a] (Online3DViewer reads them)


def _vertex_width(header: _Header) -> int:
    """The numbers of a vertex, by the keyword: x y z [nx ny nz] [r g b a] [s t]."""
    has_normals, has_colors, has_uvs = (bool(header.keyword.group(k)) for k in (3, 2, 1))
    return 3 + 3 * has_normals + 4 * has_colors + 2 * has_uvs


def _vertex_columns(positions: np.ndarray, extra: np.ndarray, header: _Header, faces: np.ndarray, face_colors: np.ndarray | None) -> tuple:
    """_OffArrays' fields from the vertices' x y z and their other numbers (V, width - 3,
    or a plain OFF's colour widths - 3). Colours become float32 here, the precision the Mesh
    keeps, so that a COFF's colours are not held in float64 beside the crease analysis."""
    has_normals, has_colors, has_uvs = (bool(header.keyword.group(k)) for k in (3, 2, 1))
    column = 0
    normals = colors = uvs = None
    if has_normals:
        normals, column = extra[:, 0:3], 3
    if has_colors or 3 + extra.shape[1] > _vertex_width(header):  # COFF, or a plain OFF with colours after x y z
        colors = unit_colors_by_largest(extra[:, column : column + 4]).astype(np.float32)
        column += 4
    if has_uvs:
        uvs = extra[:, column : column + 2]
    return positions, faces, normals, colors, uvs, face_colors if colors is None else None


def _header(text: str, where: str) -> _Header:
    """The keyword and counts, read line by line from the start of the text."""
    keyword, counts, offset, number = None, [], 0, 0
    names = ("vertex count", "face count")
    while offset < len(text):
        end = text.find("\n", offset)
        end = len(text) if end < 0 else end + 1
        words, offset, number = text[offset:end].split("#", 1)[0].split(), end, number + 1
        if not words:
            continue
        if keyword is None:
            keyword = _KEYWORD.fullmatch(words[0])
            if keyword is None:
                raise MeshError(f"{where}: not an OFF file (it does not start with OFF, COFF, NOFF, STOFF, ...)")
            if keyword.group(4) or keyword.group(5):
                raise MeshError(f"{where}: {words[0]}: 4D and n-dimensional OFF files are not supported")
            if len(words) > 1 and words[1].upper() == "BINARY":
                raise MeshError(f"{where}: binary OFF files are not supported")
            words = [keyword.group(6)] * bool(keyword.group(6)) + words[1:]  # OFF8 6 0: the count glued on
        while words and len(counts) < 2:
            counts.append(_count(words.pop(0), names[len(counts)], number, where))
        if len(counts) == 2:
            if words:  # the edge count, on the face count's line (ignored, as by every reader)
                _count(words.pop(0), "edge count", number, where)
            return _Header(keyword, counts[0], counts[1], words, number, offset)
    if keyword is None:
        raise MeshError(f"{where}: not an OFF file (it is empty)")
    raise MeshError(f"{where}: truncated: the file ends in its header (expected the vertex and face counts)")


def _count(token: str, what: str, line: int, where: str) -> int:
    try:
        value = int(token)
    except ValueError:
        raise MeshError(f"{where}: line {line}: {what}: expected an integer, got {token[:20]!r}") from None
    if value < 0:
        raise MeshError(f"{where}: line {line}: {what}: expected a count, got {value}")
    return value


HEADER_BYTES = 1 << 16  # the most text before the counts (comments) read here; more, and the whole text is read


def _plain_in_blocks(path: Path, file_size: int, where: str) -> _OffArrays | None:
    """The commonest OFF read a block of lines at a time (files.text_line_blocks), without
    the whole text: its tokens are never all Python strings at once (a 2M-triangle OFF
    split into tokens peaked at 22x its arrays). No comments, a vertex a line (x y z and
    what the keyword adds, `COFF`, `NOFF`, `STOFF`..., or a plain OFF's r g b [a]), then a
    face a line, every face the same polygon, with or without a colour of as many values on
    every line (off_faces.py), as the readers below read them (numbers read in C, polygons
    fanned from their first corner). None for anything else, and for a
    file that turns out otherwise on the way (a blank line, a comment, a bad index): the
    whole-text readers below then read it, and name what is wrong."""
    blocks = text_line_blocks(path, where, MeshError)
    first, header = b"", None
    while header is None and len(first) <= HEADER_BYTES:  # the blocks up to the counts' line
        block = next(blocks, None)
        if block is None:
            return None
        first += block
        try:
            header = _header(first.decode("ascii"), where)
        except UnicodeDecodeError:
            return None
        except MeshError as error:
            if "ends in its header" not in str(error):
                return None
    if header is None:
        return None
    if header.rest or not header.face_count:
        return None
    check_declared_counts(where, header.vertex_count, header.face_count, 6 * header.vertex_count + 8 * header.face_count, file_size)
    width = _vertex_width(header)
    # x y z and the vertex lines' other numbers (the first line's width - 3), once it is read:
    # apart, so that a COFF's colours are not kept beside its positions in one wide array
    positions = extra = None
    faces = PlainFaces(header.vertex_count, where)
    read_vertices = 0
    texts = ascii_texts(itertools.chain([first], blocks), skip=header.offset)
    for section in vertex_and_face_lines(texts, header.vertex_count, header.face_count):
        if section is None:
            return None
        vertex_lines, face_lines = section
        if vertex_lines:
            text = "\n".join(vertex_lines)
            values = None if "#" in text else parse_floats(text)
            if positions is None and values is not None:
                line_width = values.size // len(vertex_lines)
                if line_width != width and not (width == 3 and line_width in PLAIN_COLOUR_WIDTHS):
                    return None
                positions, extra = np.empty((header.vertex_count, 3)), np.empty((header.vertex_count, line_width - 3))
            if values is None or values.size != (3 + extra.shape[1]) * len(vertex_lines):
                return None
            rows = values.reshape(len(vertex_lines), -1)
            positions[read_vertices : read_vertices + len(rows)] = rows[:, :3]
            extra[read_vertices : read_vertices + len(rows)] = rows[:, 3:]
            read_vertices += len(rows)
        if face_lines and not faces.read(face_lines):
            return None
    if positions is None:  # (no vertex lines: the counts say otherwise, or none)
        positions, extra = np.empty((header.vertex_count, 3)), np.empty((header.vertex_count, width - 3))
    arrays = _OffArrays(*_vertex_columns(positions, extra, header, *faces.finish()))
    if file_size > TEXT_BLOCK_BYTES:  # several blocks: their temporaries given back
        return_freed_memory()
    return arrays


def _uniform_faces(text: str, header: _Header) -> _OffArrays | None:
    """The common file read in one split: plain OFF, no comments, every face the same
    polygon (triangles, or quads as some exporters write) without a colour (n + 1 tokens
    each, wherever the lines break), its numbers read in C (number_text.py), polygons fanned
    as the line-aware reader fans them. None for anything else, which the line-aware reader
    below handles (a colour after a face's indices can only be told from the next face by
    its line)."""
    if header.keyword.group(0) != "OFF" or "#" in text:
        return None
    tokens = header.rest + text[header.offset :].split()
    vertex_count, face_count = header.vertex_count, header.face_count
    faces = tokens[3 * vertex_count :]
    corners = len(faces) // face_count - 1 if face_count else 0
    if not 3 <= corners <= vertex_count or len(faces) != (corners + 1) * face_count or set(faces[:: corners + 1]) != {str(corners)}:
        return None
    try:
        vertices = tokens_as_numbers(tokens[: 3 * vertex_count], np.float64).reshape(vertex_count, 3)
        polygons = tokens_as_numbers(faces, np.int64).reshape(face_count, corners + 1)[:, 1:]
    except ValueError:  # not numbers where numbers belong: the careful reader names the line
        return None
    if polygons.min() < 0 or polygons.max() >= vertex_count:
        return None
    return _OffArrays(vertices, polygon_fans(polygons), None, None, None)


class _Tokens:
    """The tokens of the (non-empty) lines, read from (line, word) on; `numbers` holds each
    line's number in the file, for messages."""

    def __init__(self, lines: list[list[str]], numbers: list[int], where: str):
        self.lines, self.line_numbers, self.where, self.line, self.word = lines, numbers, where, 0, 0

    def _here(self) -> str:
        return f"line {self.line_numbers[min(self.line, len(self.lines) - 1)]}" if self.lines else "line 1"

    def _next(self, what: str) -> str:
        while self.line < len(self.lines) and self.word >= len(self.lines[self.line]):
            self.line, self.word = self.line + 1, 0
        if self.line >= len(self.lines):
            raise MeshError(f"{self.where}: truncated: the file ends while reading the {what}")
        token = self.lines[self.line][self.word]
        self.word += 1
        return token

    def integer(self, what: str) -> int:
        token = self._next(what)
        try:
            return int(token)
        except ValueError:
            raise MeshError(f"{self.where}: {self._here()}: {what}: expected an integer, got {token[:20]!r}") from None

    def numbers(self, count: int, width: int, what: str, extra_widths: tuple[int, ...] = ()) -> np.ndarray:
        """count × width numbers; fast when every line holds one row (the usual layout). When
        every one of those lines holds w numbers, w in extra_widths, count × w."""
        self.settle()
        rows = self.lines[self.line : self.line + count]
        widths = {len(row) for row in rows}
        try:
            if self.word == 0 and len(rows) == count and len(widths) == 1 and widths <= {width, *extra_widths}:
                self.line += count
                return np.array(rows, dtype=np.float64).reshape(count, -1)
            values = [float(self._next(what)) for _ in range(count * width)]
        except ValueError as error:
            raise MeshError(f"{self.where}: {self._here()}: {what}: not a number ({error})") from None
        return np.array(values, dtype=np.float64).reshape(count, width)

    def rest_of_line(self) -> list[str]:
        """The words left on the current line (a face's colour), and move past them."""
        rest = self.lines[self.line][self.word :] if self.line < len(self.lines) and self.word > 0 else []
        if self.word > 0:
            self.line, self.word = self.line + 1, 0
        return rest

    def settle(self) -> None:
        """Past a line whose words are all read: at the next line's start."""
        if self.line < len(self.lines) and self.word >= len(self.lines[self.line]):
            self.line, self.word = self.line + 1, 0


def _faces(tokens: _Tokens, face_count: int, vertex_count: int, where: str) -> tuple[np.ndarray, np.ndarray | None]:
    """The triangles (polygons fanned) and, when faces carry them, their colours."""
    tokens.settle()
    rows = tokens.lines[tokens.line : tokens.line + face_count]
    if tokens.word == 0 and len(rows) == face_count and rows and all(row[0] == "3" and len(row) == 4 for row in rows):
        try:  # the usual layout: one triangle per line, no colours
            faces = np.array([row[1:4] for row in rows], dtype=np.int64)
        except ValueError:
            faces = None
        if faces is not None:
            return _checked(faces, vertex_count, where), None
    triangles: list[list[int]] = []
    colors: list[list[str]] = []
    for face in range(face_count):
        size = tokens.integer(f"face {face}")
        if size < 0 or size > vertex_count:
            raise MeshError(f"{where}: face {face} has {size} vertices (the file has {vertex_count})")
        corners = [tokens.integer(f"face {face}") for _ in range(size)]
        color = tokens.rest_of_line()  # RGB or RGBA; one word is a colour-map index (no map: ignored)
        triangles.extend([corners[0], corners[k], corners[k + 1]] for k in range(1, size - 1))
        colors.extend([color if len(color) in (3, 4) else []] * max(size - 2, 0))
    faces = _checked(np.array(triangles, dtype=np.int64).reshape(-1, 3), vertex_count, where)
    return faces, _face_colors(colors, where)


def _face_colors(colors: list[list[str]], where: str) -> np.ndarray | None:
    """Per-triangle RGBA in [0, 1]; a face without a colour is white (its material's colour)."""
    if not any(colors):
        return None
    try:
        values = [[float(c) for c in color] for color in colors]
    except ValueError as error:
        raise MeshError(f"{where}: a face colour is not a number ({error})") from None
    full = 255.0 if max(max(row, default=0.0) for row in values) > 1.0 else 1.0  # integers 0..255 or floats 0..1
    rows = np.array([row + [full] * (4 - len(row)) if row else [full] * 4 for row in values])
    if not np.isfinite(rows).all():
        raise MeshError(f"{where}: a face colour is not finite")
    return unit_colors_by_largest(rows)


def _checked(faces: np.ndarray, vertex_count: int, where: str) -> np.ndarray:
    if len(faces) and (faces.min() < 0 or faces.max() >= vertex_count):
        culprit = int(faces.min() if faces.min() < 0 else faces.max())
        raise MeshError(f"{where}: a face refers to vertex {culprit}, but the file has {vertex_count} vertices")
    return faces
