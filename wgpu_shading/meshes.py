"""Triangle meshes: the Mesh type, procedural built-ins, and files read through trimesh.

Vertex positions are stored in float32 *relative to* `Mesh.origin` (float64, the centre
of the bounding box). The GPU wants float32, and a mesh modelled 1e5 units from the
origin would lose its detail in float32 absolute coordinates; the origin is added back
in float64 on the CPU as part of the model matrix (see SceneObject.world_from_model).

Vertex normals come from the file when it has them, else they are the normalized sum
of the adjacent faces' unit normals (the seeds' definition). Built-ins carry their
exact analytic normals.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Callable
from urllib.parse import parse_qsl

import numpy as np

from .errors import MeshError

if TYPE_CHECKING:  # pragma: no cover
    from .scene import Material

BUILTIN_PREFIX = "builtin:"
MESH_SUFFIXES = (".obj", ".ply", ".stl", ".off", ".glb", ".gltf")


@dataclass(frozen=True, eq=False)
class Mesh:
    """An indexed triangle mesh, ready for upload.

    positions: (N, 3) float32, relative to `origin`
    normals:   (N, 3) float32, unit length (zero only where no normal can be defined)
    indices:   (F, 3) uint32, counter-clockwise front faces
    uvs:       (N, 2) float32 or None (v = 0 at the bottom of the image)
    origin:    float64 offset added back to `positions`
    material:  the file's own material (OBJ/MTL, glTF), if any
    """

    positions: np.ndarray = field(repr=False)
    normals: np.ndarray = field(repr=False)
    indices: np.ndarray = field(repr=False)
    uvs: np.ndarray | None = field(default=None, repr=False)
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    name: str = ""
    material: "Material | None" = field(default=None, repr=False)

    def __post_init__(self) -> None:
        for array in (self.positions, self.normals, self.indices, self.uvs):
            if array is not None:
                array.setflags(write=False)  # shared with GPU caches: must not change under them

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
        return sum(a.nbytes for a in (self.positions, self.normals, self.indices, self.uvs) if a is not None)

    def world_positions(self) -> np.ndarray:
        """Positions in model space as float64 (origin added back)."""
        return self.positions.astype(np.float64) + np.asarray(self.origin)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """float64 (lower, upper) corners of the bounding box in model space."""
        return (
            self.positions.min(axis=0).astype(np.float64) + self.origin,
            self.positions.max(axis=0).astype(np.float64) + self.origin,
        )

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
    ) -> "Mesh":
        """Validate and convert user arrays; computes normals when none are given."""
        positions = np.asarray(positions, dtype=np.float64)
        faces = np.asarray(indices)
        if positions.ndim != 2 or positions.shape[1] != 3:
            raise MeshError(f"{name}: positions must have shape (N, 3), got {positions.shape}")
        if faces.ndim == 1 and faces.size % 3 == 0:
            faces = faces.reshape(-1, 3)
        if faces.ndim != 2 or faces.shape[1] != 3:
            raise MeshError(f"{name}: indices must have shape (F, 3) (triangles), got {faces.shape}")
        if len(positions) == 0 or len(faces) == 0:
            raise MeshError(f"{name}: the mesh is empty ({len(positions)} vertices, {len(faces)} triangles)")
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
        if normals is None:
            unit_normals = vertex_normals(positions, faces)
        else:
            unit_normals = _validated_normals(np.asarray(normals, dtype=np.float64), positions, faces, name)
        if uvs is not None:
            uvs = np.asarray(uvs, dtype=np.float64)
            if uvs.shape != (len(positions), 2):
                raise MeshError(f"{name}: uvs must have shape ({len(positions)}, 2), got {uvs.shape}")
            if not np.isfinite(uvs).all():
                raise MeshError(f"{name}: uvs contain NaN or infinite values")
            uvs = np.ascontiguousarray(uvs, dtype=np.float32)
        lower, upper = positions.min(axis=0), positions.max(axis=0)
        origin = (lower + upper) / 2.0
        if np.all(np.abs(origin) <= 1e-3 * max(float((upper - lower).max()), 1e-30)):
            origin = np.zeros(3)  # keep meshes that are already centred bit-exact
        return cls(
            positions=np.ascontiguousarray(positions - origin, dtype=np.float32),
            normals=np.ascontiguousarray(unit_normals, dtype=np.float32),
            indices=faces,
            uvs=uvs,
            origin=tuple(float(v) for v in origin),
            name=name,
            material=material,
        )


# --------------------------------------------------------------------------- normals


def face_normals(positions: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit face normals (zero for zero-area faces) and twice the face areas, float64."""
    p0, p1, p2 = (positions[faces[:, k]] for k in range(3))
    cross = np.cross(p1 - p0, p2 - p0)
    length = np.linalg.norm(cross, axis=1)
    scale = np.max(np.abs(positions)) if len(positions) else 1.0
    # "zero area" relative to the mesh's own scale, so tiny meshes (1e-5) keep their faces
    degenerate = length <= 1e-12 * max(scale, 1e-300) ** 2
    unit = np.zeros_like(cross)
    np.divide(cross, length[:, None], out=unit, where=~degenerate[:, None])
    return unit, np.where(degenerate, 0.0, length)


def vertex_normals(positions: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Normalized sum of the unit normals of the faces around each vertex (seeds 000, 001, 004).

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


# --------------------------------------------------------------------------- built-ins


def uv_sphere(radius: float = 1.0, slices: int = 64, stacks: int = 32) -> Mesh:
    """A UV sphere around the Y axis with exact normals; 2·slices·(stacks−1) triangles.

    Poles are single vertices (so 20 triangles is possible: slices=5, stacks=3), and the
    seam column is duplicated so UVs wrap cleanly.
    """
    slices, stacks = int(slices), int(stacks)
    if slices < 3 or stacks < 2:
        raise MeshError(f"builtin:sphere needs slices >= 3 and stacks >= 2, got slices={slices}, stacks={stacks}")
    if not radius > 0:
        raise MeshError(f"builtin:sphere needs radius > 0, got {radius}")
    theta = np.linspace(0.0, math.pi, stacks + 1)[1:-1]  # polar angle of the inner rings
    phi = np.linspace(0.0, 2.0 * math.pi, slices + 1)  # seam duplicated
    sin_t, cos_t = np.sin(theta)[:, None], np.cos(theta)[:, None]
    ring = np.stack(
        [sin_t * np.sin(phi)[None, :], np.broadcast_to(cos_t, (len(theta), len(phi))), sin_t * np.cos(phi)[None, :]],
        axis=-1,
    ).reshape(-1, 3)
    u = np.broadcast_to(phi[None, :] / (2.0 * math.pi), (len(theta), len(phi))).reshape(-1)
    v = np.broadcast_to(1.0 - theta[:, None] / math.pi, (len(theta), len(phi))).reshape(-1)
    # One pole vertex per slice so each polar triangle gets its own u (texture-friendly).
    pole_u = (np.arange(slices) + 0.5) / slices
    top = np.tile([0.0, 1.0, 0.0], (slices, 1))
    bottom = np.tile([0.0, -1.0, 0.0], (slices, 1))
    normals = np.concatenate([top, ring, bottom])
    uvs = np.concatenate(
        [np.stack([pole_u, np.ones(slices)], 1), np.stack([u, v], 1), np.stack([pole_u, np.zeros(slices)], 1)]
    )
    columns = slices + 1
    ring_start, bottom_start = slices, slices + len(ring)

    def ring_index(row: np.ndarray, column: np.ndarray) -> np.ndarray:
        return ring_start + row * columns + column

    s = np.arange(slices)
    faces = [np.stack([s, ring_index(0, s), ring_index(0, s + 1)], 1)]  # top cap
    if stacks > 2:
        r, c = np.meshgrid(np.arange(stacks - 2), s, indexing="ij")
        r, c = r.reshape(-1), c.reshape(-1)
        a, b = ring_index(r, c), ring_index(r + 1, c)
        a1, b1 = ring_index(r, c + 1), ring_index(r + 1, c + 1)
        faces += [np.stack([a, b, b1], 1), np.stack([a, b1, a1], 1)]
    last = stacks - 2
    faces.append(np.stack([ring_index(last, s), bottom_start + s, ring_index(last, s + 1)], 1))
    return Mesh.from_arrays(
        normals * radius, np.concatenate(faces), normals=normals, uvs=uvs, name=f"builtin:sphere({slices}x{stacks})"
    )


def sphere_for_triangles(triangles: int, radius: float = 1.0) -> Mesh:
    """The UV sphere with about `triangles` triangles (slices = 2·stacks)."""
    stacks = max(2, round(math.sqrt(max(triangles, 8) / 4.0 + 0.25) + 0.5))
    slices = max(3, round(triangles / (2.0 * (stacks - 1))))
    return uv_sphere(radius, slices, stacks)


def torus(major_radius: float = 0.5, minor_radius: float = 0.2, segments: int = 48, rings: int | None = None) -> Mesh:
    """The seeds' torus (Gordon & Clevenger's Torus(0.5, 0.2, 48)) around the Y axis.

    `segments` subdivide the big circle, `rings` the tube (default: the same count).
    """
    segments = int(segments)
    rings = segments if rings is None else int(rings)
    if segments < 3 or rings < 3:
        raise MeshError(f"builtin:torus needs segments >= 3 and rings >= 3, got {segments}, {rings}")
    if not 0 < minor_radius < major_radius:
        raise MeshError(f"builtin:torus needs 0 < minor < major, got major={major_radius}, minor={minor_radius}")
    around = np.linspace(0.0, 2.0 * math.pi, segments + 1)  # big circle, seam duplicated
    tube = np.linspace(0.0, 2.0 * math.pi, rings + 1)
    a, t = np.meshgrid(around, tube, indexing="ij")
    # Unit direction from the tube centre to the surface: the exact normal.
    normal = np.stack([np.cos(t) * np.cos(a), np.sin(t), -np.cos(t) * np.sin(a)], axis=-1)
    centre = np.stack([major_radius * np.cos(a), np.zeros_like(a), -major_radius * np.sin(a)], axis=-1)
    positions = (centre + minor_radius * normal).reshape(-1, 3)
    uvs = np.stack([a / (2.0 * math.pi), t / (2.0 * math.pi)], axis=-1).reshape(-1, 2)
    columns = rings + 1
    i, j = np.meshgrid(np.arange(segments), np.arange(rings), indexing="ij")
    i, j = i.reshape(-1), j.reshape(-1)
    v00, v01 = i * columns + j, i * columns + j + 1
    v10, v11 = (i + 1) * columns + j, (i + 1) * columns + j + 1
    faces = np.concatenate([np.stack([v00, v10, v11], 1), np.stack([v00, v11, v01], 1)])
    return Mesh.from_arrays(
        positions, faces, normals=normal.reshape(-1, 3), uvs=uvs, name=f"builtin:torus({segments}x{rings})"
    )


def cube(size: float = 1.0) -> Mesh:
    """An axis-aligned cube centred on the origin: 24 vertices, so every face is flat."""
    half = size / 2.0
    faces_axes = [  # normal, u axis, v axis
        ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
        ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
        ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
        ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
        ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
        ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
    ]
    positions, normals, uvs, faces = [], [], [], []
    for face, (n, u, v) in enumerate(faces_axes):
        n, u, v = np.array(n, float), np.array(u, float), np.array(v, float)
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            positions.append(half * (n + su * u + sv * v))
            normals.append(n)
            uvs.append(((su + 1) / 2, (sv + 1) / 2))
        base = 4 * face
        faces += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    return Mesh.from_arrays(np.array(positions), np.array(faces), normals=np.array(normals), uvs=np.array(uvs), name="builtin:cube")


def plane(size: float = 2.0, subdivisions: int = 1) -> Mesh:
    """A square in the XY plane facing +Z (towards the default camera)."""
    n = int(subdivisions)
    if n < 1:
        raise MeshError(f"builtin:plane needs subdivisions >= 1, got {n}")
    coords = np.linspace(-size / 2.0, size / 2.0, n + 1)
    x, y = np.meshgrid(coords, coords, indexing="xy")
    positions = np.stack([x.reshape(-1), y.reshape(-1), np.zeros(x.size)], 1)
    uvs = (positions[:, :2] / size) + 0.5
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
    i, j = i.reshape(-1), j.reshape(-1)
    v00 = j * (n + 1) + i
    v10, v01, v11 = v00 + 1, v00 + n + 1, v00 + n + 2
    faces = np.concatenate([np.stack([v00, v10, v11], 1), np.stack([v00, v11, v01], 1)])
    normals = np.tile([0.0, 0.0, 1.0], (len(positions), 1))
    return Mesh.from_arrays(positions, faces, normals=normals, uvs=uvs, name=f"builtin:plane({n})")


BUILTINS: dict[str, tuple[Callable[..., Mesh], dict[str, type]]] = {
    "sphere": (uv_sphere, {"radius": float, "slices": int, "stacks": int}),
    "torus": (torus, {"major": float, "minor": float, "segments": int, "rings": int}),
    "cube": (cube, {"size": float}),
    "plane": (plane, {"size": float, "subdivisions": int}),
}
_PARAMETER_NAMES = {"torus": {"major": "major_radius", "minor": "minor_radius"}}


def builtin(spec: str) -> Mesh:
    """`builtin:NAME` or `builtin:NAME?key=value&...`, e.g. `builtin:sphere?slices=20&stacks=20`."""
    body = spec[len(BUILTIN_PREFIX):] if spec.startswith(BUILTIN_PREFIX) else spec
    name, _, query = body.partition("?")
    if name not in BUILTINS:
        raise MeshError(f"unknown built-in mesh {spec!r}; available: {', '.join(BUILTIN_PREFIX + n for n in BUILTINS)}")
    factory, parameters = BUILTINS[name]
    kwargs: dict[str, object] = {}
    for key, raw in parse_qsl(query, keep_blank_values=True, strict_parsing=False):
        if key not in parameters:
            raise MeshError(f"{spec!r}: unknown parameter {key!r}; {name} takes {', '.join(parameters)}")
        try:
            value = parameters[key](raw)
        except ValueError:
            raise MeshError(f"{spec!r}: parameter {key} expects {parameters[key].__name__}, got {raw!r}") from None
        kwargs[_PARAMETER_NAMES.get(name, {}).get(key, key)] = value
    return factory(**kwargs)


# --------------------------------------------------------------------------- files


def load_mesh(source: str | os.PathLike[str]) -> Mesh:
    """A built-in (`builtin:torus`) or a mesh file (OBJ, PLY, STL, OFF, GLB/glTF)."""
    text = str(source)
    if text.startswith(BUILTIN_PREFIX):
        return builtin(text)
    path = Path(text)
    if not path.exists():
        raise MeshError(f"mesh file {text!r} not found")
    if path.is_dir():
        raise MeshError(f"mesh file {text!r} is a directory")
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise MeshError(f"mesh file {text!r}: unsupported format {path.suffix!r}; expected one of {', '.join(MESH_SUFFIXES)}")
    import trimesh  # lazy: trimesh costs ~0.3 s to import

    try:
        loaded = trimesh.load(str(path), process=False)
    except IndexError as error:  # trimesh indexes vertices with the file's face indices
        raise MeshError(f"mesh file {text!r}: a face refers to a vertex that does not exist ({error})") from None
    except Exception as error:  # trimesh raises many exception types for malformed files
        raise MeshError(f"mesh file {text!r}: cannot be read ({type(error).__name__}: {error})") from None
    parts = _triangle_parts(loaded)
    if not parts:
        raise MeshError(f"mesh file {text!r} contains no triangles")
    return _merge(parts, name=path.name)


def _triangle_parts(loaded: object) -> list:
    import trimesh

    if isinstance(loaded, trimesh.Scene):
        # dump() applies the scene graph's transforms; keeps per-part normals and visuals.
        parts = [g for g in loaded.dump() if isinstance(g, trimesh.Trimesh)]
    elif isinstance(loaded, trimesh.Trimesh):
        parts = [loaded]
    else:
        parts = []
    return [p for p in parts if len(p.faces) and len(p.vertices)]


def _merge(parts: list, name: str) -> Mesh:
    from .materials import material_from_trimesh

    positions, indices, normals, uvs = [], [], [], []
    offset = 0
    have_uvs = all(getattr(p.visual, "uv", None) is not None and len(p.visual.uv) == len(p.vertices) for p in parts)
    for part in parts:
        vertices = np.asarray(part.vertices, dtype=np.float64)
        faces = np.asarray(part.faces, dtype=np.int64)
        file_normals = part._cache.cache.get("vertex_normals")  # present only when the file had normals
        positions.append(vertices)
        indices.append(faces + offset)
        if file_normals is not None and np.shape(file_normals) == vertices.shape:
            normals.append(np.asarray(file_normals, dtype=np.float64))
        else:
            normals.append(None)
        if have_uvs:
            uvs.append(np.asarray(part.visual.uv, dtype=np.float64))
        offset += len(vertices)
    all_positions = np.concatenate(positions)
    all_indices = np.concatenate(indices)
    if all(n is None for n in normals):
        merged_normals = None
    else:
        computed = vertex_normals(all_positions, all_indices.astype(np.uint32))
        merged_normals = np.concatenate(
            [n if n is not None else computed[start : start + len(p)] for n, p, start in _with_starts(normals, positions)]
        )
    material = material_from_trimesh(parts[0], name)
    return Mesh.from_arrays(
        all_positions,
        all_indices,
        normals=merged_normals,
        uvs=np.concatenate(uvs) if have_uvs else None,
        name=name,
        material=material,
    )


def _with_starts(normals: list, positions: list):
    start = 0
    for n, p in zip(normals, positions):
        yield n, p, start
        start += len(p)
