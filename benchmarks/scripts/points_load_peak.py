"""Peak resident memory of loading a large point cloud with `load_mesh`, in a fresh process (Linux).

    python benchmarks/scripts/points_load_peak.py 10000000 /tmp/points10m.ply

Writes a binary little-endian PLY of that many points on a sphere (float x y z, float nx ny
nz, uchar red green blue: 27 bytes a point, as scanners write them; skipped when the file
exists), then loads it and prints one JSON object: the mesh's arrays (positions, normals,
colours: what a Renderer uploads), the process's resident memory after imports, its peak
(VmHWM), and the peak above the imports as a multiple of the mesh's arrays.
docs/primitives.md quotes the result.
"""

import json
import sys
import time
from pathlib import Path

import numpy as np
from stl_load_peak import status  # (this folder: the same peak measurement)


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
        "ply\nformat binary_little_endian 1.0\ncomment points_load_peak.py\n"
        f"element vertex {count}\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
    )
    with open(path, "wb") as file:
        file.write(header.encode("ascii"))
        records.tofile(file)


def main() -> None:
    count, path = int(sys.argv[1]), Path(sys.argv[2])
    if not path.exists():
        write_point_ply(path, count)
    import trimesh  # noqa: F401  - imported by load_mesh; counted in the baseline

    from wgpu_shading import load_mesh

    with open("/proc/self/clear_refs", "w") as file:
        file.write("5")  # reset the peak mark (VmHWM) to the current resident size
    baseline = status("VmRSS")
    start = time.perf_counter()
    mesh = load_mesh(path)
    seconds = time.perf_counter() - start
    arrays = sum(a.nbytes for a in (mesh.positions, mesh.normals, mesh.colors) if a is not None)
    peak = status("VmHWM")
    print(json.dumps({
        "file_bytes": path.stat().st_size, "points": mesh.point_count, "vertices": mesh.vertex_count,
        "mesh_array_bytes": arrays, "baseline_rss": baseline, "peak_rss": peak,
        "peak_above_baseline_over_arrays": round((peak - baseline) / arrays, 2), "seconds": round(seconds, 1),
        "cpu_seconds": round(time.process_time(), 1),
    }))


if __name__ == "__main__":
    main()
