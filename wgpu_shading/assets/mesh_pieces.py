"""The vertex sets a mesh file is read into ("pieces": an OBJ, a PLY, a glTF primitive
instance, each with its parts and materials) and their assembly into one Mesh, with
normals as docs/real-world-files.md says: the file's normals win; glTF primitives
without NORMAL are flat; otherwise vertices are welded by position and split at the crease
angle (scene/geometry/crease_normals.py)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from ..errors import MeshError
from ..scene.freed_memory import return_freed_memory
from ..scene.geometry.mesh import MAX_TRIANGLES, MAX_VERTICES, Mesh, MeshPart, check_counts, face_normals
from ..scene.geometry.crease_normals import crease_normals
from ..scene.geometry.vertex_arrays import finite_rows

# A mesh of more vertices than this hands its load's freed temporaries back once assembled
# (scene/freed_memory.py): the gathers and conversions of its arrays into a Mesh left
# ~50-90 MB of a 10M-triangle OBJ's on glibc's heap, under the render's peak, which comes next.
TRIMMED_VERTICES = 1 << 20


@dataclass
class MeshPiece:
    """One vertex set of a file: an OBJ, a glTF primitive instance, a PLY.

    `primitive` says what `faces` holds: "triangles" (f, 3), "lines" (f, 2) segments, or
    "points" (every vertex a point; `faces` unused). Parts count faces, segments or vertices."""

    positions: np.ndarray
    faces: np.ndarray | None
    normals: np.ndarray | None = None
    uvs: np.ndarray | None = None
    colors: np.ndarray | None = None  # (n, 4) float in [0, 1]
    flat: np.ndarray | None = None  # (f,) bool: faces that are always flat
    all_flat: bool = False
    parts: list = field(default_factory=list)  # (first face, count, material, name)
    tangents: np.ndarray | None = None  # (n, 4) glTF TANGENT, only with the file's normals
    primitive: str = "triangles"
    extra_uvs: np.ndarray | None = None  # (n, k, 2): texture coordinate sets 1..k (Texture.uv_set)
    # (f, 3 or 4): each triangle's colour (with_face_colors), every corner its own vertex once
    # the normals are made (assemble)
    face_colors: np.ndarray | None = None

    @property
    def element_count(self) -> int:
        return len(self.positions) if self.primitive == "points" else len(self.faces)


def point_piece(positions, normals=None, colors=None, material=None, name: str = "") -> MeshPiece:
    """A point cloud: every vertex a point, in one part."""
    return MeshPiece(positions, None, normals, None, colors, parts=[(0, len(positions), material, name)], primitive="points")


def _no_lights() -> list:
    return []


def _no_camera(index: int) -> None:
    return None  # OBJ, PLY, STL and OFF hold no cameras


@dataclass
class MeshFile:
    """What a reader makes of a mesh file: every reader returns one (assets/meshes.py lists
    the readers by suffix).

    pieces: the file's vertex sets; notes: what the user should be told once the file has
    been read whole (said by the loader, once each); lights: the file's own lights, each
    with its node's matrix in the file's space (glTF KHR_lights_punctual), read when asked
    from what was parsed for the pieces (a file is parsed once; a broken light table fails
    only a caller who wants the lights); camera(index): the file's camera `index` as
    gltf/cameras.py gives it, None for formats without cameras. Lights and cameras hang on
    the nodes as the pieces were posed (an animation time)."""

    pieces: list[MeshPiece]
    notes: list[str] = field(default_factory=list)
    lights: Callable[[], list] = _no_lights
    camera: Callable[[int], object] = _no_camera
    # The Mesh follows from the file's bytes alone (no material library, image or other file
    # read beside it) and everything the user is told is in `notes`: the mesh cache may keep
    # it (mesh_cache.py). A reader says so; unsaid, it is not kept.
    self_contained: bool = False


def with_face_colors(piece: MeshPiece, face_colors: np.ndarray) -> MeshPiece:
    """One colour per face, unblended: every corner its own vertex (MeshLab; averaging
    into vertices would blur the faces' colours). The corners are split once the normals
    are made (assemble), which the crease analysis then makes for the file's vertices, not
    for three times as many corners: the same normals (every corner welded back to its
    position's vertex, in the same order): a 10M-triangle face-coloured PLY loads in 8 s
    instead of 23."""
    return replace(piece, face_colors=face_colors)


def _split_face_colors(piece: MeshPiece, name: str) -> MeshPiece:
    """A piece with face colours as every corner its own vertex with its face's colour."""
    if piece.face_colors is None:
        return piece
    _check_corners_apart(piece, name, "coloured")
    return _corners_apart(piece, colors=np.repeat(piece.face_colors, 3, axis=0), face_colors=None)


def _check_corners_apart(piece: MeshPiece, name: str, what: str) -> None:
    """A MeshError when every corner its own vertex makes more vertices than supported
    (said before the corners' copies are made)."""
    if 3 * len(piece.faces) > MAX_VERTICES:
        raise MeshError(f"{name}: {3 * len(piece.faces)} vertices once every {what} face's corners are split; at most {MAX_VERTICES} are supported")


def _corners_apart(piece: MeshPiece, **given) -> MeshPiece:
    """The piece with every corner its own vertex, in face order: each per-vertex array
    gathered by corner, except the fields `given` here (normals or colours per corner; face
    colours, which stay a face's until assemble splits them)."""
    corners = piece.faces.reshape(-1)
    arrays = {name: getattr(piece, name) for name in ("normals", "uvs", "colors", "tangents", "extra_uvs")}
    gathered = {name: None if array is None else array[corners] for name, array in arrays.items() if name not in given}
    return replace(piece, positions=piece.positions[corners], faces=numbered_corners(len(piece.faces)), **gathered, **given)


def _piece_normals(piece: MeshPiece, crease_angle: float, name: str) -> MeshPiece:
    """The piece with normals: the file's, flat, or welded and creased. Lines and points
    without normals get zero normals (drawn unlit: docs/primitives.md)."""
    if piece.normals is not None:
        return piece
    if piece.primitive != "triangles":
        return replace(piece, normals=np.zeros((len(piece.positions), 3), np.float32))
    if piece.all_flat:  # every corner its own vertex, with its face's normal
        _check_corners_apart(piece, name, "flat")
        unit, _ = face_normals(piece.positions, piece.faces)
        return _corners_apart(piece, normals=np.repeat(unit, 3, axis=0))
    source, faces, normals = crease_normals(piece.positions, piece.faces, crease_angle, piece.flat, MAX_VERTICES, name)
    normals.setflags(write=False)  # unit float32, ours: the Mesh keeps them without a copy (mesh.py, owned)
    if source is None:
        return replace(piece, normals=normals)
    return replace(
        piece,
        positions=piece.positions[source],
        faces=faces,
        normals=normals,
        uvs=None if piece.uvs is None else piece.uvs[source],
        colors=None if piece.colors is None else piece.colors[source],
        extra_uvs=None if piece.extra_uvs is None else piece.extra_uvs[source],
    )


def polygon_fans(polygons: np.ndarray) -> np.ndarray:
    """(n, k) polygons of one size as (n·(k − 2), 3) triangles: each polygon's fan from its
    first corner, (a, k, k + 1), one polygon after the other (the OFF and PLY readers')."""
    fan = np.arange(1, polygons.shape[1] - 1)
    first = np.broadcast_to(polygons[:, :1], (len(polygons), len(fan)))
    return np.stack([first, polygons[:, fan], polygons[:, fan + 1]], axis=2).reshape(-1, 3)


def numbered_corners(count: int) -> np.ndarray:
    """(count, 3) triangles 0 1 2, 3 4 5, ...: uint32, read-only and owning its memory,
    which a Mesh keeps as its indices without a copy (scene/geometry/mesh.py, owned)."""
    faces = np.empty((count, 3), np.uint32)
    faces.reshape(-1)[:] = np.arange(3 * count, dtype=np.uint32)
    faces.setflags(write=False)
    return faces


def _check_piece(piece: MeshPiece, name: str) -> None:
    """What normals and welding index with must be valid first (trimesh reads PLY, STL and
    OFF faces without checking them, process=False): finite positions, indices in range."""
    width = {"triangles": 3, "lines": 2}.get(piece.primitive)
    if width and (piece.faces.ndim != 2 or piece.faces.shape[1] != width):
        raise MeshError(f"{name}: {piece.primitive} must have {width} vertices each, got an array of shape {piece.faces.shape}")
    finite = finite_rows(piece.positions)
    if finite is not None:
        bad = int(np.flatnonzero(~finite)[0])
        raise MeshError(f"{name}: vertex {bad} has a NaN or infinite coordinate: {piece.positions[bad].tolist()}")
    if not width:
        return
    low, high = int(piece.faces.min()), int(piece.faces.max())
    if low < 0 or high >= len(piece.positions):
        culprit = low if low < 0 else high
        what = "a face" if width == 3 else "a line"
        raise MeshError(
            f"{name}: {what} refers to vertex {culprit}, but the file has {len(piece.positions)} vertices "
            f"(valid: 0..{len(piece.positions) - 1})"
        )


def _check_counts(pieces: list[MeshPiece], name: str) -> None:
    """The Mesh's own limits, before the normals: a file of few polygons of many corners
    (an OFF, a PLY through trimesh) gave triangles past the limit that were all welded and
    creased before the Mesh refused them."""
    count = {kind: sum(len(piece.faces) for piece in pieces if piece.primitive == kind) for kind in ("triangles", "lines")}
    check_counts(sum(len(piece.positions) for piece in pieces), count["triangles"], count["lines"], name, MAX_VERTICES, MAX_TRIANGLES)


def assemble(pieces: list[MeshPiece], name: str, crease_angle: float) -> Mesh:
    """The pieces as one Mesh: each with its normals, then joined, parts in order (the
    triangles, segments and points of each piece numbered after the earlier pieces')."""
    for piece in pieces:
        _check_piece(piece, name)
    _check_counts(pieces, name)
    pieces = [_split_face_colors(_piece_normals(piece, crease_angle, name), name) for piece in pieces]
    any_uvs = any(p.uvs is not None for p in pieces)
    any_colors = any(p.colors is not None for p in pieces)
    any_tangents = any(p.tangents is not None for p in pieces)
    uv_sets = max((p.extra_uvs.shape[1] for p in pieces if p.extra_uvs is not None), default=0)
    positions, faces, lines, normals, uvs, colors, tangents, extra_uvs, parts = [], [], [], [], [], [], [], [], []
    vertex_offset = 0
    offsets = {"triangles": 0, "lines": 0, "points": 0}
    for piece in pieces:
        count = len(piece.positions)
        offsets["points"] = vertex_offset
        positions.append(piece.positions)
        if piece.primitive != "points":  # (one piece: no copy)
            (faces if piece.primitive == "triangles" else lines).append(piece.faces + vertex_offset if vertex_offset else piece.faces)
        normals.append(piece.normals)
        if any_uvs:
            uvs.append(piece.uvs if piece.uvs is not None else np.zeros((count, 2)))
        if any_colors:
            colors.append(piece.colors if piece.colors is not None else np.ones((count, 4)))
        if any_tangents:  # zeros: no tangent, the derivative frame
            tangents.append(piece.tangents if piece.tangents is not None else np.zeros((count, 4)))
        if uv_sets:  # sets a piece lacks are zeros (its materials never read them)
            own = np.zeros((count, 0, 2)) if piece.extra_uvs is None else piece.extra_uvs
            extra_uvs.append(np.concatenate([own, np.zeros((count, uv_sets - own.shape[1], 2))], axis=1))
        for first, length, material, part_name in piece.parts:
            if material is not None and material.texture is not None and piece.uvs is None:
                warnings.warn(f"{name}: part {part_name!r} has a texture but no texture coordinates; drawn untextured", stacklevel=3)
                material = replace(material, texture=None)
            parts.append(MeshPart(offsets[piece.primitive] + first, length, material, part_name, piece.primitive))
        vertex_offset += count
        if piece.primitive != "points":
            offsets[piece.primitive] += len(piece.faces)

    def joined(arrays: list) -> np.ndarray | None:  # one piece (a PLY, an STL): no copy
        return None if not arrays else arrays[0] if len(arrays) == 1 else np.concatenate(arrays)

    mesh = Mesh.from_arrays(
        joined(positions),
        joined(faces),
        normals=joined(normals),
        uvs=joined(uvs),
        colors=joined(colors),
        tangents=joined(tangents),
        parts=tuple(parts),
        name=name,
        lines=joined(lines),
        extra_uvs=joined(extra_uvs),
    )
    if vertex_offset > TRIMMED_VERTICES:
        return_freed_memory()
    return mesh
