"""Dataset rendering (docs/datasets.md): many meshes × many views → image files, resumable, on one
machine or a Dask cluster, with the pixels of `wgpu-shading render` (docs/datasets.md).

    from wgpu_shading.dataset import Outputs, mesh_jobs, render_dataset, turntable_views
    jobs = mesh_jobs(["meshes/*.obj"], turntable_views(24), Outputs(depth="npy"), {"size": 256})
    result = render_dataset(jobs, "out", workers=1)

A stage above render/ (imports render, assets, scene); the cli's `batch` command sits on top.
Dask (the `dask` extra) is imported only for workers > 1 or a scheduler address.
"""

from .jobs import Job, Outputs, chunks
from .manifest import mesh_jobs, read_manifest
from .run import BatchResult, render_dataset
from .views import sphere_views, turntable_views

__all__ = [
    "BatchResult",
    "Job",
    "Outputs",
    "chunks",
    "mesh_jobs",
    "read_manifest",
    "render_dataset",
    "sphere_views",
    "turntable_views",
]
