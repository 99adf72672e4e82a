"""Memory: peak RSS of rendering the 1.3M-triangle sphere, against 3× its arrays + baseline;
and of loading a 10M-triangle mesh file and rendering it, as a binary STL, a binary PLY, an
OBJ (plain, and as Blender writes one), a binary glTF, a binary STL whose every vertex is on
a crease, and binary and ASCII PLY and OFF files of faces of two sizes (FILE_FORMATS).

Measured in fresh processes (scripts/memory_peak.py, scripts/load_peak.py). Besides the
default run, one with LP_NUM_THREADS=0 (llvmpipe rasterizing on the driver's thread,
nothing queued) isolates how much of the peak is llvmpipe's binned-triangle queue rather
than our buffers. Each file (the same torus, written once into a temporary folder) goes
through everything a user's file does: its reader (the STL's joining its corners), the
crease normals, the Mesh, the upload in vertex-cache order, the frame.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wgpu_shading.scene import sphere_for_triangles

from .measure import progress

SCRIPT = Path(__file__).resolve().parent / "scripts" / "memory_peak.py"
FILE_SCRIPT = Path(__file__).resolve().parent / "scripts" / "load_peak.py"


# The big files measured: file name suffix → what it is and load_peak.py's options to write it
FILE_FORMATS = {
    "stl": ("binary STL", []), "ply": ("binary PLY", ["--triangles"]), "obj": ("OBJ", []),
    "exported.obj": ("OBJ, `vt` and `vn` numbered on their own (as Blender writes it)", ["--exported"]),
    "seams.obj": ("OBJ of `v`, `vt` and `f v/vt` with UV seams and no normals (as Agisoft Metashape writes it)", ["--uv-seams"]),
    "glb": ("glTF (GLB)", []),
    "gltf": ("glTF, its buffer embedded as base64 (a `glTF-Embedded` file)", []),
    "cubes.stl": ("binary STL of separate cubes, every vertex on a crease (a voxel model)", ["--cubes"]),
    "uvs.ply": ("binary PLY with a `texcoord` list on every face (as MeshLab and Agisoft Metashape export a textured mesh)", ["--face-uvs"]),
    "mixed.ply": ("binary PLY of quads and triangles, with texture coordinates (as Blender writes it)", ["--mixed"]),
    "mixed-ascii.ply": ("ASCII PLY of quads and triangles", ["--mixed", "--ascii"]),
    "mixed.off": ("OFF of quads and triangles", ["--mixed"]),
    "coloured.off": ("COFF: an OFF with a colour on every vertex line (as MeshLab writes it)", ["--colours"]),
}


@dataclass
class FileMemoryRow:
    """One fresh process loading a mesh file, then rendering it (scripts/load_peak.py)."""

    file_format: str  # a key of FILE_FORMATS
    triangles: int
    vertices: int
    file_bytes: int
    mesh_bytes: int
    baseline: int
    load_peak: int
    peak: int
    load_seconds: float
    load_cpu_seconds: float
    render_seconds: float
    render_cpu_seconds: float

    def in_meshes(self, peak: int) -> float:
        return (peak - self.baseline) / self.mesh_bytes


def run_file_memory(triangles: int, size: int, file_format: str = "stl") -> FileMemoryRow:
    what, options = FILE_FORMATS[file_format]
    progress(f"memory: a {triangles:,}-triangle {what} loaded and rendered at {size}² in a fresh process")
    with tempfile.TemporaryDirectory() as folder:
        result = subprocess.run(
            [sys.executable, str(FILE_SCRIPT), str(triangles), str(Path(folder) / f"torus.{file_format}"), *options, "--render", str(size)],
            capture_output=True, text=True, timeout=1200, check=True,
        )
    sample = json.loads(result.stdout.strip().splitlines()[-1])
    return FileMemoryRow(
        file_format=file_format, triangles=sample["triangles"], vertices=sample["vertices"], file_bytes=sample["file_bytes"],
        mesh_bytes=sample["mesh_array_bytes"], baseline=sample["baseline_rss"], load_peak=sample["load_peak_rss"],
        peak=sample["peak_rss"], load_seconds=sample["load_seconds"], load_cpu_seconds=sample["load_cpu_seconds"],
        render_seconds=sample["render_seconds"], render_cpu_seconds=sample["render_cpu_seconds"],
    )


@dataclass
class MemoryRow:
    label: str
    triangles: int
    mesh_bytes: int
    baseline: int
    with_mesh: int
    peak: int  # median over runs
    peaks: tuple[int, ...] = ()  # every run's peak (llvmpipe's queue makes them bimodal)
    uploaded: int = 0  # our GPU buffers for the mesh

    @property
    def ours_in_meshes(self) -> float:
        """What our code holds: the mesh's arrays plus their GPU copy, in mesh arrays."""
        return (self.mesh_bytes + self.uploaded) / self.mesh_bytes

    @property
    def peak_over_baseline_in_meshes(self) -> float:
        return (self.peak - self.baseline) / self.mesh_bytes


def run_memory(triangles: int, size: int, runs: int) -> list[MemoryRow]:
    progress(f"memory: {triangles:,}-triangle sphere at {size}², {runs} fresh processes per variant")
    mesh = sphere_for_triangles(triangles)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "sphere.npz"
        np.savez(path, positions=mesh.positions, normals=mesh.normals, indices=mesh.indices, uvs=mesh.uvs)
        for label, extra_env in (("default", {}), ("LP_NUM_THREADS=0 (no binning queue)", {"LP_NUM_THREADS": "0"})):
            samples = []
            for _ in range(runs):
                result = subprocess.run(
                    [sys.executable, str(SCRIPT), str(path), str(size)],
                    env={**os.environ, **extra_env}, capture_output=True, text=True, timeout=600, check=True,
                )
                samples.append(json.loads(result.stdout.strip().splitlines()[-1]))
            rows.append(
                MemoryRow(
                    label=label,
                    triangles=samples[0]["triangles"],
                    mesh_bytes=samples[0]["mesh_bytes"],
                    baseline=int(statistics.median(s["baseline"] for s in samples)),
                    with_mesh=int(statistics.median(s["with_mesh"] for s in samples)),
                    peak=int(statistics.median(s["peak"] for s in samples)),
                    peaks=tuple(s["peak"] for s in samples),
                    uploaded=samples[0]["uploaded"],
                )
            )
    return rows
