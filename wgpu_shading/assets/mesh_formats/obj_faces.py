"""OBJ face lines (`f`): runs of them read at once in numpy or line by line, fan-triangulated,
their indices resolved (positive from the start, negative back from the v/vt/vn declared so
far, 0 an error), and concave polygons cut again by ear clipping. obj.py reads the rest of
the file and gives each run here."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ...errors import MeshError
from .checks import MAX_FACE_CORNERS
from .line_sections import BlockLines
from .number_text import blank_bytes, parse_numbers, word_starts


@dataclass
class FaceRun:
    """Consecutive face lines with the same state (material, smoothing, vertex counts)."""

    material: str | None
    flat: bool
    vertex_count: int
    uv_count: int
    normal_count: int
    first_line: int
    lines: Sequence[str] = field(default_factory=list)  # a BlockLines (line_sections.py): read from its bytes


def run_corners(run: FaceRun, path: str, notes: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """Triangle corners of a run: (T, 3, 3) int64 zero-based (v, vt, vn) with −1 for absent,
    and the run-relative polygon index of each triangle. What the user should be told is
    added to `notes` (said once the file is read: MeshFile.notes)."""
    lines = run.lines
    at_once = fans_at_once(lines)
    if at_once is not None:
        raw, polygon = at_once
    else:  # a face the vectorised reading cannot take (a bad number, under 3 corners, mixed formats): line by line, fan-triangulated
        triangles, polygon_of = [], []
        for ordinal, line in enumerate(lines):
            tokens = line.split()[1:]
            try:
                parsed = [[int(x) if x else 0 for x in (token.split("/") + ["", ""])[:3]] for token in tokens]
            except ValueError:
                raise MeshError(f"{path}:{face_line(run, ordinal)}: cannot read face {line.strip()!r} (expected vertex indices)") from None
            if len(parsed) < 3:
                raise MeshError(f"{path}:{face_line(run, ordinal)}: a face needs at least 3 vertices, got {line.strip()!r}")
            for k in range(1, len(parsed) - 1):
                triangles.append([parsed[0], parsed[k], parsed[k + 1]])
                polygon_of.append(ordinal)
        raw = np.array(triangles, np.int64).reshape(-1, 3, 3)
        polygon = np.array(polygon_of, np.int64)
    counts = np.array([run.vertex_count, run.uv_count, run.normal_count])
    fast = resolve_positive(raw, counts)
    if fast is not None:
        return fast, polygon
    zero = raw[:, :, 0] == 0
    if zero.any():
        ordinal = int(polygon[np.flatnonzero(zero.any(axis=1))[0]])
        raise MeshError(f"{path}:{face_line(run, ordinal)}: face index 0 in {lines[ordinal].strip()!r} (OBJ indices start at 1)")
    # Positive indices count from 1; negative ones back from the last v/vt/vn declared so far.
    resolved = np.where(raw > 0, raw - 1, np.where(raw < 0, counts + raw, -1))
    missing = (raw != 0) & ((resolved < 0) | (resolved >= counts))
    for column, what, plural in ((1, "texture coordinate (vt)", "texture coordinates"), (2, "normal (vn)", "normals")):
        # A vt/vn index past the declared ones (OpenSubdiv's catmark_torus_creases0.obj has no
        # vn lines at all): the faces are still there, as f3d draws them; only the attribute goes.
        if missing[:, :, column].any():
            ordinal = int(polygon[np.flatnonzero(missing[:, :, column].any(axis=1))[0]])
            notes.append(f"{path}:{face_line(run, ordinal)}: face {lines[ordinal].strip()!r} refers to a {what} that does not exist "
                         f"({run.uv_count} vt, {run.normal_count} vn declared before it); its {plural} are ignored")
            resolved[:, :, column] = np.where(missing[:, :, column], -1, resolved[:, :, column])
    out_of_range = missing[:, :, 0].any(axis=1)
    if out_of_range.any():
        ordinal = int(polygon[np.flatnonzero(out_of_range)[0]])
        raise MeshError(
            f"{path}:{face_line(run, ordinal)}: face {lines[ordinal].strip()!r} refers to a vertex that does not exist "
            f"({run.vertex_count} v, {run.uv_count} vt, {run.normal_count} vn declared before it)"
        )
    return resolved, polygon


FACE_LINES_AT_ONCE = 1 << 16  # lines read together: bounded temporaries (~40 bytes a line, a few arrays of them)
# Corners of one face line (checks.MAX_FACE_CORNERS). Text blocks bound the corners read at
# once (4 MiB of lines: files.text_line_blocks), except a single line longer than a block,
# which is a block of its own: such lines are counted on their bytes first.


def check_face_sizes(data: bytes, starts: np.ndarray, face_lines: np.ndarray, path: str, first_line: int) -> None:
    """A MeshError naming the first face line of the block (`data`, its lines beginning at
    `starts`) with more than MAX_FACE_CORNERS corners. Only lines long enough to hold that
    many (two bytes a corner at least) are counted, on their bytes."""
    ends = np.append(starts[1:], len(data))
    for index in face_lines[ends[face_lines] - starts[face_lines] > 2 * MAX_FACE_CORNERS].tolist():
        text = np.frombuffer(data, np.uint8, ends[index] - starts[index], starts[index])
        words = int(np.count_nonzero(word_starts(text)))
        if words - 1 > MAX_FACE_CORNERS:  # (the `f` is a word too)
            raise MeshError(f"{path}:{first_line + index}: a face of {words - 1} corners; at most {MAX_FACE_CORNERS} are supported")


def fans_at_once(lines: Sequence[str]) -> tuple[np.ndarray, np.ndarray] | None:
    """The fan triangles of face lines (each starting with `f`) read in numpy, the same as the
    line-by-line reading gives: (T, 3, 3) one-based (v, vt, vn), 0 where absent, and each
    triangle's line. Any polygon sizes (an exporter's quads among triangles: Blender's) and
    `v//vn` corners (`v/0/vn`: a vt of 0 is absent). None where some corner has another
    number of slashes than the first, or a number is bad, or a face has under 3 corners:
    the line-by-line reading then says where. (Line by line, Suzanne's 500 quads took 3.6 ms
    of its 5 ms load.) In blocks of FACE_LINES_AT_ONCE lines."""
    raws, polygons, per_corner = [], [], None
    for start in range(0, len(lines), FACE_LINES_AT_ONCE):
        stop = min(start + FACE_LINES_AT_ONCE, len(lines))
        # The lines' bytes as the block holds them (a BlockLines), never decoded; text otherwise.
        text = lines.text(start, stop) if isinstance(lines, BlockLines) else "\n".join(lines[start:stop]).encode()
        block = _block_fans(text, stop - start, per_corner)
        if block is None:
            return None
        raw, polygon, per_corner = block
        raws.append(raw)
        polygons.append(polygon + start)
    if len(raws) == 1:
        return raws[0], polygons[0]
    return np.concatenate(raws), np.concatenate(polygons)


def _block_fans(text: bytes, line_count: int, per_corner: int | None) -> tuple[np.ndarray, np.ndarray, int] | None:
    """fans_at_once for one block of `line_count` lines (`text`, joined by newlines);
    `per_corner`: the numbers a corner has in the blocks before."""
    if b"/" in text and b"//" in text:  # (one character is found with memchr: 0.01 ms; "//" took 0.5 ms a block)
        text = text.replace(b"//", b"/0/")
    data = np.frombuffer(text, np.uint8)
    filled = np.zeros(len(data) + 1, bool)  # a blank before the text
    np.logical_not(blank_bytes(text), out=filled[1:])
    starts = np.flatnonzero(filled[1:] > filled[:-1])  # where each token begins (the first line's `f` at 0)
    newlines = np.flatnonzero(data == 10)
    slash_at = np.flatnonzero(data == 47)
    line_starts = np.concatenate([[0], newlines + 1])
    # Every line `f a b c` (most files: scans, and Blender's `f a/b/c ...`): four tokens a
    # line, each line's first at its start, so no token's line need be looked up.
    triangle_lines = len(starts) == 4 * line_count and np.array_equal(starts[::4], line_starts)
    if not len(slash_at) and triangle_lines:
        if per_corner not in (None, 1):  # the run's earlier blocks had v/vt corners: not one form
            return None
        corners, per_corner = np.full(line_count, 3), 1
    else:
        if triangle_lines:
            corners = np.full(line_count, 3)
        else:
            token_line = np.searchsorted(newlines, starts)  # the newlines before a token: its line
            corners = np.bincount(token_line, minlength=line_count) - 1  # the `f` is a token too
            if len(corners) != line_count or corners.min(initial=3) < 3:
                return None
        # Each token's slashes, counted from its start to the next token's (the text starts
        # with a line's `f`: starts[0] is 0), one pass over the bytes.
        slashes = np.add.reduceat(data == 47, starts, dtype=np.int64) if len(starts) else np.zeros(0, np.int64)
        if per_corner is None:
            per_corner = int(slashes[1]) + 1  # the first corner's
        expected = np.full(len(starts), per_corner - 1, slashes.dtype)
        expected[np.cumsum(corners + 1) - (corners + 1)] = 0  # each line's `f`
        if per_corner > 3 or not np.array_equal(slashes, expected):
            return None
    values = parse_numbers(text.replace(b"f", b" ").replace(b"/", b" "), np.int64)
    total = int(corners.sum())
    if values is None or values.size != total * per_corner:
        return None  # (a token with an empty number has fewer: every token has per_corner exactly)
    corner_values = np.zeros((total, 3), np.int64)
    corner_values[:, :per_corner] = values.reshape(total, per_corner)
    if (corners == 3).all():  # triangles only (most files): no fans to cut
        return corner_values.reshape(-1, 3, 3), np.arange(line_count), per_corner
    fans = corners - 2
    polygon = np.repeat(np.arange(line_count), fans)
    first = (np.cumsum(corners) - corners)[polygon]  # each triangle's polygon's first corner
    k = np.arange(len(polygon)) - np.repeat(np.cumsum(fans) - fans, fans) + 1  # triangle (0, k, k + 1) of its fan
    return corner_values[np.stack([first, first + k, first + k + 1], axis=1)], polygon, per_corner


# Ear clipping is for real polygons. mapbox_earcut on a ring that passes through one point
# again and again (a face of repeated corners) took 0.9 s at 2,000 corners, 7.9 s at 4,000
# and 63 s at 8,000: such a face, and any face of more corners than this, keeps its fan.
EAR_CLIP_CORNERS = 1 << 16  # a 100,000-corner star took 4.7 s


def ear_clip_concave(corners: np.ndarray, polygon: np.ndarray, positions: np.ndarray) -> tuple[np.ndarray, int]:
    """Concave polygons triangulated again by ear clipping; the fan is kept for the rest.

    A fan from the first corner is right only when every fan triangle faces the polygon's
    own normal (its vector area, the sum of the fan's): then the corners lie in angular order
    around the first one. Otherwise (an L, a ring cut open by a slit, letters) the fan covers
    the concave notches, which f3d, Blender and assimp leave open. A ring that comes back
    more than twice to one point (a slit comes back once), or of more than EAR_CLIP_CORNERS
    corners, keeps its fan. Returns the triangles and how many faces kept their fans that
    way (kept_fans_note: one note for the file, not one per run of face lines)."""
    if len(corners) == 0 or triangles_only(polygon):
        return corners, 0
    backwards, normal_of = _backwards(corners[:, :, 0], polygon, positions)
    if not backwards.any():
        return corners, 0
    import mapbox_earcut

    pieces, start, kept_fans = [], 0, 0
    for bad in np.unique(polygon[backwards]).tolist():
        first, stop = np.searchsorted(polygon, [bad, bad + 1])
        fan = corners[first:stop]
        ring = np.concatenate([fan[:1, 0], fan[:, 1], fan[-1:, 2]])  # the polygon's corners in order
        normal = normal_of[bad]
        axes = [k for k in range(3) if k != int(np.argmax(np.abs(normal)))]
        points = positions[ring[:, 0]][:, axes]
        if len(ring) > EAR_CLIP_CORNERS or np.unique(points, axis=0, return_counts=True)[1].max() > 2:
            kept_fans += 1
            continue  # (its fan stays, with the corners around it)
        pieces.append(corners[start:first])
        indices = mapbox_earcut.triangulate_float64(points, np.array([len(ring)], np.uint32))
        triangles = ring[np.asarray(indices, np.int64).reshape(-1, 3)]
        tri_points = positions[triangles[:, :, 0]]
        facing = np.cross(tri_points[:, 1] - tri_points[:, 0], tri_points[:, 2] - tri_points[:, 0]) @ normal
        triangles[facing < 0] = triangles[facing < 0][:, ::-1]  # the file's winding, whatever the projection did
        pieces.append(triangles)
        start = stop
    pieces.append(corners[start:])
    return np.concatenate(pieces), kept_fans


def has_concave(vertices: np.ndarray, polygon: np.ndarray, positions: np.ndarray) -> bool:
    """Whether ear_clip_concave would cut some polygon again: `vertices`, the triangles' v (T, 3)."""
    return len(vertices) > 0 and not triangles_only(polygon) and bool(_backwards(vertices, polygon, positions)[0].any())


def _backwards(vertices: np.ndarray, polygon: np.ndarray, positions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each fan triangle facing against its polygon's normal (the vector area, the sum of
    the fan's), and those normals."""
    points = positions[vertices]
    areas = np.cross(points[:, 1] - points[:, 0], points[:, 2] - points[:, 0])
    count = int(polygon.max()) + 1
    normal_of = np.stack([np.bincount(polygon, areas[:, k], count) for k in range(3)], axis=1)
    return np.einsum("ij,ij->i", areas, normal_of[polygon]) < 0.0, normal_of


def kept_fans_note(path: str, count: int) -> str:
    """What to tell the user of `count` concave faces that ear_clip_concave left as their fans."""
    one = count == 1
    return (f"{path}: {count} concave {'face passes' if one else 'faces pass'} more than twice through one point or "
            f"{'has' if one else 'have'} over {EAR_CLIP_CORNERS} corners: drawn as {'its fan' if one else 'their fans'} "
            "from the first corner, not cut by ear clipping")


def triangles_only(polygon: np.ndarray) -> bool:
    """Every face a triangle: the polygon numbers of the triangles run 0, 1, ... one each."""
    return len(polygon) == 0 or len(polygon) == int(polygon[-1]) + 1


def resolve_positive(raw: np.ndarray, counts: np.ndarray) -> np.ndarray | None:
    """The common case without full-size masks: every given index positive and in range
    (an absent vt/vn column is all 0). None when anything else is there."""
    resolved = np.empty_like(raw)
    for column in range(3):
        values = raw[:, :, column]
        low, high = int(values.min()), int(values.max())
        if column > 0 and low == high == 0:
            resolved[:, :, column] = -1
        elif low > 0 and high <= counts[column]:
            np.subtract(values, 1, out=resolved[:, :, column])
        else:
            return None
    return resolved


def face_line(run: FaceRun, ordinal: int) -> int:
    return run.first_line + ordinal  # runs hold consecutive face lines only
