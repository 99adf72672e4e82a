"""OFF files (Geomview's Object File Format) read as a stream of tokens.

The format is whitespace-separated: nothing ties a vertex or a face to one line, and
libigl's writer breaks long faces over several lines, which trimesh (one face per line)
read as "contains no triangles". Here a face is its count n followed by n indices,
wherever the line breaks fall; what follows the indices on the face's last line is its
colour (ignored, as before). `#` starts a comment. The header keyword may carry the
prefixes ST (texture coordinates), C (vertex colours) and N (normals), in that order of
the vertex's numbers: x y z [nx ny nz] [r g b a] [s t] (Geomview's OFF specification);
polygons are fanned from their first vertex (convex polygons, as trimesh did).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import MeshError
from ..files import read_text_bytes
from .checks import off_declared_counts

_KEYWORD = re.compile(r"(ST)?(C)?(N)?(4)?(n)?OFF")


@dataclass
class OffData:
    positions: np.ndarray
    faces: np.ndarray
    normals: np.ndarray | None
    colors: np.ndarray | None
    uvs: np.ndarray | None


def read_off(path: Path, file_size: int) -> OffData:
    where = f"mesh file {str(path)!r}"
    data = read_text_bytes(path, where, MeshError)  # a NUL byte: refused at once (2 GB of NULs took minutes)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    off_declared_counts(text, where, file_size)  # limits, before anything is allocated
    fast = _triangles_only(text)
    if fast is not None:
        return fast
    lines = [line.split("#", 1)[0].split() for line in text.splitlines()]
    lines = [words for words in lines if words]
    if not lines:
        raise MeshError(f"{where}: not an OFF file (it is empty)")
    keyword = _KEYWORD.fullmatch(lines[0][0])
    if keyword is None:
        raise MeshError(f"{where}: not an OFF file (it does not start with OFF, COFF, NOFF, STOFF, ...)")
    if keyword.group(4) or keyword.group(5):
        raise MeshError(f"{where}: {lines[0][0]}: 4D and n-dimensional OFF files are not supported")
    if len(lines[0]) > 1 and lines[0][1].upper() == "BINARY":
        raise MeshError(f"{where}: binary OFF files are not supported")
    tokens = _Tokens(lines, where, 0, 1)
    vertex_count, face_count = tokens.integer("vertex count"), tokens.integer("face count")
    tokens.integer("edge count")
    has_normals, has_colors, has_uvs = bool(keyword.group(3)), bool(keyword.group(2)), bool(keyword.group(1))
    width = 3 + 3 * has_normals + 4 * has_colors + 2 * has_uvs
    vertices = tokens.numbers(vertex_count, width, "vertices")
    faces = _faces(tokens, face_count, vertex_count, where)
    column = 3
    normals = colors = uvs = None
    if has_normals:
        normals, column = vertices[:, 3:6], 6
    if has_colors:
        colors = vertices[:, column : column + 4]
        column += 4
        if colors.max(initial=0.0) > 1.0:  # integer colours 0..255
            colors = colors / 255.0
        colors = np.clip(colors, 0.0, 1.0)
    if has_uvs:
        uvs = vertices[:, column : column + 2]
    return OffData(vertices[:, :3], faces, normals, colors, uvs)


def _triangles_only(text: str) -> OffData | None:
    """The common file read in one split: plain OFF, no comments, every face a triangle
    without a colour (4 tokens each, wherever the lines break). None for anything else,
    which the line-aware reader below handles (a colour after a face's indices can only be
    told from the next face by its line)."""
    if "#" in text:
        return None
    tokens = text.split()
    if len(tokens) < 4 or tokens[0] != "OFF":
        return None
    try:
        vertex_count, face_count = int(tokens[1]), int(tokens[2])
        int(tokens[3])
        faces = tokens[4 + 3 * vertex_count :]
        if vertex_count < 0 or len(faces) != 4 * face_count or set(faces[::4]) != {"3"}:
            return None
        vertices = np.array(tokens[4 : 4 + 3 * vertex_count], dtype=np.float64).reshape(vertex_count, 3)
        triangles = np.array(faces, dtype=np.int64).reshape(face_count, 4)[:, 1:]
    except ValueError:  # not numbers where numbers belong: the careful reader names the line
        return None
    if len(triangles) and (triangles.min() < 0 or triangles.max() >= vertex_count):
        return None
    return OffData(vertices, triangles, None, None, None)


class _Tokens:
    """The tokens of the lines, read from (line, word) on."""

    def __init__(self, lines: list[list[str]], where: str, line: int, word: int):
        self.lines, self.where, self.line, self.word = lines, where, line, word

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
            raise MeshError(f"{self.where}: line {self.line + 1}: {what}: expected an integer, got {token[:20]!r}") from None

    def numbers(self, count: int, width: int, what: str) -> np.ndarray:
        """count × width numbers; fast when every line holds one row (the usual layout)."""
        if self.word >= len(self.lines[self.line]) if self.line < len(self.lines) else False:
            self.line, self.word = self.line + 1, 0
        rows = self.lines[self.line : self.line + count]
        try:
            if self.word == 0 and len(rows) == count and all(len(row) == width for row in rows):
                self.line += count
                return np.array(rows, dtype=np.float64).reshape(count, width)
            values = [float(self._next(what)) for _ in range(count * width)]
        except ValueError as error:
            raise MeshError(f"{self.where}: {what}: not a number ({error})") from None
        return np.array(values, dtype=np.float64).reshape(count, width)

    def finish_line(self) -> None:
        """Skip the rest of the current line (a face's colour)."""
        if self.word > 0:
            self.line, self.word = self.line + 1, 0


def _faces(tokens: _Tokens, face_count: int, vertex_count: int, where: str) -> np.ndarray:
    tokens.finish_line() if tokens.line < len(tokens.lines) and tokens.word >= len(tokens.lines[tokens.line]) else None
    rows = tokens.lines[tokens.line : tokens.line + face_count]
    if tokens.word == 0 and len(rows) == face_count and rows and all(row[0] == "3" and len(row) >= 4 for row in rows):
        try:  # the usual layout: one triangle per line
            faces = np.array([row[1:4] for row in rows], dtype=np.int64)
        except ValueError:
            faces = None
        if faces is not None:
            return _checked(faces, vertex_count, where)
    triangles: list[list[int]] = []
    for face in range(face_count):
        size = tokens.integer(f"face {face}")
        if size < 0 or size > vertex_count:
            raise MeshError(f"{where}: face {face} has {size} vertices (the file has {vertex_count})")
        corners = [tokens.integer(f"face {face}") for _ in range(size)]
        tokens.finish_line()  # a colour may follow the indices
        triangles.extend([corners[0], corners[k], corners[k + 1]] for k in range(1, size - 1))
    return _checked(np.array(triangles, dtype=np.int64).reshape(-1, 3), vertex_count, where)


def _checked(faces: np.ndarray, vertex_count: int, where: str) -> np.ndarray:
    if len(faces) and (faces.min() < 0 or faces.max() >= vertex_count):
        culprit = int(faces.min() if faces.min() < 0 else faces.max())
        raise MeshError(f"{where}: a face refers to vertex {culprit}, but the file has {vertex_count} vertices")
    return faces
