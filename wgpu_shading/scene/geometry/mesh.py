"""The Mesh type and vertex normals.

Vertex positions are stored in float32 *relative to* `Mesh.origin` (float64, the centre
of the bounding box). The GPU wants float32, and a mesh modelled 1e5 units from the
origin would lose its detail in float32 absolute coordinates; the origin is added back
in float64 on the CPU as part of the model matrix (see SceneObject.world_from_model).

Vertex normals come from the file when it has them, else they are the normalized sum
of the adjacent faces' unit normals (the seeds' definition), optionally after welding by
position and splitting at creases (docs/real-world-files.md, see crease_normals.py).

A mesh from a file may have several parts (OBJ `usemtl`, glTF primitives): each part is a
contiguous range of triangles with its own material, drawn with its own draw call.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from ...errors import MeshError
from .mesh_parts import PRIMITIVES, MeshPart, check_parts, default_parts, kept_for_lines_and_points, triangle_edges, valid_elements
from .crease_normals import check_split_count, crease_normals
from .face_normals import face_normals
from .solids import solid_orientation
from .vertex_normals import validated_normals, vertex_normals
from .vertex_arrays import bounds, finite_rows, relative_positions, unit_colors, unit_or_zero_normals

__all__ = ["MAX_VERTICES", "MAX_TRIANGLES", "Mesh", "check_counts", "MeshPart", "PRIMITIVES", "face_normals", "owned", "vertex_normals"]

if TYPE_CHECKING:  # pragma: no cover
    from ..material import Material

# Limits (docs/reliability.md). Counts: host and GPU memory (~100 bytes per triangle in
# all). Extent (the bounding box's diagonal, in model units): flat shading takes the cross
# product of two float32 edges on the GPU, whose squared length must stay below float32's
# 3.4e38; below MIN_EXTENT no camera can get close enough to see the mesh.
MAX_VERTICES = 1 << 25  # 33.5 million
MAX_TRIANGLES = 1 << 25
MIN_EXTENT = 1e-9
MAX_EXTENT = 1e9
MAX_ORIGIN = 1e15  # where the mesh sits (kept in float64)


def owned(array: np.ndarray) -> np.ndarray:
    """`array` as a read-only array no one else can write: itself when it is already
    read-only and owns its memory, else a read-only copy (the caller's array stays writable)."""
    array = np.asarray(array)
    if array.flags.writeable or not array.flags.owndata or not array.flags.c_contiguous:
        array = np.array(array, order="C", copy=True)
    array.setflags(write=False)
    return array


def _private(array: np.ndarray | None, *inputs: object) -> np.ndarray | None:
    """Mark an array computed here read-only (so Mesh keeps it without a copy), unless it
    may still share memory with one of the caller's `inputs` (then Mesh copies it)."""
    if array is None:
        return None
    if array.flags.owndata and not any(isinstance(i, np.ndarray) and np.may_share_memory(array, i) for i in inputs):
        array.setflags(write=False)
    return array



def check_counts(vertices: int, triangles: int, segments: int, name: str,
                 max_vertices: int = MAX_VERTICES, max_triangles: int = MAX_TRIANGLES) -> None:
    """The Mesh's size limits, one message: checked by Mesh.from_arrays, and by the file
    readers before they make normals (assets/mesh_pieces.py)."""
    if vertices > max_vertices or triangles > max_triangles or segments > max_triangles:
        raise MeshError(
            f"{name}: {vertices} vertices, {triangles} triangles and {segments} line segments; "
            f"at most {max_vertices} of each are supported"
        )

@dataclass(frozen=True, eq=False)
class Mesh:
    """An indexed mesh of triangles, lines and points (scene/geometry/mesh_parts.py), ready for upload.

    positions: (N, 3) float32, relative to `origin`
    normals:   (N, 3) float32, unit length (zero only where no normal can be defined); a
               point whose normal is zero is drawn in its colour, unlit (docs/primitives.md)
    indices:   (F, 3) uint32, counter-clockwise front faces; (0, 3) for a mesh without surfaces
    uvs:       (N, 2) float32 or None (v = 0 at the bottom of the image): texture coordinate set 0
    origin:    float64 offset added back to `positions`
    colors:    (N, 4) float32 vertex colors in [0, 1] or None (they multiply the material's
               ambient and diffuse, like GL_COLOR_MATERIAL with GL_AMBIENT_AND_DIFFUSE)
    tangents:  (N, 4) float32 or None: a file's tangents (glTF TANGENT: x, y, z and the
               handedness w, bitangent = cross(normal, tangent)·w); rows of zeros: none
    parts:     the ranges of triangles, line segments and points with their file materials;
               by default one part per kind present (a mesh of vertices alone: a point cloud)
    line_indices: (L, 2) uint32 or None: line segments between two vertices
    extra_uvs: (N, K, 2) float32 or None: texture coordinate sets 1..K (glTF TEXCOORD_n, each
               with its texture transform; `Texture.uv_set` says which set a texture reads)
    """

    positions: np.ndarray = field(repr=False)
    normals: np.ndarray = field(repr=False)
    indices: np.ndarray = field(repr=False)
    uvs: np.ndarray | None = field(default=None, repr=False)
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    name: str = ""
    colors: np.ndarray | None = field(default=None, repr=False)
    parts: tuple[MeshPart, ...] = field(default=(), repr=False)
    tangents: np.ndarray | None = field(default=None, repr=False)
    line_indices: np.ndarray | None = field(default=None, repr=False)
    extra_uvs: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        # A Mesh is a snapshot: renderers cache its upload by identity, so its arrays must
        # never change. The caller's arrays are copied (and left writable); arrays that are
        # read-only and own their memory (made by from_arrays or a loader) are kept as they are.
        for key in ("positions", "normals", "indices", "uvs", "colors", "tangents", "line_indices", "extra_uvs"):
            array = getattr(self, key)
            if array is not None:
                object.__setattr__(self, key, owned(array))
        if len(self.indices) == 0:
            object.__setattr__(self, "indices", owned(np.zeros((0, 3), np.uint32)))
        parts = tuple(self.parts) or default_parts(self.triangle_count, self.line_count, self.vertex_count, None, self.name)
        check_parts(parts, self.triangle_count, self.line_count, self.vertex_count, self.name)
        object.__setattr__(self, "parts", parts)

    @property
    def material(self) -> "Material | None":
        """The file's material when the whole mesh has one (None for several or none)."""
        materials = {id(part.material) for part in self.parts}
        return self.parts[0].material if len(materials) == 1 else None

    def __repr__(self) -> str:
        counts = [f"{self.vertex_count} vertices", f"{self.triangle_count} triangles"]
        counts += [f"{count} {kind}" for count, kind in ((self.line_count, "line segments"), (self.point_count, "points")) if count]
        return f"Mesh({self.name!r}, {', '.join(counts)})"

    def _repr_pretty_(self, printer, cycle: bool) -> None:
        """IPython's (and hypothesis's) pretty printer: the short repr, not every array."""
        printer.text(repr(self))

    @property
    def vertex_count(self) -> int:
        return len(self.positions)

    @property
    def triangle_count(self) -> int:
        return len(self.indices)

    @property
    def line_count(self) -> int:
        """Line segments."""
        return 0 if self.line_indices is None else len(self.line_indices)

    @property
    def point_count(self) -> int:
        return sum(part.count for part in self.parts if part.primitive == "points")

    @property
    def primitives(self) -> frozenset[str]:
        """The kinds of primitive the mesh draws ("triangles", "lines", "points")."""
        return frozenset(part.primitive for part in self.parts if part.count)

    @cached_property
    def _points_with_normals(self) -> frozenset[tuple[int, int]]:
        return frozenset((p.first, p.count) for p in self.parts
                         if p.primitive == "points" and self.normals[p.first : p.first + p.count].any())

    def has_point_normals(self, part: MeshPart) -> bool:
        """Whether some point of a point part has a normal (it is drawn as a lit disc); cached."""
        return (part.first, part.count) in self._points_with_normals

    @cached_property
    def edge_indices(self) -> np.ndarray:
        """(E, 2) uint32: every edge of the triangles once (what `--edges` draws); cached."""
        return owned(triangle_edges(self.indices))

    @property
    def nbytes(self) -> int:
        """Size of the mesh's own arrays in bytes."""
        arrays = (self.positions, self.normals, self.indices, self.uvs, self.colors, self.tangents, self.line_indices, self.extra_uvs)
        return sum(a.nbytes for a in arrays if a is not None)

    def part_vertices(self, part: MeshPart) -> np.ndarray:
        """The float32 positions a part draws (origin-relative), corners repeated."""
        if part.primitive == "points":
            return self.positions[part.first : part.first + part.count]
        elements = self.indices if part.primitive == "triangles" else self.line_indices
        return self.positions[elements[part.first : part.first + part.count].reshape(-1)]

    def part_centre(self, part: MeshPart) -> tuple[float, float, float]:
        """Centre of a part's bounding box in model space (float64)."""
        lower, upper = bounds(self.part_vertices(part))
        centre = (lower + upper) / 2.0 + self.origin
        return (float(centre[0]), float(centre[1]), float(centre[2]))

    def world_positions(self) -> np.ndarray:
        """Positions in model space as float64 (origin added back)."""
        return self.positions.astype(np.float64) + np.asarray(self.origin)

    @cached_property
    def relative_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """float64 (lower, upper) corners of the stored (origin-relative) positions; cached."""
        return bounds(self.positions)

    @cached_property
    def solid(self) -> int:
        """+1 if the mesh is a closed surface wound counter-clockwise seen from outside, −1
        if closed and inside out, 0 if open (scene/geometry/solids.py; cached: shadows ask per frame)."""
        return solid_orientation(self.positions, self.indices)

    @cached_property
    def exact_solid(self) -> int:
        """`solid` with only corners at identical positions counted as one vertex, and every
        piece on its own: +1 when the rasterizer, too, sees closed surfaces each wound
        counter-clockwise from outside (no crack along a seam, no piece inside out;
        render/gpu/clusters.py)."""
        return solid_orientation(self.positions, self.indices, weld_tolerance=0.0, each_piece=True)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """float64 (lower, upper) corners of the bounding box in model space (from the cached
        relative_bounds: a dataset job asks for them every view, 0.5 ms a 35K-vertex mesh)."""
        lower, upper = self.relative_bounds
        return lower + self.origin, upper + self.origin

    @classmethod
    def from_arrays(
        cls,
        positions: np.ndarray,
        indices: np.ndarray | None = None,
        normals: np.ndarray | None = None,
        uvs: np.ndarray | None = None,
        *,
        name: str = "mesh",
        material: "Material | None" = None,
        colors: np.ndarray | None = None,
        parts: tuple[MeshPart, ...] = (),
        crease_angle: float | None = None,
        flat_faces: np.ndarray | None = None,
        tangents: np.ndarray | None = None,
        lines: np.ndarray | None = None,
        extra_uvs: np.ndarray | None = None,
    ) -> "Mesh":
        """Validate and convert user arrays; computes normals when none are given.

        indices (F, 3) are triangles; lines (L, 2) segments; a mesh with neither is a point
        cloud (every vertex a point), and `parts` may name ranges of each kind (MeshPart).
        Without normals: crease_angle=None gives the seeds' normalized sum per given vertex;
        a number (degrees) welds vertices by position and splits at edges sharper than it
        (normals.crease_normals; vertices may be split, so the vertex count can change).
        Vertices of no triangle (points, lines) keep a zero normal: unlit.
        flat_faces (F,) bool marks faces that are always flat (OBJ `s off`).
        tangents (N, 4): kept only with the caller's normals (welding drops them).
        extra_uvs (N, K, 2): texture coordinate sets 1..K (Texture.uv_set)."""
        with np.errstate(all="ignore"):  # every bad value is reported as a MeshError instead
            return cls._from_arrays(
                positions, indices, normals, uvs, name=name, material=material, colors=colors,
                parts=parts, crease_angle=crease_angle, flat_faces=flat_faces, tangents=tangents,
                lines=lines, extra_uvs=extra_uvs,
            )

    @classmethod
    def _from_arrays(
        cls, positions, indices, normals, uvs, *, name: str, material, colors, parts, crease_angle, flat_faces, tangents=None,
        lines=None, extra_uvs=None,
    ) -> "Mesh":
        caller_positions, caller_uvs, caller_colors = positions, uvs, colors
        try:
            # float32 stays float32 (a loaded file's, half the memory); each use converts
            # what it reads to float64 exactly, so the results are those of float64 input.
            positions = np.asarray(positions)
            if positions.dtype not in (np.float32, np.float64):
                positions = positions.astype(np.float64)
        except (TypeError, ValueError) as error:
            raise MeshError(f"{name}: positions must be numbers ({error})") from None
        if positions.ndim != 2 or positions.shape[1] != 3:
            raise MeshError(f"{name}: positions must have shape (N, 3), got {positions.shape}")
        faces = valid_elements(np.zeros((0, 3)) if indices is None else indices, 3, len(positions), "indices", "(F, 3) (triangles)", name)
        segments = None if lines is None else valid_elements(lines, 2, len(positions), "lines", "(L, 2) (segments)", name)
        line_count = 0 if segments is None else len(segments)
        point_parts = [part for part in parts if part.primitive == "points"]
        if len(positions) == 0 or not (len(faces) or line_count or point_parts or not parts):
            raise MeshError(f"{name}: the mesh is empty ({len(positions)} vertices, {len(faces)} triangles)")
        check_counts(len(positions), len(faces), line_count, name)
        finite = finite_rows(positions)
        if finite is not None:
            bad = ~finite
            first = int(np.flatnonzero(bad)[0])
            count = int(bad.sum())
            raise MeshError(
                f"{name}: {count} {'vertex has' if count == 1 else 'vertices have'} NaN or infinite coordinates "
                f"(first: vertex {first} = {positions[first].tolist()})"
            )
        parts = tuple(parts) or default_parts(len(faces), line_count, len(positions), material, name)
        check_parts(parts, len(faces), line_count, len(positions), name)
        if colors is not None:
            colors = np.asarray(colors)
            if colors.ndim != 2 or len(colors) != len(positions) or colors.shape[1] not in (3, 4) or colors.dtype.kind not in "iuf":
                raise MeshError(f"{name}: colors must be numbers of shape ({len(positions)}, 3 or 4), got {colors.shape} {colors.dtype}")
            colors = unit_colors(colors)
        if extra_uvs is not None:
            extra_uvs = np.asarray(extra_uvs, dtype=np.float64)
            if extra_uvs.ndim != 3 or extra_uvs.shape[0] != len(positions) or extra_uvs.shape[2] != 2 or not extra_uvs.shape[1]:
                raise MeshError(f"{name}: extra_uvs must have shape ({len(positions)}, K, 2), got {extra_uvs.shape}")
            if not np.isfinite(extra_uvs).all():
                raise MeshError(f"{name}: extra_uvs contain NaN or infinite values")
        if normals is None and crease_angle is not None and len(faces):
            source, faces, unit_normals = crease_normals(positions, faces, crease_angle, flat_faces, MAX_VERTICES, name)
            if source is not None:
                check_split_count(len(source), MAX_VERTICES, name)  # (crease_normals refuses what it can see sooner)
                source, segments, parts = kept_for_lines_and_points(source, segments, parts)
                unit_normals = np.concatenate([unit_normals, np.zeros((len(source) - len(unit_normals), 3), np.float32)])
                positions = positions[source]
                uvs = None if uvs is None else np.asarray(uvs)[source]
                colors = None if colors is None else colors[source]
                extra_uvs = None if extra_uvs is None else extra_uvs[source]
        elif not len(faces):  # lines and points: the given normals or none (unlit)
            unit_normals = np.zeros(positions.shape, np.float32) if normals is None else unit_or_zero_normals(_rows(normals, positions, name))
        elif normals is None:
            unit_normals = vertex_normals(positions, faces)
        else:
            unit_normals = validated_normals(np.asarray(normals), positions, faces, name)
        if normals is None:
            tangents = None  # tangents belong to the file's normals
        if tangents is not None:
            tangents = np.asarray(tangents, dtype=np.float64)
            if tangents.shape != (len(positions), 4):
                raise MeshError(f"{name}: tangents must have shape ({len(positions)}, 4), got {tangents.shape}")
            tangents = np.ascontiguousarray(np.nan_to_num(tangents, nan=0.0, posinf=0.0, neginf=0.0), dtype=np.float32)
        if uvs is not None:
            uvs = np.asarray(uvs)  # (float32 uvs are checked as they are: a float64 copy was 16 bytes a vertex)
            if uvs.dtype.kind not in "fiu":
                uvs = uvs.astype(np.float64)
            if uvs.shape != (len(positions), 2):
                raise MeshError(f"{name}: uvs must have shape ({len(positions)}, 2), got {uvs.shape}")
            if not np.isfinite(uvs).all():
                raise MeshError(f"{name}: uvs contain NaN or infinite values")
            uvs = np.ascontiguousarray(uvs, dtype=np.float32)
            if not np.isfinite(uvs).all():  # (finite in float64, infinite as the float32 the GPU reads)
                raise MeshError(f"{name}: uvs beyond float32's range (|value| up to {float(np.finfo(np.float32).max):.3g})")
        lower, upper = bounds(positions)
        extent = float(np.linalg.norm(upper - lower))
        # A point cloud whose points all lie at one place (a single point) has no extent and
        # needs none: a point is drawn so many pixels across wherever the camera is.
        single_place = extent == 0.0 and not len(faces) and not line_count
        if not MIN_EXTENT <= extent <= MAX_EXTENT and not single_place:
            raise MeshError(
                f"{name}: the mesh is {extent:.3g} units across; between {MIN_EXTENT:g} and {MAX_EXTENT:g} are supported "
                "(float32 on the GPU): scale the file's coordinates, then use the object's scale"
            )
        if float(np.abs(lower).max()) > MAX_ORIGIN or float(np.abs(upper).max()) > MAX_ORIGIN:
            raise MeshError(f"{name}: coordinates must be within ±{MAX_ORIGIN:g}")
        if len(faces):
            _check_some_area(positions, faces, extent, name)
        origin = (lower + upper) / 2.0
        if np.all(np.abs(origin) <= 1e-3 * max(float((upper - lower).max()), 1e-30)):
            origin = np.zeros(3)  # keep meshes that are already centred bit-exact
        given = (caller_positions, indices, normals, caller_uvs, caller_colors, lines, extra_uvs)
        return cls(
            positions=_private(relative_positions(positions, origin), *given),
            normals=_private(np.ascontiguousarray(unit_normals, dtype=np.float32), *given),
            indices=_private(faces, *given),
            uvs=_private(uvs, *given),
            origin=tuple(float(v) for v in origin),
            name=name,
            colors=_private(colors, *given),
            parts=parts,
            tangents=_private(tangents, *given),
            line_indices=_private(segments, *given),
            extra_uvs=None if extra_uvs is None else _private(np.ascontiguousarray(extra_uvs, dtype=np.float32), *given),
        )


def _rows(normals, positions: np.ndarray, name: str) -> np.ndarray:
    normals = np.asarray(normals)
    if normals.shape != positions.shape or normals.dtype.kind not in "iuf":
        raise MeshError(f"{name}: normals must be numbers of shape {positions.shape}, got {normals.shape}")
    return normals


def _check_some_area(positions: np.ndarray, faces: np.ndarray, extent: float, name: str) -> None:
    """A mesh whose every triangle is degenerate (collinear or repeated corners) rasterizes
    no pixel: a blank image with exit 0 unless refused here. Twice the area of the largest
    triangle, relative to the mesh's size squared, below float32's resolution counts as none."""
    faces = np.asarray(faces)
    threshold = 1e-12 * extent * extent
    # Chunks growing from 256 triangles to 65536: an ordinary mesh stops at the first (the
    # whole first 64K chunk was 7 ms of the 70K-triangle bunny's load), a degenerate one
    # still takes bounded temporaries.
    start, size = 0, 256
    while start < len(faces):
        corners = positions[faces[start : start + size]].astype(np.float64)
        start, size = start + size, min(size * 16, 65536)
        doubled_areas = np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
        if float(doubled_areas.max(initial=0.0)) > threshold:
            return
    raise MeshError(
        f"{name}: none of its {len(faces)} triangles has any area (their corners are collinear or repeated); "
        "nothing would be drawn"
    )
