"""Mesh files read through trimesh (OBJ/MTL, PLY, STL, OFF, glTF/GLB) into Mesh objects."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..errors import MeshError
from ..scene.builtins import BUILTIN_PREFIX, builtin
from ..scene.mesh import Mesh, vertex_normals
from .examples import resolve_example
from .file_materials import material_from_trimesh

MESH_SUFFIXES = (".obj", ".ply", ".stl", ".off", ".glb", ".gltf")


def load_mesh(source: str | os.PathLike[str]) -> Mesh:
    """A built-in (`builtin:torus`), a sample (`example:knot.obj`) or a mesh file (OBJ, PLY,
    STL, OFF, GLB/glTF)."""
    text = resolve_example(str(source))
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
