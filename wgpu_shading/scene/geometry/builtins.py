"""Procedural meshes with exact analytic normals: `builtin:sphere`, `torus`, `cube`, `plane`."""

from __future__ import annotations

import math
from typing import Callable
from urllib.parse import parse_qsl

import numpy as np

from ...errors import MeshError, shown
from .mesh import Mesh

BUILTIN_PREFIX = "builtin:"
# Tessellation limit, checked before anything is allocated (a 20000×20000 sphere would
# take > 6 GB): 4 million triangles is ~100 MB of mesh.
MAX_BUILTIN_TRIANGLES = 4_000_000


def _check_tessellation(name: str, triangles: int, counts: str) -> None:
    if triangles > MAX_BUILTIN_TRIANGLES:
        raise MeshError(
            f"builtin:{name} with {counts} would have {triangles} triangles; at most {MAX_BUILTIN_TRIANGLES} are supported"
        )


def _check_size(name: str, **sizes: float) -> None:
    for key, value in sizes.items():
        if not (math.isfinite(value) and 1e-6 <= value <= 1e6):
            raise MeshError(f"builtin:{name} needs {key} between 1e-06 and 1e+06, got {value}")


def _full_turn(steps: int) -> tuple[np.ndarray, np.ndarray]:
    """cos and sin of steps + 1 angles from 0 to 2π, the last exactly equal to the first: the
    duplicated seam vertices sit where the first column's do (sin(2π) is −2.4e-16 in floating
    point, which left the seam open by that much; a closed surface is what
    render/gpu/clusters.py needs to skip the faces turned away, docs/performance.md)."""
    angles = np.linspace(0.0, 2.0 * math.pi, steps + 1)
    cosines, sines = np.cos(angles), np.sin(angles)
    cosines[-1], sines[-1] = cosines[0], sines[0]
    return cosines, sines


def uv_sphere(radius: float = 1.0, slices: int = 64, stacks: int = 32) -> Mesh:
    """A UV sphere around the Y axis with exact normals; 2·slices·(stacks−1) triangles.

    Poles are single vertices (so 20 triangles is possible: slices=5, stacks=3), and the
    seam column is duplicated so UVs wrap cleanly.
    """
    slices, stacks = int(slices), int(stacks)
    if slices < 3 or stacks < 2:
        raise MeshError(f"builtin:sphere needs slices >= 3 and stacks >= 2, got slices={slices}, stacks={stacks}")
    _check_size("sphere", radius=radius)
    _check_tessellation("sphere", 2 * slices * (stacks - 1), f"slices={slices}, stacks={stacks}")
    theta = np.linspace(0.0, math.pi, stacks + 1)[1:-1]  # polar angle of the inner rings
    phi = np.linspace(0.0, 2.0 * math.pi, slices + 1)  # seam duplicated
    cos_p, sin_p = _full_turn(slices)
    sin_t, cos_t = np.sin(theta)[:, None], np.cos(theta)[:, None]
    ring = np.stack(
        [sin_t * sin_p[None, :], np.broadcast_to(cos_t, (len(theta), len(phi))), sin_t * cos_p[None, :]],
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
    _check_size("torus", major=major_radius, minor=minor_radius)
    if not 0 < minor_radius < major_radius:
        raise MeshError(f"builtin:torus needs 0 < minor < major, got major={major_radius}, minor={minor_radius}")
    _check_tessellation("torus", 2 * segments * rings, f"segments={segments}, rings={rings}")
    around = np.linspace(0.0, 2.0 * math.pi, segments + 1)  # big circle, seam duplicated
    tube = np.linspace(0.0, 2.0 * math.pi, rings + 1)
    a, t = np.meshgrid(around, tube, indexing="ij")
    cos_a, sin_a = (np.broadcast_to(values[:, None], a.shape) for values in _full_turn(segments))
    cos_t, sin_t = (np.broadcast_to(values[None, :], a.shape) for values in _full_turn(rings))
    # Unit direction from the tube centre to the surface: the exact normal.
    normal = np.stack([cos_t * cos_a, sin_t, -cos_t * sin_a], axis=-1)
    centre = np.stack([major_radius * cos_a, np.zeros_like(a), -major_radius * sin_a], axis=-1)
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
    _check_size("cube", size=size)  # a negative size would turn it inside out
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
    _check_size("plane", size=size)
    _check_tessellation("plane", 2 * n * n, f"subdivisions={n}")
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
        raise MeshError(f"unknown built-in mesh {shown(spec)}; available: {', '.join(BUILTIN_PREFIX + n for n in BUILTINS)}")
    factory, parameters = BUILTINS[name]
    kwargs: dict[str, object] = {}
    for key, raw in parse_qsl(query, keep_blank_values=True, strict_parsing=False):
        if key not in parameters:
            raise MeshError(f"{shown(spec)}: unknown parameter {shown(key)}; {name} takes {', '.join(parameters)}")
        try:
            if len(raw) > 40:
                raise ValueError(raw)
            value = parameters[key](raw)
        except ValueError:
            raise MeshError(f"{shown(spec)}: parameter {key} expects {parameters[key].__name__}, got {shown(raw)}") from None
        if key in kwargs or _PARAMETER_NAMES.get(name, {}).get(key, key) in kwargs:
            raise MeshError(f"{shown(spec)}: parameter {key} is given twice")
        kwargs[_PARAMETER_NAMES.get(name, {}).get(key, key)] = value
    return factory(**kwargs)


# --------------------------------------------------------------------------- files
