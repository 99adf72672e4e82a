"""What the PLY tests compare this package's readers with: trimesh's reading of the same
file (every numpy reader of assets/mesh_formats/ply.py out of its way), array by array."""

from __future__ import annotations

from pathlib import Path
from unittest import mock

import numpy as np

from wgpu_shading import load_mesh
from wgpu_shading.assets.mesh_formats import ply
from wgpu_shading.assets.mesh_formats.ply_header import PLY_TYPES

ARRAYS = ("positions", "normals", "indices", "colors", "uvs", "origin")


def through_trimesh(path: Path):
    """load_mesh(path) as trimesh reads the file (the Mesh built from trimesh's arrays)."""
    with mock.patch.object(ply, "triangle_layout", lambda header, size: None), \
            mock.patch.object(ply, "read_ascii_triangles", lambda *args: None), \
            mock.patch.object(ply, "read_polygons", lambda *args: None):
        return load_mesh(path)


def assert_same_mesh(mesh, expected) -> None:
    """The same arrays (dtype and values) and the same parts."""
    for name in ARRAYS:
        ours, theirs = getattr(mesh, name), getattr(expected, name)
        assert (ours is None) == (theirs is None), name
        if ours is not None:
            ours, theirs = np.asarray(ours), np.asarray(theirs)
            assert ours.dtype == theirs.dtype, name
            np.testing.assert_array_equal(ours, theirs, err_msg=name)
    assert [(p.first, p.count, p.name) for p in mesh.parts] == [(p.first, p.count, p.name) for p in expected.parts]


def vertex_bytes(columns, values: dict, count: int, order: str = "<") -> bytearray:
    """A binary PLY's vertex records: `columns` (name, PLY type), values[name] for each."""
    vertices = np.zeros(count, np.dtype([(name, order + PLY_TYPES[kind]) for name, kind in columns]))
    for name, _ in columns:
        vertices[name] = values[name]
    return bytearray(vertices.tobytes())
