"""Peak resident memory of loading a large binary STL with `load_mesh`, in a fresh process (Linux).

    python benchmarks/scripts/stl_load_peak.py 10000000 /tmp/torus10m.stl

Writes a smooth torus of about that many triangles as a binary STL (every corner repeated,
as STL stores it; skipped when the file exists), then loads it and prints one JSON object:
the mesh's arrays (positions + normals + indices, what a Renderer uploads), the process's
resident memory after imports, its peak (VmHWM), and the peak above the imports as a
multiple of the mesh's arrays. docs/reliability.md quotes the result.
"""

import json
import math
import sys
import time
from pathlib import Path

import numpy as np


def write_torus_stl(path: Path, triangles: int) -> None:
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
    records = np.zeros(len(faces), np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")]))
    records["corners"] = positions[faces]
    with open(path, "wb") as file:
        file.write(b"torus".ljust(80, b" ") + np.uint32(len(faces)).tobytes())
        records.tofile(file)


def status(key: str) -> int:
    with open("/proc/self/status") as file:
        for line in file:
            if line.startswith(key):
                return int(line.split()[1]) * 1024
    raise KeyError(key)


def main() -> None:
    triangles, path = int(sys.argv[1]), Path(sys.argv[2])
    if not path.exists():
        write_torus_stl(path, triangles)
    import trimesh  # noqa: F401  - imported by load_mesh; counted in the baseline

    from wgpu_shading import load_mesh

    with open("/proc/self/clear_refs", "w") as file:
        file.write("5")  # reset the peak mark (VmHWM) to the current resident size
    baseline = status("VmRSS")
    start = time.perf_counter()
    mesh = load_mesh(path)
    seconds = time.perf_counter() - start
    arrays = sum(array.nbytes for array in (mesh.positions, mesh.normals, mesh.indices))
    peak = status("VmHWM")
    print(json.dumps({
        "file_bytes": path.stat().st_size, "triangles": mesh.triangle_count, "vertices": mesh.vertex_count,
        "mesh_array_bytes": arrays, "baseline_rss": baseline, "peak_rss": peak,
        "peak_above_baseline_over_arrays": round((peak - baseline) / arrays, 2), "seconds": round(seconds, 1),
    }))


if __name__ == "__main__":
    main()
