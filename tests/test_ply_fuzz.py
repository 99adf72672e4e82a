"""Random small PLY files (binary either byte order, or ASCII; normals, colours, texcoord
lists, scalars and colours after a face's lists, faces of several sizes, a bad index, a
cut-off end) read by load_mesh and by trimesh (the independent reference): load_mesh gives
a Mesh or a MeshError, never another exception, and where both read a mesh they agree on
its vertices and triangles (where only we read one, the faces are of several sizes, which
trimesh cannot read: ply_polygons.py)."""

from __future__ import annotations

import logging
import warnings

import numpy as np
import pytest

from ply_reference import through_trimesh
from wgpu_shading import MeshError, load_mesh
from wgpu_shading.assets.mesh_formats.ply_header import PLY_TYPES

TYPES = ["uchar", "char", "short", "ushort", "int", "uint", "float", "double"]
FACE_SCALARS = ["flags", "quality", "texnumber", "red", "green", "blue", "alpha"]


def _number(rng, kind: str):
    return float(rng.random()) if kind in ("float", "double") else int(rng.integers(0, 100))


def _write(path, rng) -> bool:
    """A random PLY at `path`; whether its faces are all of one size."""
    binary, order = rng.random() < 0.7, "<" if rng.random() < 0.7 else ">"
    vertices, face_count = int(rng.integers(3, 12)), int(rng.integers(1, 12))
    vertex_props = [("x", "float"), ("y", "float"), ("z", "float")]
    if rng.random() < 0.4:
        vertex_props += [("nx", "float"), ("ny", "float"), ("nz", "float")]
    if rng.random() < 0.4:
        vertex_props += [("red", "uchar"), ("green", "uchar"), ("blue", "uchar")]
    face_props = [("vertex_indices", "list uchar int")] + [("texcoord", "list uchar float")] * bool(rng.random() < 0.4)
    for name in rng.choice(FACE_SCALARS, int(rng.integers(0, 4)), replace=False).tolist():
        face_props.append((name, "uchar" if rng.random() < 0.5 else str(rng.choice(TYPES))))
    kind = "binary_little_endian" if order == "<" else "binary_big_endian"
    header = ["ply", f"format {kind if binary else 'ascii'} 1.0", f"element vertex {vertices}"]
    header += [f"property {t} {n}" for n, t in vertex_props] + [f"element face {face_count}"]
    header += [f"property {t} {n}" for n, t in face_props] + ["end_header"]
    rows = [[(float(rng.normal()), t) if t == "float" else (int(rng.integers(0, 256)), t) for _, t in vertex_props] for _ in range(vertices)]
    corners, one_size = 3 if rng.random() < 0.8 else int(rng.integers(4, 6)), True
    for _ in range(face_count):
        size = corners if rng.random() < 0.9 else int(rng.integers(3, 6))
        one_size &= size == corners
        record = [(size, "uchar")] + [(int(i), "int") for i in rng.integers(0, vertices + (rng.random() < 0.05), size)]
        for name, kind in face_props[1:]:
            if name == "texcoord":
                count = 2 * size if rng.random() < 0.95 else 2 * size - 2
                record += [(count, "uchar")] + [(float(rng.random()), "float") for _ in range(count)]
            else:
                record.append((_number(rng, kind), kind))
        rows.append(record)
    with open(path, "wb") as file:
        file.write(("\n".join(header) + "\n").encode())
        for record in rows:
            if binary:
                file.write(b"".join(np.array(value, order + PLY_TYPES[kind]).tobytes() for value, kind in record))
            else:
                file.write((" ".join(f"{v:.9g}" if isinstance(v, float) else str(v) for v, _ in record) + "\n").encode())
        if binary and rng.random() < 0.05:
            file.truncate(file.tell() - 3)
    return one_size


def _outcome(read, path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        logging.disable(logging.CRITICAL)
        try:
            return read(path)
        except MeshError as error:
            return error
        finally:
            logging.disable(logging.NOTSET)


@pytest.mark.parametrize("seed", range(4))
def test_random_plys_are_a_mesh_or_a_mesh_error_and_agree_with_trimesh(tmp_path, seed):
    rng = np.random.default_rng(seed)
    for number in range(40):
        path = tmp_path / f"random{number}.ply"
        one_size = _write(path, rng)
        ours, theirs = _outcome(load_mesh, path), _outcome(through_trimesh, path)  # (anything else raises here)
        if not isinstance(ours, MeshError) and not isinstance(theirs, MeshError):
            assert (ours.vertex_count, ours.triangle_count) == (theirs.vertex_count, theirs.triangle_count), path.read_bytes()[:600]
        elif isinstance(ours, MeshError) != isinstance(theirs, MeshError):
            assert not one_size and isinstance(theirs, MeshError), (path.read_bytes()[:600], ours, theirs)
