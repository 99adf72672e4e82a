"""The Mesh type and vertex normals.

Vertex positions are stored in float32 *relative to* `Mesh.origin` (float64, the centre
of the bounding box). The GPU wants float32, and a mesh modelled 1e5 units from the
origin would lose its detail in float32 absolute coordinates; the origin is added back
in float64 on the CPU as part of the model matrix (see SceneObject.world_from_model).

Vertex normals come from the file when it has them, else they are the normalized sum
of the adjacent faces' unit normals (the seeds' definition), optionally after welding by
position and splitting at creases (docs/real-world-files.md, see normals.py).

A mesh from a file may have several parts (OBJ `usemtl`, glTF primitives): each part is a
contiguous range of triangles with its own material, drawn with its own draw call.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from ..errors import MeshError
from .normals import crease_normals, face_normals
from .solids import solid_orientation

if TYPE_CHECKING:  # pragma: no cover
    from .material import Material

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


@dataclass(frozen=True)
class MeshPart:
    """Triangles first .. first + count - 1 of a mesh, with the material the file gave them
    (None: the file said nothing; the object's or OpenGL's default material is used)."""

    first: int
    count: int
    material: "Material | None" = None
    name: str = ""


@dataclass(frozen=True, eq=False)
class Mesh:
    """An indexed triangle mesh, ready for upload.

    positions: (N, 3) float32, relative to `origin`
    normals:   (N, 3) float32, unit length (zero only where no normal can be defined)
    indices:   (F, 3) uint32, counter-clockwise front faces
    uvs:       (N, 2) float32 or None (v = 0 at the bottom of the image)
    origin:    float64 offset added back to `positions`
    colors:    (N, 4) float32 vertex colors in [0, 1] or None (they multiply the material's
               ambient and diffuse, like GL_COLOR_MATERIAL with GL_AMBIENT_AND_DIFFUSE)
    tangents:  (N, 4) float32 or None: a file's tangents (glTF TANGENT: x, y, z and the
               handedness w, bitangent = cross(normal, tangent)·w); rows of zeros: none
    parts:     the triangle ranges and their file materials; one part covering every
               triangle when the file has one material (or none)
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

    def __post_init__(self) -> None:
        # A Mesh is a snapshot: renderers cache its upload by identity, so its arrays must
        # never change. The caller's arrays are copied (and left writable); arrays that are
        # read-only and own their memory (made by from_arrays or a loader) are kept as they are.
        for key in ("positions", "normals", "indices", "uvs", "colors", "tangents"):
            array = getattr(self, key)
            if array is not None:
                object.__setattr__(self, key, owned(array))
        parts = tuple(self.parts) or (MeshPart(0, len(self.indices)),)
        if sum(part.count for part in parts) != len(self.indices):
            raise MeshError(f"{self.name}: parts cover {sum(p.count for p in parts)} of {len(self.indices)} triangles")
        object.__setattr__(self, "parts", parts)

    @property
    def material(self) -> "Material | None":
        """The file's material when the whole mesh has one (None for several or none)."""
        materials = {id(part.material) for part in self.parts}
        return self.parts[0].material if len(materials) == 1 else None

    def __repr__(self) -> str:
        return f"Mesh({self.name!r}, {self.vertex_count} vertices, {self.triangle_count} triangles)"

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
    def nbytes(self) -> int:
        """Size of the mesh's own arrays in bytes."""
        arrays = (self.positions, self.normals, self.indices, self.uvs, self.colors, self.tangents)
        return sum(a.nbytes for a in arrays if a is not None)

    def part_centre(self, part: MeshPart) -> tuple[float, float, float]:
        """Centre of a part's bounding box in model space (float64)."""
        corners = self.positions[self.indices[part.first : part.first + part.count].reshape(-1)]
        centre = (corners.min(axis=0).astype(np.float64) + corners.max(axis=0)) / 2.0 + self.origin
        return (float(centre[0]), float(centre[1]), float(centre[2]))

    def world_positions(self) -> np.ndarray:
        """Positions in model space as float64 (origin added back)."""
        return self.positions.astype(np.float64) + np.asarray(self.origin)

    @cached_property
    def relative_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """float64 (lower, upper) corners of the stored (origin-relative) positions; cached."""
        return self.positions.min(axis=0).astype(np.float64), self.positions.max(axis=0).astype(np.float64)

    @cached_property
    def solid(self) -> int:
        """+1 if the mesh is a closed surface wound counter-clockwise seen from outside, −1
        if closed and inside out, 0 if open (scene/solids.py; cached: shadows ask per frame)."""
        return solid_orientation(self.positions, self.indices)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """float64 (lower, upper) corners of the bounding box in model space (from the cached
        relative_bounds: a dataset job asks for them every view, 0.5 ms a 35K-vertex mesh)."""
        lower, upper = self.relative_bounds
        return lower + self.origin, upper + self.origin

    @classmethod
    def from_arrays(
        cls,
        positions: np.ndarray,
        indices: np.ndarray,
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
    ) -> "Mesh":
        """Validate and convert user arrays; computes normals when none are given.

        Without normals: crease_angle=None gives the seeds' normalized sum per given vertex;
        a number (degrees) welds vertices by position and splits at edges sharper than it
        (normals.crease_normals; vertices may be split, so the vertex count can change).
        flat_faces (F,) bool marks faces that are always flat (OBJ `s off`).
        tangents (N, 4): kept only with the caller's normals (welding drops them)."""
        with np.errstate(all="ignore"):  # every bad value is reported as a MeshError instead
            return cls._from_arrays(
                positions, indices, normals, uvs, name=name, material=material, colors=colors,
                parts=parts, crease_angle=crease_angle, flat_faces=flat_faces, tangents=tangents,
            )

    @classmethod
    def _from_arrays(
        cls, positions, indices, normals, uvs, *, name: str, material, colors, parts, crease_angle, flat_faces, tangents=None
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
        faces = np.asarray(indices)
        if positions.ndim != 2 or positions.shape[1] != 3:
            raise MeshError(f"{name}: positions must have shape (N, 3), got {positions.shape}")
        if faces.ndim == 1 and faces.size % 3 == 0:
            faces = faces.reshape(-1, 3)
        if faces.ndim != 2 or faces.shape[1] != 3:
            raise MeshError(f"{name}: indices must have shape (F, 3) (triangles), got {faces.shape}")
        if len(positions) == 0 or len(faces) == 0:
            raise MeshError(f"{name}: the mesh is empty ({len(positions)} vertices, {len(faces)} triangles)")
        if len(positions) > MAX_VERTICES or len(faces) > MAX_TRIANGLES:
            raise MeshError(
                f"{name}: {len(positions)} vertices and {len(faces)} triangles; at most {MAX_VERTICES} of each are supported"
            )
        bad = ~np.isfinite(positions).all(axis=1)
        if bad.any():
            first = int(np.flatnonzero(bad)[0])
            count = int(bad.sum())
            raise MeshError(
                f"{name}: {count} {'vertex has' if count == 1 else 'vertices have'} NaN or infinite coordinates "
                f"(first: vertex {first} = {positions[first].tolist()})"
            )
        if faces.dtype.kind not in "iu":
            if faces.dtype.kind == "f" and np.all(np.isfinite(faces)) and np.all(faces == np.round(faces)):
                faces = faces.astype(np.int64)
            else:
                raise MeshError(f"{name}: indices must be integers, got dtype {faces.dtype}")
        low, high = int(faces.min()), int(faces.max())
        if low < 0 or high >= len(positions):
            culprit = low if low < 0 else high
            raise MeshError(
                f"{name}: index {culprit} is out of range; the mesh has {len(positions)} vertices (valid: 0..{len(positions) - 1})"
            )
        faces = np.ascontiguousarray(faces, dtype=np.uint32)
        if colors is not None:
            colors = np.asarray(colors)
            if colors.dtype.kind in "iu":
                colors = colors.astype(np.float32) / 255.0
            if colors.ndim != 2 or len(colors) != len(positions) or colors.shape[1] not in (3, 4):
                raise MeshError(f"{name}: colors must have shape ({len(positions)}, 3 or 4), got {colors.shape}")
            if colors.shape[1] == 3:
                colors = np.concatenate([colors, np.ones((len(colors), 1))], axis=1)
            colors = np.ascontiguousarray(np.clip(np.nan_to_num(colors, nan=1.0), 0.0, 1.0), dtype=np.float32)
        if normals is None and crease_angle is not None:
            source, faces, unit_normals = crease_normals(positions, faces, crease_angle, flat_faces)
            if source is not None:
                positions = positions[source]
                uvs = None if uvs is None else np.asarray(uvs)[source]
                colors = None if colors is None else colors[source]
        elif normals is None:
            unit_normals = vertex_normals(positions, faces)
        else:
            unit_normals = _validated_normals(np.asarray(normals, dtype=np.float64), positions, faces, name)
        if normals is None:
            tangents = None  # tangents belong to the file's normals
        if tangents is not None:
            tangents = np.asarray(tangents, dtype=np.float64)
            if tangents.shape != (len(positions), 4):
                raise MeshError(f"{name}: tangents must have shape ({len(positions)}, 4), got {tangents.shape}")
            tangents = np.ascontiguousarray(np.nan_to_num(tangents, nan=0.0, posinf=0.0, neginf=0.0), dtype=np.float32)
        if uvs is not None:
            uvs = np.asarray(uvs, dtype=np.float64)
            if uvs.shape != (len(positions), 2):
                raise MeshError(f"{name}: uvs must have shape ({len(positions)}, 2), got {uvs.shape}")
            if not np.isfinite(uvs).all():
                raise MeshError(f"{name}: uvs contain NaN or infinite values")
            uvs = np.ascontiguousarray(uvs, dtype=np.float32)
        lower, upper = positions.min(axis=0).astype(np.float64), positions.max(axis=0).astype(np.float64)
        extent = float(np.linalg.norm(upper - lower))
        if not MIN_EXTENT <= extent <= MAX_EXTENT:
            raise MeshError(
                f"{name}: the mesh is {extent:.3g} units across; between {MIN_EXTENT:g} and {MAX_EXTENT:g} are supported "
                "(float32 on the GPU): scale the file's coordinates, then use the object's scale"
            )
        if float(np.abs(lower).max()) > MAX_ORIGIN or float(np.abs(upper).max()) > MAX_ORIGIN:
            raise MeshError(f"{name}: coordinates must be within ±{MAX_ORIGIN:g}")
        _check_some_area(positions, faces, extent, name)
        origin = (lower + upper) / 2.0
        if np.all(np.abs(origin) <= 1e-3 * max(float((upper - lower).max()), 1e-30)):
            origin = np.zeros(3)  # keep meshes that are already centred bit-exact
        given = (caller_positions, indices, normals, caller_uvs, caller_colors)
        return cls(
            positions=_private(_relative(positions, origin), *given),
            normals=_private(np.ascontiguousarray(unit_normals, dtype=np.float32), *given),
            indices=_private(faces, *given),
            uvs=_private(uvs, *given),
            origin=tuple(float(v) for v in origin),
            name=name,
            colors=_private(colors, *given),
            parts=tuple(parts) or (MeshPart(0, len(faces), material, name),),
            tangents=_private(tangents, *given),
        )


# --------------------------------------------------------------------------- normals


def vertex_normals(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Normalized sum of the unit normals of the faces around each vertex (the seeds' rule, docs/conventions.md#vertex-normals).

    Zero-area faces contribute nothing. Where the sum cancels (a vertex shared by a
    thin double-sided sheet, say), the normal of the largest adjacent face is used
    instead, so every vertex that touches a real face gets a unit normal. Vertices
    that touch no face with area keep a zero normal; the shaders then fall back to
    the geometric normal.
    """
    positions = np.asarray(positions, dtype=np.float64)
    unit_faces, areas = face_normals(positions, faces)
    count = len(positions)
    flat_vertices = faces.reshape(-1)
    summed = np.stack(
        [np.bincount(flat_vertices, weights=np.repeat(unit_faces[:, k], 3), minlength=count) for k in range(3)],
        axis=1,
    )
    length = np.linalg.norm(summed, axis=1)
    adjacent = np.bincount(flat_vertices, weights=np.repeat((areas > 0).astype(float), 3), minlength=count)
    # A sum of k unit vectors that is shorter than 1e-6·k has cancelled: its direction is noise.
    cancelled = (length <= 1e-6 * np.maximum(adjacent, 1.0)) & (adjacent > 0)
    result = np.zeros_like(summed)
    good = length > 0
    good &= ~cancelled
    result[good] = summed[good] / length[good, None]
    if cancelled.any():
        # The largest adjacent face wins: sort faces by area and let larger ones overwrite.
        order = np.argsort(areas)
        corner_vertices = faces[order].reshape(-1)
        corner_normals = np.repeat(unit_faces[order], 3, axis=0)
        corner_areas = np.repeat(areas[order], 3)
        keep = cancelled[corner_vertices] & (corner_areas > 0)
        result[corner_vertices[keep]] = corner_normals[keep]
    return result


def _validated_normals(normals: np.ndarray, positions: np.ndarray, faces: np.ndarray, name: str) -> np.ndarray:
    if normals.shape != positions.shape:
        raise MeshError(f"{name}: normals must have shape {positions.shape}, got {normals.shape}")
    squared = np.einsum("ij,ij->i", normals, normals)
    if np.all(np.abs(squared - 1.0) < 1e-9):  # already unit (and so finite): computed ones, most files
        return normals
    finite = np.isfinite(normals).all(axis=1)
    length = np.linalg.norm(np.where(finite[:, None], normals, 0.0), axis=1)
    usable = finite & (length > 1e-20)
    result = np.zeros_like(normals)
    result[usable] = normals[usable] / length[usable, None]
    if not usable.all():
        # Zero-length or NaN normals in the input: replace those with computed ones
        # rather than let normalize(0) reach the shader.
        computed = vertex_normals(positions, faces)
        result[~usable] = computed[~usable]
    return result


def _relative(positions: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """float32(positions − origin), the subtraction in float64, a block of rows at a time
    (a whole float64 copy of a 10M-triangle mesh's positions is 120 MB)."""
    result = np.empty(positions.shape, np.float32)
    for start in range(0, len(positions), 1 << 16):
        result[start : start + (1 << 16)] = positions[start : start + (1 << 16)].astype(np.float64) - origin
    return result


def _check_some_area(positions: np.ndarray, faces: np.ndarray, extent: float, name: str) -> None:
    """A mesh whose every triangle is degenerate (collinear or repeated corners) rasterizes
    no pixel: a blank image with exit 0 unless refused here. Twice the area of the largest
    triangle, relative to the mesh's size squared, below float32's resolution counts as none."""
    faces = np.asarray(faces)
    threshold = 1e-12 * extent * extent
    for start in range(0, len(faces), 65536):  # chunks: an ordinary mesh stops at the first
        corners = positions[faces[start : start + 65536]].astype(np.float64)
        doubled_areas = np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
        if float(doubled_areas.max(initial=0.0)) > threshold:
            return
    raise MeshError(
        f"{name}: none of its {len(faces)} triangles has any area (their corners are collinear or repeated); "
        "nothing would be drawn"
    )
