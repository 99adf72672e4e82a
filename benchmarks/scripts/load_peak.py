"""Peak resident memory of loading a large mesh file with `load_mesh`, and of rendering it,
in a fresh process (Linux).

    python benchmarks/scripts/load_peak.py 10000000 /tmp/torus10m.stl
    python benchmarks/scripts/load_peak.py 10000000 /tmp/torus10m.stl --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/points10m.ply
    python benchmarks/scripts/load_peak.py 10000000 /tmp/torus10m.ply --triangles --render 512
    python benchmarks/scripts/load_peak.py 2000000 /tmp/torus2m.stl --crease-angle 0 --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/exported10m.obj --exported --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/cubes10m.stl --cubes --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/mixed10m.ply --mixed --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/mixed10m.off --mixed --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/mixed-ascii10m.ply --mixed --ascii --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/embedded10m.gltf --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/coloured10m.off --colours --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/mixed-coloured10m.off --mixed --colours --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/ascii10m.stl --ascii --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/points10m.xyz
    python benchmarks/scripts/load_peak.py 10000000 /tmp/uvs10m.ply --face-uvs --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/ascii-uvs10m.ply --face-uvs --ascii --render 512
    python benchmarks/scripts/load_peak.py 10000000 /tmp/seams10m.obj --uv-seams --render 512

Writes the file when it does not exist, by its suffix: `.stl`, a smooth torus of about
COUNT triangles as a binary STL (every corner repeated, as STL stores it; triangles in the
order of the torus's grid); `.ply`, a point cloud of COUNT points on a sphere as a binary
little-endian PLY (float x y z, float nx ny nz, uchar red green blue: 27 bytes a point, as
scanners write them), or with --triangles the same torus as the STL's as a binary
little-endian PLY mesh (float x y z; list uchar int vertex_indices, as VTK and MeshLab
write a scan), or with --face-uvs with a `texcoord` list on every face (as MeshLab and
Agisoft Metashape export a textured mesh; with --ascii as an ASCII PLY), or with --mixed as Blender's PLY exporter writes a mesh it does not
triangulate (float x y z, nx ny nz, s t; `list uchar uint`; the torus's quads, every tenth
as two triangles: faces of two sizes), with --mixed --ascii the same faces in an ASCII PLY;
`.off`, with --mixed, those faces as a plain OFF, with --colours the torus as a COFF (an
RGBA colour on every vertex line, as MeshLab writes one), with --mixed --colours the faces of
two sizes with an RGB colour after each; `.stl` with --ascii, the torus as an ASCII STL (%e
numbers, as SolidWorks writes them); `.xyz`, COUNT points on a sphere with their normals
(x y z nx ny nz a line); `.obj`, the same torus as an OBJ of `v` and `f a b c` lines, or with --uv-seams of `v`, `vt`
and `f v/vt` lines (uvs with seams, no normals: Agisoft Metashape's export); `.glb`, the same
torus as a binary glTF with float32 normals (as Blender exports one); `.gltf`, the same glTF
with its buffer embedded as a base64 data: URI (a `glTF-Embedded` file); with --cubes an STL of
about COUNT/12 separate unit cubes on a grid (a voxel model, or a CAD part: every vertex on
a 90° crease, split into its three faces' normals, so the Mesh has twice the STL's
vertices). Then loads it and prints one JSON object: the mesh's arrays
(positions + normals + indices + colours, what a Renderer uploads), the process's resident
memory after imports (with --render: after the device and a small render too), its peak
(VmHWM), and the peak above that baseline as a multiple of the mesh's arrays; with --render
also the peak of the load alone, then the mesh rendered as `wgpu-shading render` frames it.
`--crease-angle A` loads it with that crease angle (0: every edge sharp, every vertex through
the crease analysis; docs/performance.md, "Loading a large mesh").
docs/reliability.md, docs/primitives.md and the memory table of `python -m benchmarks`
(benchmarks/memory.py) quote the result.
"""

import json
import math
import sys
import time
from pathlib import Path

import numpy as np


def torus(triangles: int) -> tuple[np.ndarray, np.ndarray]:
    """A smooth torus of about `triangles` triangles: float32 positions, faces in the order of its grid."""
    side = max(3, int(math.sqrt(triangles / 2)))
    u = np.linspace(0, 2 * np.pi, side, endpoint=False)
    uu, vv = np.meshgrid(u, u)
    positions = np.stack(
        [(1 + 0.35 * np.cos(vv)) * np.cos(uu), (1 + 0.35 * np.cos(vv)) * np.sin(uu), 0.35 * np.sin(vv)], -1
    ).reshape(-1, 3).astype(np.float32)
    i, j = np.arange(side)[:, None], np.arange(side)[None, :]
    a, b = i * side + j, i * side + (j + 1) % side
    c, d = ((i + 1) % side) * side + j, ((i + 1) % side) * side + (j + 1) % side
    faces = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    return positions, faces


def write_torus_stl(path: Path, triangles: int) -> None:
    positions, faces = torus(triangles)
    records = np.zeros(len(faces), np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")]))
    records["corners"] = positions[faces]
    with open(path, "wb") as file:
        file.write(b"torus".ljust(80, b" ") + np.uint32(len(faces)).tobytes())
        records.tofile(file)


def write_cubes_stl(path: Path, triangles: int) -> None:
    """About `triangles` / 12 separate unit cubes, 1.5 apart on a grid, as a binary STL
    (written a block of cubes at a time: the writer itself stays small)."""
    count = max(1, triangles // 12)
    side = math.ceil(count ** (1 / 3))
    corner = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], np.float32)
    cube = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                     [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])  # outward
    record = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
    with open(path, "wb") as file:
        file.write(b"cubes".ljust(80, b" ") + np.uint32(12 * count).tobytes())
        for start in range(0, count, 1 << 16):
            ids = np.arange(start, min(start + (1 << 16), count))
            origins = 1.5 * np.stack([ids % side, ids // side % side, ids // (side * side)], -1).astype(np.float32)
            records = np.zeros(12 * len(ids), record)
            records["corners"] = (origins[:, None, None] + corner[cube]).reshape(-1, 3, 3)
            records.tofile(file)


def write_point_ply(path: Path, count: int) -> None:
    rng = np.random.default_rng(1)
    records = np.zeros(count, np.dtype([("p", "<f4", (3,)), ("n", "<f4", (3,)), ("c", "u1", (3,))]))
    for start in range(0, count, 1 << 20):  # in blocks: the writer itself stays small
        block = rng.normal(size=(min(1 << 20, count - start), 3))
        block /= np.linalg.norm(block, axis=1, keepdims=True)
        records["p"][start : start + len(block)] = block
        records["n"][start : start + len(block)] = block
        records["c"][start : start + len(block)] = np.round((block * 0.5 + 0.5) * 255)
    header = (
        "ply\nformat binary_little_endian 1.0\ncomment load_peak.py\n"
        f"element vertex {count}\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
    )
    with open(path, "wb") as file:
        file.write(header.encode("ascii"))
        records.tofile(file)


def write_torus_ply(path: Path, triangles: int) -> None:
    positions, faces = torus(triangles)
    records = np.zeros(len(faces), np.dtype([("count", "u1"), ("corners", "<i4", (3,))]))
    records["count"], records["corners"] = 3, faces
    header = (
        "ply\nformat binary_little_endian 1.0\ncomment load_peak.py\n"
        f"element vertex {len(positions)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    with open(path, "wb") as file:
        file.write(header.encode("ascii"))
        positions.astype("<f4").tofile(file)
        records.tofile(file)


def write_torus_ply_mixed(path: Path, triangles: int) -> None:
    """The torus as Blender writes a PLY: normals and texture coordinates per vertex, quads
    and triangles (every tenth quad as two), written a block of quads at a time."""
    positions, quads, halved = torus_quads(triangles)
    quads = quads.astype("<u4")
    side = int(round(math.sqrt(len(positions))))
    normals = positions / np.linalg.norm(positions, axis=1, keepdims=True)
    header = (
        "ply\nformat binary_little_endian 1.0\ncomment Created by Blender (load_peak.py)\n"
        f"element vertex {len(positions)}\n" + "".join(f"property float {name}\n" for name in ("x", "y", "z", "nx", "ny", "nz", "s", "t"))
        + f"element face {len(quads) + int(halved.sum())}\nproperty list uchar uint vertex_indices\nend_header\n"
    )
    uvs = np.stack([np.arange(len(positions)) % side, np.arange(len(positions)) // side], 1) / side
    with open(path, "wb") as file:
        file.write(header.encode("ascii"))
        np.concatenate([positions, normals, uvs], axis=1).astype("<f4").tofile(file)
        for start in range(0, len(quads), 1 << 16):
            block, halves = quads[start : start + (1 << 16)], halved[start : start + (1 << 16)]
            sizes = np.where(halves, 26, 17)  # a quad's record, or two triangles' records
            at = np.cumsum(sizes) - sizes
            out = np.zeros(int(sizes.sum()), np.uint8)
            whole, cut = at[~halves], at[halves]
            out[whole] = 4
            out[whole[:, None] + 1 + np.arange(16)] = block[~halves].view(np.uint8).reshape(-1, 16)
            for first, corners in ((0, [0, 1, 2]), (13, [0, 2, 3])):
                out[cut + first] = 3
                out[cut[:, None] + first + 1 + np.arange(12)] = np.ascontiguousarray(block[halves][:, corners]).view(np.uint8).reshape(-1, 12)
            out.tofile(file)


def torus_quads(triangles: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The torus's positions, its quads (a b d c of each grid cell) and which of them are
    written as two triangles (every tenth): faces of two sizes, as a quad-dominant exporter
    writes them."""
    positions, faces = torus(triangles)
    quads = np.concatenate([faces[: len(faces) // 2], faces[len(faces) // 2 :, 2:]], axis=1)
    return positions, quads, np.arange(len(quads)) % 10 == 0


def mixed_face_text(quads: np.ndarray, halved: np.ndarray, coloured: bool = False):
    """The face lines (`4 a b c d`, or `3 a b c` twice) a block of quads at a time; coloured:
    each with an RGB colour after its indices (`number % 256` 128 200: 0..255, as MeshLab)."""
    for start in range(0, len(quads), 1 << 16):
        lines = []
        for number, (quad, halve) in enumerate(zip(quads[start : start + (1 << 16)].tolist(), halved[start : start + (1 << 16)].tolist()), start):
            colour = " %d 128 200" % (number % 256) if coloured else ""
            if halve:
                lines += ["3 %d %d %d%s" % (quad[0], quad[1], quad[2], colour), "3 %d %d %d%s" % (quad[0], quad[2], quad[3], colour)]
            else:
                lines.append("4 %d %d %d %d%s" % (*quad, colour))
        yield "\n".join(lines) + "\n"


def write_torus_text_mixed(path: Path, triangles: int, coloured: bool = False) -> None:
    """The torus as a text file of faces of two sizes (torus_quads): a plain OFF (coloured:
    an RGB colour after each face's indices), or an ASCII PLY (float x y z; `list uchar int
    vertex_indices`)."""
    positions, quads, halved = torus_quads(triangles)
    faces = len(quads) + int(halved.sum())
    with open(path, "w") as file:
        if path.suffix.lower() == ".off":
            file.write(f"OFF\n{len(positions)} {faces} 0\n")
        else:
            file.write(f"ply\nformat ascii 1.0\ncomment load_peak.py\nelement vertex {len(positions)}\nproperty float x\n"
                       f"property float y\nproperty float z\nelement face {faces}\nproperty list uchar int vertex_indices\nend_header\n")
        np.savetxt(file, positions, fmt="%.6f")
        for text in mixed_face_text(quads, halved, coloured):
            file.write(text)


def write_torus_stl_ascii(path: Path, triangles: int) -> None:
    """The torus as an ASCII STL in the layout exporters write (numbers as %e, as SolidWorks
    writes them: ~230 bytes a triangle), a block of facets at a time."""
    positions, faces = torus(triangles)
    facet = "facet normal %e %e %e\n outer loop\n  vertex %e %e %e\n  vertex %e %e %e\n  vertex %e %e %e\n endloop\nendfacet\n"
    with open(path, "w") as file:
        file.write("solid torus\n")
        for start in range(0, len(faces), 1 << 16):
            a, b, c = (positions[faces[start : start + (1 << 16), k]].astype(np.float64) for k in range(3))
            normals = np.cross(b - a, c - a)
            normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-30)
            file.write("".join(facet % tuple(row) for row in np.concatenate([normals, a, b, c], axis=1).tolist()))
        file.write("endsolid torus\n")


def write_points_xyz(path: Path, count: int) -> None:
    """COUNT points on a unit sphere with their normals as a `.xyz` (x y z nx ny nz a line,
    6 decimals, as MeshLab and Open3D write `xyzn`), a block of points at a time."""
    rng = np.random.default_rng(1)
    with open(path, "w") as file:
        for start in range(0, count, 1 << 20):
            points = rng.normal(size=(min(1 << 20, count - start), 3))
            points /= np.linalg.norm(points, axis=1, keepdims=True)
            np.savetxt(file, np.concatenate([points, points], axis=1), fmt="%.6f")


def write_torus_ply_face_uvs(path: Path, triangles: int) -> None:
    """The torus as a binary PLY whose faces carry their corners' texture coordinates (`list
    uchar int vertex_indices`, `list uchar float texcoord`), as MeshLab and Agisoft Metashape
    export a textured mesh: the grid's (column, row) / side at each corner, so the vertices
    of the first column and row take two uvs (the seams where the torus wraps)."""
    positions, faces = torus(triangles)
    side = int(round(math.sqrt(len(positions))))
    i, j = np.meshgrid(np.arange(side), np.arange(side), indexing="ij")
    corner_uv = {"a": (j, i), "b": (j + 1, i), "c": (j, i + 1), "d": (j + 1, i + 1)}
    uv = np.concatenate([np.stack([np.stack(corner_uv[k], -1).reshape(-1, 2) for k in names], 1) for names in ("abd", "adc")])
    records = np.zeros(len(faces), np.dtype([("count", "u1"), ("corners", "<i4", (3,)), ("uv_count", "u1"), ("uv", "<f4", (6,))]))
    records["count"], records["corners"], records["uv_count"] = 3, faces, 6
    records["uv"] = (uv / side).reshape(-1, 6)
    encoding = "ascii" if "--ascii" in sys.argv else "binary_little_endian"
    header = (f"ply\nformat {encoding} 1.0\ncomment TextureFile torus.png\nelement vertex {len(positions)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              f"element face {len(faces)}\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n")
    with open(path, "wb") as file:
        file.write(header.encode())
        if encoding == "ascii":  # (with --ascii: a vertex a line, then `3 a b c 6 u v u v u v` a line)
            np.savetxt(file, positions, fmt="%.6f")
            for start in range(0, len(faces), 1 << 20):
                block = records[start : start + (1 << 20)]
                np.savetxt(file, np.concatenate([np.full((len(block), 1), 3), block["corners"], np.full((len(block), 1), 6), block["uv"]], axis=1),
                           fmt="%d %d %d %d %d %.6f %.6f %.6f %.6f %.6f %.6f")
        else:
            positions.tofile(file)
            records.tofile(file)


def write_torus_obj_uv_seams(path: Path, triangles: int) -> None:
    """The torus as an OBJ of `v`, `vt` and `f v/vt` lines without normals, as Agisoft
    Metashape exports a textured mesh: a `vt` per grid point of (side + 1)², so the torus's
    first column and row of vertices take two uvs each (its seams)."""
    positions, faces = torus(triangles)
    side = int(round(math.sqrt(len(positions))))
    i, j = np.meshgrid(np.arange(side), np.arange(side), indexing="ij")
    corner_vt = {"a": i * (side + 1) + j, "b": i * (side + 1) + j + 1, "c": (i + 1) * (side + 1) + j, "d": (i + 1) * (side + 1) + j + 1}
    vts = np.concatenate([np.stack([corner_vt[k].reshape(-1) for k in names], 1) for names in ("abd", "adc")])
    rows, columns = np.meshgrid(np.arange(side + 1), np.arange(side + 1), indexing="ij")
    with open(path, "w") as file:
        np.savetxt(file, positions, fmt="v %.6f %.6f %.6f")
        np.savetxt(file, np.stack([columns.reshape(-1), rows.reshape(-1)], 1) / side, fmt="vt %.6f %.6f")
        np.savetxt(file, np.stack([faces + 1, vts + 1], 2).reshape(len(faces), 6), fmt="f %d/%d %d/%d %d/%d")


def write_torus_coff(path: Path, triangles: int) -> None:
    """The torus as a COFF, as MeshLab writes an OFF with vertex colours: `x y z r g b a` a
    vertex line (0..255), then `3 a b c` a face line."""
    positions, faces = torus(triangles)
    colours = np.abs(positions / np.abs(positions).max(axis=0)) * 255
    with open(path, "w") as file:
        file.write(f"COFF\n{len(positions)} {len(faces)} 0\n")
        np.savetxt(file, np.concatenate([positions, colours, np.full((len(positions), 1), 255.0)], axis=1), fmt="%.6f %.6f %.6f %d %d %d %d")
        np.savetxt(file, faces, fmt="3 %d %d %d")


def write_torus_obj(path: Path, triangles: int) -> None:
    """The torus as an OBJ of `v x y z` lines (6 decimals, as MeshLab writes them) and `f a b c` lines."""
    positions, faces = torus(triangles)
    with open(path, "w") as file:
        np.savetxt(file, positions, fmt="v %.6f %.6f %.6f")
        np.savetxt(file, faces + 1, fmt="f %d %d %d")


def write_torus_obj_exported(path: Path, triangles: int) -> None:
    """The torus as an OBJ as Blender, Maya and Cinema 4D write one: `v`, `vt` and `vn` lines
    numbered on their own (the `vt` lines in another order, the `vn` lines reversed), so
    that each `f v/vt/vn` corner's three numbers differ."""
    positions, faces = torus(triangles)
    count = len(positions)
    uv_line = (np.arange(count, dtype=np.int64) * 7919) % count  # vertex → its vt line (7919 is prime: a permutation)
    vertex_of_uv = np.empty(count, np.int64)
    vertex_of_uv[uv_line] = np.arange(count)
    normals = positions / np.linalg.norm(positions, axis=1, keepdims=True)
    with open(path, "w") as file:
        np.savetxt(file, positions, fmt="v %.6f %.6f %.6f")
        np.savetxt(file, positions[vertex_of_uv][:, :2], fmt="vt %.6f %.6f")
        np.savetxt(file, normals[::-1], fmt="vn %.4f %.4f %.4f")
        corners = np.stack([faces + 1, uv_line[faces] + 1, count - faces], axis=2).reshape(len(faces), 9)
        np.savetxt(file, corners, fmt="f %d/%d/%d %d/%d/%d %d/%d/%d")


def torus_gltf(triangles: int) -> tuple[dict, list[np.ndarray]]:
    """The torus as a glTF document as exporters write one (float32 POSITION and NORMAL,
    uint32 indices, one node without a transform) and the arrays of its one buffer, in order."""
    positions, faces = torus(triangles)
    ring = positions.astype(np.float64)
    ring[:, :2] /= np.linalg.norm(ring[:, :2], axis=1, keepdims=True)  # the point of the ring the tube is around
    ring[:, 2] = 0.0
    normals = positions - ring
    normals = (normals / np.linalg.norm(normals, axis=1, keepdims=True)).astype(np.float32)
    indices = faces.astype(np.uint32).reshape(-1)
    views, offset = [], 0
    for array, target in ((positions, 34962), (normals, 34962), (indices, 34963)):
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": array.nbytes, "target": target})
        offset += array.nbytes
    document = {
        "asset": {"version": "2.0", "generator": "load_peak.py"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "buffers": [{"byteLength": offset}], "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
             "min": positions.min(axis=0).tolist(), "max": positions.max(axis=0).tolist()},
            {"bufferView": 1, "componentType": 5126, "count": len(normals), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(indices), "type": "SCALAR"},
        ],
    }
    return document, [positions, normals, indices]


def write_torus_glb(path: Path, triangles: int) -> None:
    """The torus as a binary glTF (GLB), as Blender exports one (torus_gltf)."""
    import json

    document, arrays = torus_gltf(triangles)
    offset = document["buffers"][0]["byteLength"]
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    binary_length = offset + (-offset % 4)
    with open(path, "wb") as file:
        file.write(np.array([0x46546C67, 2, 12 + 8 + len(text) + 8 + binary_length], "<u4").tobytes())
        file.write(np.array([len(text), 0x4E4F534A], "<u4").tobytes() + text)
        file.write(np.array([binary_length, 0x004E4942], "<u4").tobytes())
        for array in arrays:
            array.tofile(file)
        file.write(b"\0" * (binary_length - offset))


def write_torus_gltf_embedded(path: Path, triangles: int) -> None:
    """The torus as a .gltf whose buffer is a base64 data: URI (torus_gltf), as the Khronos
    sample models' `glTF-Embedded` variants and Blender's "glTF Embedded" export hold theirs."""
    import base64
    import json

    document, arrays = torus_gltf(triangles)
    head, tail = json.dumps(document | {"buffers": [{"byteLength": document["buffers"][0]["byteLength"], "uri": "@"}]}).split('"@"')
    with open(path, "w") as file:
        file.write(head + '"data:application/octet-stream;base64,')
        file.write(base64.b64encode(b"".join(array.tobytes() for array in arrays)).decode())
        file.write('"' + tail)


WRITERS = {".stl": write_torus_stl, ".ply": write_point_ply, ".obj": write_torus_obj, ".glb": write_torus_glb, ".gltf": write_torus_gltf_embedded, ".off": write_torus_text_mixed,
           ".xyz": write_points_xyz}


def status(key: str) -> int:
    with open("/proc/self/status") as file:
        for line in file:
            if line.startswith(key):
                return int(line.split()[1]) * 1024
    raise KeyError(key)


def main() -> None:
    count, path = int(sys.argv[1]), Path(sys.argv[2])
    render_size = int(sys.argv[sys.argv.index("--render") + 1]) if "--render" in sys.argv else None
    crease = {"crease_angle": float(sys.argv[sys.argv.index("--crease-angle") + 1])} if "--crease-angle" in sys.argv else {}
    if not path.exists():
        writer = WRITERS[path.suffix.lower()]
        if "--triangles" in sys.argv:
            writer = write_torus_ply
        elif "--face-uvs" in sys.argv:
            writer = write_torus_ply_face_uvs
        elif "--exported" in sys.argv:
            writer = write_torus_obj_exported
        elif "--uv-seams" in sys.argv:
            writer = write_torus_obj_uv_seams
        elif "--cubes" in sys.argv:
            writer = write_cubes_stl
        elif "--colours" in sys.argv:
            writer = (lambda path, count: write_torus_text_mixed(path, count, coloured=True)) if "--mixed" in sys.argv else write_torus_coff
        elif "--ascii" in sys.argv and path.suffix.lower() == ".stl":
            writer = write_torus_stl_ascii
        elif "--mixed" in sys.argv:
            writer = write_torus_text_mixed if "--ascii" in sys.argv or path.suffix.lower() == ".off" else write_torus_ply_mixed
        writer(path, count)
    import trimesh  # noqa: F401  - imported by load_mesh; counted in the baseline

    from wgpu_shading import load_mesh

    if render_size is not None:  # the device, a pipeline and a small render belong to the baseline
        from wgpu_shading import Renderer
        from wgpu_shading.assets.mesh_scene import mesh_scene

        renderer = Renderer()
        renderer.render(mesh_scene("builtin:torus", (render_size, render_size), None))
    with open("/proc/self/clear_refs", "w") as file:
        file.write("5")  # reset the peak mark (VmHWM) to the current resident size
    baseline = status("VmRSS")
    start, cpu = time.perf_counter(), time.process_time()
    mesh = load_mesh(path, **crease)
    seconds, cpu_seconds = time.perf_counter() - start, time.process_time() - cpu
    arrays = sum(array.nbytes for array in (mesh.positions, mesh.normals, mesh.indices, mesh.colors) if array is not None)
    load_peak = status("VmHWM")
    result = {
        "file_bytes": path.stat().st_size, "triangles": mesh.triangle_count, "points": mesh.point_count, "vertices": mesh.vertex_count,
        "mesh_array_bytes": arrays, "baseline_rss": baseline, "load_peak_rss": load_peak, "peak_rss": load_peak,
        "load_seconds": round(seconds, 1), "load_cpu_seconds": round(cpu_seconds, 1),
    }
    if render_size is not None:
        from wgpu_shading.scene.view.bare_mesh import bare_mesh_scene

        scene = bare_mesh_scene(mesh, (render_size, render_size))  # what `render MESH` draws, for the loaded mesh
        start, cpu = time.perf_counter(), time.process_time()
        image = renderer.render(scene)
        result["render_seconds"], result["render_cpu_seconds"] = round(time.perf_counter() - start, 1), round(time.process_time() - cpu, 1)
        assert (image[:, :, :3] > 0).any()
        result["peak_rss"] = status("VmHWM")
    result["load_peak_above_baseline_over_arrays"] = round((load_peak - baseline) / arrays, 2)
    result["peak_above_baseline_over_arrays"] = round((result["peak_rss"] - baseline) / arrays, 2)
    print(json.dumps(result))


if __name__ == "__main__":
    import os

    from wgpu_shading.assets.disk_cache import CACHE_VARIABLE

    os.environ[CACHE_VARIABLE] = "off"  # the file parsed, not read back from the mesh cache
    main()
